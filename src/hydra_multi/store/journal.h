#pragma once
// The durable journal of the updates the station accepted (SQLite, WAL mode; DESIGN.md "The
// station as a service"): one row and one transaction per update (robot, epoch, sequence, the
// update as its .dsgb record, arrival time, whether it is a snapshot, the bytes of its message),
// written before the update is acknowledged, so that a station that restarts on the same folder
// replays it and loses nothing it acknowledged. A robot's sequence is in the journal at most once
// as a delta and once as a snapshot (a snapshot the station asked for may carry the sequence of a
// delta it holds beyond a gap). A second table holds each robot's last BYE, so that a station that
// restarts after the robots finished knows they did. SQLite stays inside this unit.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "hydra_multi/core/result.h"
#include "hydra_multi/core/robot_id.h"

namespace hydra_multi::store {

/// SQLite's `synchronous` in WAL mode: kFull syncs every commit (durable through a power loss),
/// kNormal syncs at checkpoints (durable through a crash of the process, not of the machine).
enum class Durability { kFull, kNormal };

struct JournalEntry {
  RobotId robot;
  uint64_t epoch = 0;
  uint64_t sequence = 0;
  std::string payload;  ///< the update, one .dsgb robot-update record
  int64_t arrival_ns = 0;
  bool snapshot = false;  ///< the update is a snapshot
  size_t wire_bytes = 0;  ///< of the message it came in (compressed, with the protocol's framing)
};

class Journal {
 public:
  /// Opens (or creates) the journal at `path`; an error names the file (not a database, another
  /// table layout, a folder that cannot be written).
  static Result<std::unique_ptr<Journal>> open(const std::string& path,
                                               Durability durability = Durability::kFull);
  ~Journal();
  Journal(const Journal&) = delete;
  Journal& operator=(const Journal&) = delete;

  /// Appends an update in its own transaction; OK means it is committed. An entry of a robot,
  /// sequence and kind (snapshot or not) that is there already is refused (an error), and
  /// nothing changes.
  Status append(const JournalEntry& entry);
  /// Every entry, in the order it was appended; stops at the first error (a damaged file).
  Status replay(const std::function<void(JournalEntry&&)>& each) const;
  /// Records that robot `robot`'s process `epoch` said BYE (it sends nothing more), committed
  /// before the station answers it; a later BYE of the robot replaces it.
  Status markDone(RobotId robot, uint64_t epoch);
  /// The robots done: those whose last BYE came after their last update in the journal, with
  /// the epoch of the process that said it.
  Result<std::map<RobotId, uint64_t>> done() const;
  /// Updates in the journal.
  size_t size() const;
  /// SQLite's `PRAGMA integrity_check`: "ok", or what it found.
  std::string integrityCheck() const;
  const std::string& path() const;

 private:
  struct Impl;
  explicit Journal(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace hydra_multi::store
