// The order rule for one robot's updates: in order, reordered, gapped, duplicated, conflicting,
// failing to apply; every arrival gets one outcome and the counts add up to the arrivals.

#include <gtest/gtest.h>

#include "hydra_multi/dsg/robot_stream.h"
#include "hydra_multi/dsg/update_sequencer.h"

namespace hydra_multi {
namespace {

const RobotId kA(0);

RobotUpdate update(uint64_t sequence, bool snapshot = false, uint32_t content = 0) {
  RobotUpdate u;
  u.robot = kA;
  u.sequence = sequence;
  u.is_snapshot = snapshot || sequence == 0;
  u.provided_layers = content;
  return u;
}

// Records what was applied; fails the sequences in `failing`.
struct Recorder {
  std::vector<uint64_t> applied;
  std::set<uint64_t> failing;
  UpdateSequencer::Apply apply() {
    return [this](const RobotUpdate& u) -> Status {
      if (failing.count(u.sequence)) return Error{"does not fit"};
      applied.push_back(u.sequence);
      return Status::Ok();
    };
  }
};

size_t digestOf(const RobotUpdate& u) { return u.provided_layers; }

// Every arrival is counted once, under one outcome or as applied later from the buffer.
void expectCountsAddUp(const UpdateCounts& c) {
  EXPECT_EQ(c.appliedTotal() + c.rejected + c.duplicates + c.superseded + c.behindGap(), c.offered);
}

// Out of order within the buffer: applied in sequence once the missing one comes.
TEST(UpdateSequencer, ReordersWithinTheBuffer) {
  UpdateSequencer order;
  Recorder r;
  EXPECT_EQ(order.offer(update(0), r.apply()).outcome, UpdateOutcome::kApplied);
  EXPECT_EQ(order.offer(update(2), r.apply()).outcome, UpdateOutcome::kBuffered);
  EXPECT_EQ(order.offer(update(3), r.apply()).outcome, UpdateOutcome::kBuffered);
  EXPECT_EQ(order.heldBack(), 2u);
  const SequencedUpdate one = order.offer(update(1), r.apply());
  EXPECT_EQ(one.outcome, UpdateOutcome::kApplied);
  EXPECT_EQ(one.applied, (std::vector<uint64_t>{1, 2, 3}));
  EXPECT_EQ(r.applied, (std::vector<uint64_t>{0, 1, 2, 3}));
  EXPECT_EQ(order.nextSequence(), 4u);
  EXPECT_EQ(order.counts().applied, 2u);
  EXPECT_EQ(order.counts().applied_from_buffer, 2u);
  EXPECT_EQ(order.counts().behindGap(), 0u);
  expectCountsAddUp(order.counts());
}

// A gap longer than the buffer: the robot waits for a snapshot; deltas are dropped until one
// comes; the snapshot brings it back.
TEST(UpdateSequencer, GapWaitsForASnapshot) {
  UpdateSequencer order({2, 64});
  Recorder r;
  order.offer(update(0), r.apply());
  EXPECT_EQ(order.offer(update(2), r.apply()).outcome, UpdateOutcome::kBuffered);
  EXPECT_EQ(order.offer(update(3), r.apply()).outcome, UpdateOutcome::kBuffered);
  EXPECT_EQ(order.offer(update(4), r.apply()).outcome, UpdateOutcome::kWaiting);
  EXPECT_TRUE(order.waitingForSnapshot());
  EXPECT_EQ(order.heldBack(), 0u);  // dropped with the wait
  EXPECT_EQ(order.offer(update(5), r.apply()).outcome, UpdateOutcome::kWaiting);
  EXPECT_EQ(order.counts().behindGap(), 4u);
  EXPECT_EQ(order.offer(update(6, true), r.apply()).outcome, UpdateOutcome::kApplied);
  EXPECT_FALSE(order.waitingForSnapshot());
  EXPECT_EQ(order.offer(update(7), r.apply()).outcome, UpdateOutcome::kApplied);
  EXPECT_EQ(r.applied, (std::vector<uint64_t>{0, 6, 7}));
  EXPECT_EQ(describeUpdates(order.counts(), 1),
            "3 applied of 7, 1 damaged record skipped, 0 rejected, 4 behind a missing update");
  expectCountsAddUp(order.counts());
}

// A snapshot that overtakes buffered deltas supersedes them: they are neither applied nor behind
// a gap.
TEST(UpdateSequencer, SnapshotSupersedesBufferedDeltas) {
  UpdateSequencer order;
  Recorder r;
  order.offer(update(0), r.apply());
  order.offer(update(2), r.apply());
  order.offer(update(3), r.apply());
  order.offer(update(5), r.apply());
  const SequencedUpdate snapshot = order.offer(update(4, true), r.apply());
  EXPECT_EQ(snapshot.applied, (std::vector<uint64_t>{4, 5}));
  EXPECT_EQ(order.counts().superseded, 2u);
  EXPECT_EQ(order.counts().behindGap(), 0u);
  expectCountsAddUp(order.counts());
}

// An earlier sequence: a duplicate when its content is the applied one's, rejected otherwise.
TEST(UpdateSequencer, DuplicatesToldFromConflicts) {
  UpdateSequencer order({}, digestOf);
  Recorder r;
  order.offer(update(0, true, 1), r.apply());
  order.offer(update(1, false, 2), r.apply());
  EXPECT_EQ(order.offer(update(1, false, 2), r.apply()).outcome, UpdateOutcome::kDuplicate);
  const SequencedUpdate conflict = order.offer(update(1, false, 3), r.apply());
  EXPECT_EQ(conflict.outcome, UpdateOutcome::kRejected);
  EXPECT_NE(conflict.message.find("differs from the update applied"), std::string::npos);
  EXPECT_EQ(r.applied, (std::vector<uint64_t>{0, 1}));
  EXPECT_EQ(order.counts().duplicates, 1u);
  EXPECT_EQ(order.counts().rejected, 1u);
  expectCountsAddUp(order.counts());
}

// An update that does not apply is rejected and the robot waits for a snapshot; so does a
// buffered one that fails when it is released.
TEST(UpdateSequencer, FailureToApplyWaitsForASnapshot) {
  UpdateSequencer order;
  Recorder r;
  r.failing = {1, 4};
  order.offer(update(0), r.apply());
  EXPECT_EQ(order.offer(update(1), r.apply()).outcome, UpdateOutcome::kRejected);
  EXPECT_TRUE(order.waitingForSnapshot());
  order.offer(update(2, true), r.apply());
  order.offer(update(4), r.apply());
  order.offer(update(5), r.apply());
  const SequencedUpdate released = order.offer(update(3), r.apply());
  EXPECT_EQ(released.outcome, UpdateOutcome::kApplied);
  ASSERT_EQ(released.released_rejections.size(), 1u);
  EXPECT_EQ(released.released_rejections[0], "sequence 4: does not fit");
  EXPECT_TRUE(order.waitingForSnapshot());
  EXPECT_EQ(r.applied, (std::vector<uint64_t>{0, 2, 3}));
  EXPECT_EQ(order.counts().rejected, 2u);
  EXPECT_EQ(order.counts().behindGap(), 1u);  // 5, dropped with the wait
  order.refuse();
  EXPECT_EQ(order.counts().rejected, 3u);
  expectCountsAddUp(order.counts());
}

}  // namespace
}  // namespace hydra_multi
