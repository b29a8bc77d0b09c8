#pragma once
// The station's network input (docs/PROTOCOL.md): a ZeroMQ ROUTER socket that robots' DEALERs
// connect to. A connection says HELLO (robot, epoch) and is welcomed with the sequence the
// station expects next from that robot; each UPDATE it sends is checked (size, version, framing,
// the payload decodes, the payload's robot and sequence are the connection's), handed to the
// Station, and answered with a cumulative ACK; an update held already is acknowledged and not
// handed on twice. Whatever is refused is answered with REFUSE and its reason, logged and counted;
// it never stops the station. Heartbeats go both ways; a robot silent for `missed_heartbeats`
// beats is taken as gone (its updates stay; it may come back). With CURVE keys, a ZAP handler
// admits only the robots' keys it knows, and a connection may speak only for the robot of its
// key. The station asks a robot for a snapshot of its map (SNAPSHOT_REQUEST) when the robot's
// process restarted (a HELLO of a new epoch, while the station holds updates of it), when the
// first update after a HELLO skips what the station lacks, and when a gap stays unfilled for
// `gap_s`. ZeroMQ stays inside this unit.
//
// Epochs: an UPDATE of another epoch than its connection's HELLO, and a HELLO of an epoch older
// than the robot's current run while that run is connected or has said BYE (an old process, or a
// recorded connection played again), are refused (`stale_epoch`).
//
// Durability: with `persist` (the station's journal, store/journal.h) an update is acknowledged
// only once persist() has stored it; without, once it is on the Station's ingest queue.

#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>

#include "hydra_multi/core/result.h"
#include "hydra_multi/station/station.h"

namespace hydra_multi::net {

struct StationServerOptions {
  std::string listen = "tcp://127.0.0.1:*";  ///< ZeroMQ endpoint; a '*' port picks a free one
  size_t max_message_bytes = 64u << 20;      ///< larger messages are refused
  double heartbeat_s = 1.0;
  int missed_heartbeats = 3;  ///< silent for this many beats: gone
  /// A gap (an update missing, later ones held) this long without progress: ask the robot for a
  /// snapshot (twice the robot's resend time: resends had their chance).
  double gap_s = 10.0;
  /// Every this many seconds, one progress line per robot: connected, silent for N s or done,
  /// updates applied, bytes received (0: none).
  double status_s = 10.0;
  /// A connection's messages beyond this rate (per second, with a burst of two seconds' worth)
  /// are dropped unread and unanswered, counted as `rate_limited` and logged once a second; the
  /// robot's resends bring its updates once it slows down. 0: no limit.
  double max_messages_per_s = 500.0;
  /// The same for bytes per second (the burst at least one message of the largest size). 0: none.
  double max_bytes_per_s = 0.0;
  /// A TCP connection that has not completed ZeroMQ's handshake within this time is closed.
  double handshake_s = 10.0;
  /// Updates of a robot held beyond a missing one: more are refused (`too_far_ahead`) until a
  /// snapshot closes the gap (a robot's outbox holds 4096).
  size_t max_ahead = 4096;
  std::function<void(const std::string&)> log;
  /// Stores an accepted update (its robot, epoch, sequence, its record, expanded if it came
  /// compressed, and the bytes of its message) before it is handed on and acknowledged; an error
  /// refuses it (`not_stored`) and it is not acknowledged.
  std::function<Status(const RobotUpdate& update, uint64_t epoch, const std::string& record,
                       size_t wire_bytes)>
      persist;
  /// Stores that a robot said BYE (its process's epoch) before the BYE is answered; an error is
  /// logged and the BYE left unanswered (the robot says it again).
  std::function<Status(RobotId robot, uint64_t epoch)> persist_bye;
  /// WELCOME offers zstd: robots may send payloads compressed (payload.h).
  bool accept_zstd = true;
  /// CURVE (keys.h): the station's secret key and the robots' public keys it admits, each one
  /// robot's; a connection speaks only for the robot of its key. Empty: no authentication.
  std::string secret_key;
  std::map<std::string, RobotId> robot_keys;
  /// Robots whose updates come from another input (Hydra robots): a HELLO for one is refused.
  std::set<RobotId> other_inputs;
};

/// What became of one robot's messages (over all its connections).
struct RobotLinkCounts {
  size_t updates = 0;      ///< updates handed to the station
  size_t duplicates = 0;   ///< updates held already (resent after a reconnect), acknowledged
  size_t connections = 0;  ///< HELLOs accepted
  size_t snapshots = 0;    ///< of the updates, snapshots
  size_t snapshots_requested = 0;
  size_t bytes = 0;  ///< of every message from it
  bool said_bye = false;
  uint64_t next_sequence = 0;  ///< every update before it is held
};

struct StationServerCounts {
  std::map<RobotId, RobotLinkCounts> robots;
  std::map<std::string, size_t> refused;  ///< by reason: malformed, too_large, ... (PROTOCOL.md)
  size_t bytes = 0;                       ///< of every message received
  size_t snapshots_requested = 0;
};

/// A robot's link as the station sees it now (for the viewer's status strip).
struct RobotLinkState {
  bool connected = false;  ///< a welcomed connection heard within the missed heartbeats
  bool said_bye = false;
  double silent_s = 0.0;  ///< since its last message
  size_t bytes = 0;       ///< of every message from it
};

class StationServer {
 public:
  /// Binds the socket; an error names the endpoint.
  static Result<std::unique_ptr<StationServer>> create(Station& station,
                                                       StationServerOptions options);
  ~StationServer();

  /// The endpoint bound, with the port a '*' picked ("tcp://127.0.0.1:40123").
  const std::string& endpoint() const;
  /// Serves until `stop()` is true (asked every 100 ms) or `expect_robots` robots (0: no limit)
  /// have said BYE (and one heartbeat more, to answer a BYE sent again).
  void serve(const std::function<bool()>& stop, size_t expect_robots = 0);
  const StationServerCounts& counts() const;
  /// Each robot's link, as of the serving thread's last pass (at most 100 ms old; any thread).
  std::map<RobotId, RobotLinkState> links() const;
  /// Marks an update as held already (replayed from the journal before serving), so that its
  /// robot is welcomed past it and a resend of it is not handed on again; `epoch`: the robot
  /// process's that sent it (a HELLO of another epoch is a restarted robot).
  void hold(RobotId robot, uint64_t epoch, uint64_t sequence, bool snapshot);
  /// Marks a robot as done (its BYE, replayed from the journal before serving): it counts towards
  /// serve()'s expected BYEs until a process of another epoch says HELLO for it.
  void holdDone(RobotId robot, uint64_t epoch);

 private:
  struct Impl;
  explicit StationServer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace hydra_multi::net
