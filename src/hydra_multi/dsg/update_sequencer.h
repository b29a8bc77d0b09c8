#pragma once
// The order rule for one robot's updates, by sequence number. The station's frontend
// (frontend/scene_graph_processor.h) and every replay of a recorded stream (robot_stream.h:
// dataset-graph, info, the evaluation) apply it, so all of them apply the same updates of a
// damaged or reordered stream and count them alike:
//   - the expected sequence is applied; so is a snapshot at or after it (it replaces all the
//     robot had, and is the way back after a gap);
//   - a later delta waits in a reorder buffer until the missing ones arrive; with the buffer
//     full, the buffer is dropped and the robot waits for a snapshot (a gap);
//   - an earlier sequence is a duplicate when its digest matches the one applied with that
//     sequence (or none is remembered), and rejected as conflicting otherwise;
//   - an update that fails to apply is rejected, and the robot waits for a snapshot.
// Every arrival gets one outcome; `UpdateCounts` adds them up.

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/dsg/robot_update.h"

namespace hydra_multi {

enum class UpdateOutcome {
  kApplied,    ///< applied (with any buffered successors it released)
  kBuffered,   ///< ahead of a missing sequence: kept until the gap fills
  kDuplicate,  ///< already applied, same content: ignored
  kWaiting,    ///< the robot has a gap: waiting for a snapshot, update dropped
  kRejected,   ///< malformed or conflicting: dropped
};
const char* updateOutcomeName(UpdateOutcome outcome);

/// What became of a robot's updates (or a team's, added up).
struct UpdateCounts {
  size_t offered = 0;              ///< arrivals
  size_t applied = 0;              ///< applied on arrival
  size_t applied_from_buffer = 0;  ///< applied later, once the one they waited for came
  size_t buffered = 0;             ///< arrivals kept in the reorder buffer
  size_t duplicates = 0;
  size_t waiting = 0;     ///< arrivals dropped while the robot waited for a snapshot
  size_t rejected = 0;    ///< malformed, conflicting, or failing to apply (also from the buffer)
  size_t superseded = 0;  ///< buffered, then made unnecessary by a snapshot that overtook them

  size_t appliedTotal() const { return applied + applied_from_buffer; }
  /// Arrivals never applied because one before them is missing: still held at the end, dropped
  /// with a full buffer, or dropped while the robot waited for a snapshot.
  size_t behindGap() const { return offered - appliedTotal() - rejected - duplicates - superseded; }
  UpdateCounts& operator+=(const UpdateCounts& other);
};

/// "A applied of N, S damaged records skipped, R rejected, G behind a missing update" (then the
/// superseded and duplicate ones, if any): the one line every command prints about a stream's
/// (or a team's) updates.
std::string describeUpdates(const UpdateCounts& counts, size_t damaged_records);

class UpdateSequencer;
/// "robot b: updates 5 applied of 17, 1 damaged record skipped, 0 rejected, 12 behind a missing
/// update; its map stops before update 5, waiting for a snapshot": what became of one robot's
/// stream (`order` null: nothing of it arrived).
std::string describeStream(RobotId robot, const UpdateSequencer* order, size_t damaged_records);
/// Whether a robot's stream arrived whole: something applied, nothing damaged, rejected or behind
/// a gap.
bool streamIsWhole(const UpdateSequencer* order, size_t damaged_records);

struct SequencerOptions {
  size_t reorder_buffer = 16;      ///< updates a robot may send ahead of a missing one
  size_t remembered_digests = 64;  ///< applied updates remembered to recognise duplicates
};

/// What one arrival did.
struct SequencedUpdate {
  UpdateOutcome outcome = UpdateOutcome::kRejected;
  std::string message;            ///< why, for everything but kApplied
  std::vector<uint64_t> applied;  ///< sequence numbers applied by this call, in order
  /// Buffered updates released by this call that then failed to apply (each "sequence N: why");
  /// the robot waits for a snapshot after the first.
  std::vector<std::string> released_rejections;
};

class UpdateSequencer {
 public:
  /// Applies one update to the caller's state; on an error it must change nothing.
  using Apply = std::function<Status(const RobotUpdate&)>;
  /// A digest of an update's content, to tell a duplicate from a conflicting replay (none: every
  /// earlier sequence is a duplicate).
  using Digest = std::function<size_t(const RobotUpdate&)>;

  explicit UpdateSequencer(SequencerOptions options = {}, Digest digest = {})
      : options_(options), digest_(std::move(digest)) {}

  /// One arriving update of this robot: applied through `apply` when it is due, with every
  /// buffered one it releases, or buffered, or dropped.
  SequencedUpdate offer(const RobotUpdate& update, const Apply& apply);
  /// An arrival refused before it reached the order rule (malformed): counted as rejected, and
  /// nothing else changes.
  void refuse();

  uint64_t nextSequence() const { return next_sequence_; }
  bool waitingForSnapshot() const { return waiting_; }
  /// Updates held in the reorder buffer, ahead of the missing nextSequence().
  size_t heldBack() const { return buffer_.size(); }
  const UpdateCounts& counts() const { return counts_; }

 private:
  /// Applies `update`; on success moves the expected sequence past it and remembers its digest.
  Status applyOne(const RobotUpdate& update, size_t digest, const Apply& apply);
  void startWaiting();

  SequencerOptions options_;
  Digest digest_;
  uint64_t next_sequence_ = 0;
  bool waiting_ = false;
  std::map<uint64_t, std::pair<RobotUpdate, size_t>> buffer_;  // sequence -> update, digest
  std::map<uint64_t, size_t> digests_;                         // sequence -> applied digest
  UpdateCounts counts_;
};

}  // namespace hydra_multi
