#include "hydra_multi/dsg/update_sequencer.h"

namespace hydra_multi {

const char* updateOutcomeName(UpdateOutcome outcome) {
  switch (outcome) {
    case UpdateOutcome::kApplied:
      return "applied";
    case UpdateOutcome::kBuffered:
      return "buffered";
    case UpdateOutcome::kDuplicate:
      return "duplicate";
    case UpdateOutcome::kWaiting:
      return "waiting for snapshot";
    case UpdateOutcome::kRejected:
      return "rejected";
  }
  return "rejected";
}

UpdateCounts& UpdateCounts::operator+=(const UpdateCounts& other) {
  offered += other.offered;
  applied += other.applied;
  applied_from_buffer += other.applied_from_buffer;
  buffered += other.buffered;
  duplicates += other.duplicates;
  waiting += other.waiting;
  rejected += other.rejected;
  superseded += other.superseded;
  return *this;
}

std::string describeUpdates(const UpdateCounts& counts, size_t damaged_records) {
  return std::to_string(counts.appliedTotal()) + " applied of " + std::to_string(counts.offered) +
         ", " + std::to_string(damaged_records) +
         (damaged_records == 1 ? " damaged record" : " damaged records") + " skipped, " +
         std::to_string(counts.rejected) + " rejected, " + std::to_string(counts.behindGap()) +
         " behind a missing update" +
         (counts.superseded > 0
              ? ", " + std::to_string(counts.superseded) + " superseded by a snapshot"
              : std::string()) +
         (counts.duplicates > 0 ? ", " + std::to_string(counts.duplicates) + " duplicates"
                                : std::string());
}

std::string describeStream(RobotId robot, const UpdateSequencer* order, size_t damaged_records) {
  const UpdateCounts counts = order ? order->counts() : UpdateCounts{};
  std::string line =
      "robot " + robot.str() + ": updates " + describeUpdates(counts, damaged_records);
  if (order && (order->waitingForSnapshot() || order->heldBack() > 0)) {
    line += "; its map stops before update " + std::to_string(order->nextSequence()) + ", " +
            (order->waitingForSnapshot()
                 ? std::string("waiting for a snapshot")
                 : std::to_string(order->heldBack()) + " later updates held behind it");
  }
  return line;
}

bool streamIsWhole(const UpdateSequencer* order, size_t damaged_records) {
  if (order == nullptr || damaged_records > 0) return false;
  const UpdateCounts& c = order->counts();
  return c.appliedTotal() > 0 && c.rejected == 0 && c.behindGap() == 0;
}

void UpdateSequencer::refuse() {
  ++counts_.offered;
  ++counts_.rejected;
}

void UpdateSequencer::startWaiting() {
  waiting_ = true;
  buffer_.clear();
}

Status UpdateSequencer::applyOne(const RobotUpdate& update, size_t digest, const Apply& apply) {
  if (Status status = apply(update); !status) return status;
  next_sequence_ = update.sequence + 1;
  waiting_ = false;
  digests_[update.sequence] = digest;
  while (digests_.size() > options_.remembered_digests) digests_.erase(digests_.begin());
  return Status::Ok();
}

SequencedUpdate UpdateSequencer::offer(const RobotUpdate& update, const Apply& apply) {
  ++counts_.offered;
  SequencedUpdate result;
  const size_t digest = digest_ ? digest_(update) : 0;
  if (update.sequence < next_sequence_) {
    const auto seen = digests_.find(update.sequence);
    if (digest_ && seen != digests_.end() && seen->second != digest) {
      ++counts_.rejected;
      result.message =
          "differs from the update applied with this sequence number (corrupt or conflicting "
          "replay)";
    } else {
      ++counts_.duplicates;
      result.outcome = UpdateOutcome::kDuplicate;
      result.message = "sequence " + std::to_string(update.sequence) + " was already applied";
    }
    return result;
  }
  if (waiting_ && !update.is_snapshot) {
    ++counts_.waiting;
    result.outcome = UpdateOutcome::kWaiting;
    result.message = "the robot has a gap before it; only a snapshot can follow";
    return result;
  }
  if (!update.is_snapshot && update.sequence > next_sequence_) {
    if (buffer_.size() >= options_.reorder_buffer) {
      startWaiting();
      ++counts_.waiting;
      result.outcome = UpdateOutcome::kWaiting;
      result.message = "sequence " + std::to_string(next_sequence_) + " is still missing after " +
                       std::to_string(options_.reorder_buffer) +
                       " later updates; waiting for a snapshot";
      return result;
    }
    buffer_[update.sequence] = {update, digest};
    ++counts_.buffered;
    result.outcome = UpdateOutcome::kBuffered;
    result.message = "ahead of the missing sequence " + std::to_string(next_sequence_);
    return result;
  }
  // In order (or a snapshot): apply, then whatever the buffer holds next.
  if (Status status = applyOne(update, digest, apply); !status) {
    ++counts_.rejected;
    startWaiting();
    result.message = status.message() + "; the robot now waits for a snapshot";
    return result;
  }
  ++counts_.applied;
  result.outcome = UpdateOutcome::kApplied;
  result.applied.push_back(update.sequence);
  while (!buffer_.empty() && buffer_.begin()->first <= next_sequence_) {
    const auto [next, next_digest] = std::move(buffer_.begin()->second);
    buffer_.erase(buffer_.begin());
    if (next.sequence < next_sequence_) {  // overtaken by a snapshot
      ++counts_.superseded;
      continue;
    }
    if (Status status = applyOne(next, next_digest, apply); !status) {
      ++counts_.rejected;
      startWaiting();
      result.released_rejections.push_back("sequence " + std::to_string(next.sequence) + ": " +
                                           status.message());
      break;
    }
    ++counts_.applied_from_buffer;
    result.applied.push_back(next.sequence);
  }
  return result;
}

}  // namespace hydra_multi
