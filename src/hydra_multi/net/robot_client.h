#pragma once
// A robot's side of the protocol (docs/PROTOCOL.md): a ZeroMQ DEALER socket to the station. It
// says HELLO and waits for WELCOME, which says what the station holds already; it keeps every
// update in an outbox until the station acknowledges it, sends at most `window` unacknowledged
// ones at a time, and sends an unacknowledged one again after `resend_s`. A station silent for
// `missed_heartbeats` beats is taken as gone: the client reconnects after a backoff that doubles
// from `backoff_min_s` to `backoff_max_s`, and sends again whatever the new WELCOME does not
// cover. It keeps the robot's map as one snapshot of every update (dsg/robot_stream.h): when the
// station asks for a snapshot (it lacks updates the outbox no longer has: the robot process
// restarted, or one was lost), that snapshot replaces every outbox entry up to its sequence.
// Single-threaded: the caller drives it with pump(). ZeroMQ stays inside this unit.

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "hydra_multi/dsg/robot_update.h"

namespace hydra_multi::net {

struct RobotClientOptions {
  std::string connect;  ///< the station's endpoint, e.g. tcp://127.0.0.1:40123
  uint64_t epoch = 0;   ///< this robot process's run; 0: taken from the clock
  double heartbeat_s = 1.0;
  int missed_heartbeats = 3;
  double resend_s = 5.0;       ///< an update unacknowledged this long is sent again
  size_t window = 64;          ///< unacknowledged updates in flight at most
  size_t outbox_limit = 4096;  ///< updates kept until acknowledged at most
  double backoff_min_s = 0.5, backoff_max_s = 16.0;
  std::function<void(const std::string&)> log;
  /// CURVE (keys.h): the robot's secret key and the station's public key. Empty: none.
  std::string secret_key, station_key;
  /// Send the robot's whole map (a snapshot) in place of each update, as the paper's robots do.
  bool full_resend = false;
  /// Compress payloads with zstd when the station takes it (its WELCOME says so).
  bool compress = true;
};

struct RobotClientCounts {
  size_t sent = 0;    ///< updates sent for the first time
  size_t resent = 0;  ///< sent again (after a reconnect or `resend_s`)
  size_t acknowledged = 0;
  size_t refused = 0;      ///< updates the station refused (dropped from the outbox, logged)
  size_t snapshots = 0;    ///< sent because the station asked for one
  size_t connections = 0;  ///< WELCOMEs
  size_t bytes = 0;        ///< of every message sent
  /// Updates the station had acknowledged (its cumulative ACK had passed them) and no longer held
  /// when it welcomed this robot again: a station that lost what it promised to keep (logged).
  size_t lost_acknowledged = 0;
  /// finish(): every update acknowledged, but the station's answer to BYE never came (it ended
  /// first, or the connection was cut as it answered).
  bool bye_unanswered = false;
};

class RobotClient {
 public:
  RobotClient(RobotId robot, uint32_t provided_layers, RobotClientOptions options);
  ~RobotClient();
  RobotClient(const RobotClient&) = delete;
  RobotClient& operator=(const RobotClient&) = delete;

  /// Puts an update in the outbox (and in the robot's map); false (nothing added) when the
  /// outbox is full.
  bool enqueue(const RobotUpdate& update);
  /// Adds an update to the robot's map only: one it made while its process was down (a
  /// restarted robot's map goes on where it was; what it has not sent, a snapshot brings).
  void fold(const RobotUpdate& update);
  /// Works the connection for about `budget`: connects, sends, handles the station's messages,
  /// heartbeats, reconnects.
  void pump(std::chrono::milliseconds budget);
  /// Waits (pumping) until every update is acknowledged, then says BYE until it is answered, or
  /// for twice the heartbeat timeout after the first BYE (counts().bye_unanswered); false on
  /// timeout with updates unacknowledged, or a fatal refusal.
  bool finish(std::chrono::milliseconds timeout);

  size_t unacknowledged() const;
  bool welcomed() const;
  /// Why the mission cannot go on (the station refused the HELLO); empty while it can.
  const std::string& fatal() const;
  const RobotClientCounts& counts() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hydra_multi::net
