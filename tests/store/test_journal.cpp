// The station's journal: what is appended is replayed, in order and byte for byte, also after the
// journal is closed and opened again; a robot's sequence goes in once; which robots said BYE is
// kept; a file that is not a journal is refused, naming it.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "hydra_multi/store/journal.h"

namespace hydra_multi::store {
namespace {

namespace fs = std::filesystem;

class JournalTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("hydra_multi_journal_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path() const { return (dir_ / "journal.sqlite").string(); }
  fs::path dir_;
};

JournalEntry entry(uint8_t robot, uint64_t sequence) {
  JournalEntry e;
  e.robot = RobotId(robot);
  e.epoch = 0xF000000000000001ull;  // above 2^63: stored bit for bit
  e.sequence = sequence;
  e.payload = std::string("record\0", 7) + std::to_string(sequence);
  e.arrival_ns = 1000 + static_cast<int64_t>(sequence);
  return e;
}

std::vector<JournalEntry> everything(const Journal& journal) {
  std::vector<JournalEntry> entries;
  EXPECT_TRUE(journal.replay([&](JournalEntry&& e) { entries.push_back(std::move(e)); }).ok());
  return entries;
}

// Appended entries come back in order, whole, after a reopen too, with either durability.
TEST_F(JournalTest, ReplaysWhatWasAppended) {
  for (const Durability durability : {Durability::kFull, Durability::kNormal}) {
    fs::remove(path());
    {
      auto journal = Journal::open(path(), durability);
      ASSERT_TRUE(journal.ok()) << journal.error();
      for (uint64_t s = 0; s < 5; ++s) ASSERT_TRUE(journal.value()->append(entry(1, s)).ok());
      ASSERT_TRUE(journal.value()->append(entry(0, 0)).ok());
    }
    auto journal = Journal::open(path(), durability);
    ASSERT_TRUE(journal.ok()) << journal.error();
    EXPECT_EQ(journal.value()->size(), 6u);
    EXPECT_EQ(journal.value()->integrityCheck(), "ok");
    const std::vector<JournalEntry> entries = everything(*journal.value());
    ASSERT_EQ(entries.size(), 6u);
    for (uint64_t s = 0; s < 5; ++s) {
      const JournalEntry want = entry(1, s);
      EXPECT_EQ(entries[s].robot, want.robot);
      EXPECT_EQ(entries[s].epoch, want.epoch);
      EXPECT_EQ(entries[s].sequence, s);
      EXPECT_EQ(entries[s].payload, want.payload);
      EXPECT_EQ(entries[s].arrival_ns, want.arrival_ns);
    }
    EXPECT_EQ(entries[5].robot, RobotId(0));
  }
}

// A robot's BYE is kept across a reopen, the last one per robot; a robot that sent an update after
// its BYE (a new process of it) is no longer done.
TEST_F(JournalTest, KeepsWhichRobotsAreDone) {
  {
    auto journal = Journal::open(path());
    ASSERT_TRUE(journal.ok());
    ASSERT_TRUE(journal.value()->append(entry(0, 0)).ok());
    ASSERT_TRUE(journal.value()->append(entry(1, 0)).ok());
    ASSERT_TRUE(journal.value()->markDone(RobotId(0), 5).ok());
    ASSERT_TRUE(journal.value()->markDone(RobotId(1), 6).ok());
    ASSERT_TRUE(journal.value()->markDone(RobotId(1), 7).ok());  // said again: the last counts
    ASSERT_TRUE(journal.value()->markDone(RobotId(2), 8).ok());  // done without an update
  }
  auto journal = Journal::open(path());
  ASSERT_TRUE(journal.ok());
  auto done = journal.value()->done();
  ASSERT_TRUE(done.ok()) << done.error();
  EXPECT_EQ(done.value(),
            (std::map<RobotId, uint64_t>{{RobotId(0), 5}, {RobotId(1), 7}, {RobotId(2), 8}}));
  ASSERT_TRUE(journal.value()->append(entry(1, 1)).ok());  // robot b came back
  done = journal.value()->done();
  ASSERT_TRUE(done.ok());
  EXPECT_EQ(done.value(), (std::map<RobotId, uint64_t>{{RobotId(0), 5}, {RobotId(2), 8}}));
  EXPECT_EQ(journal.value()->size(), 3u) << "BYEs are not updates";
  EXPECT_EQ(journal.value()->integrityCheck(), "ok");
}

// A robot's sequence goes in once; the second append is refused and changes nothing.
TEST_F(JournalTest, ASequenceGoesInOnce) {
  auto journal = Journal::open(path());
  ASSERT_TRUE(journal.ok());
  ASSERT_TRUE(journal.value()->append(entry(2, 7)).ok());
  const Status again = journal.value()->append(entry(2, 7));
  ASSERT_FALSE(again.ok());
  EXPECT_EQ(again.message(), path() + ": update 7 of robot c is in the journal already");
  EXPECT_TRUE(journal.value()->append(entry(1, 7)).ok());  // another robot's 7
  EXPECT_EQ(journal.value()->size(), 2u);
}

// A snapshot may carry the sequence of a delta held already (the station asked for it across a
// gap): it goes in once beside it, and comes back marked as a snapshot.
TEST_F(JournalTest, ASnapshotGoesInBesideTheDeltaOfItsSequence) {
  auto journal = Journal::open(path());
  ASSERT_TRUE(journal.ok());
  ASSERT_TRUE(journal.value()->append(entry(2, 7)).ok());
  JournalEntry snapshot = entry(2, 7);
  snapshot.snapshot = true;
  ASSERT_TRUE(journal.value()->append(snapshot).ok());
  const Status again = journal.value()->append(snapshot);
  ASSERT_FALSE(again.ok());
  EXPECT_EQ(again.message(), path() + ": snapshot 7 of robot c is in the journal already");
  const std::vector<JournalEntry> entries = everything(*journal.value());
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_FALSE(entries[0].snapshot);
  EXPECT_TRUE(entries[1].snapshot);
}

// What is not a journal is refused with the file named: a text file, a folder, another
// database's table of the same name.
TEST_F(JournalTest, RefusesWhatIsNotAJournal) {
  std::ofstream(path()) << "not a database at all, but long enough to have a header........\n";
  auto text = Journal::open(path());
  ASSERT_FALSE(text.ok());
  EXPECT_EQ(text.error().rfind(path() + ": not a journal (SQLite): ", 0), 0u) << text.error();
  auto folder = Journal::open(dir_.string());
  ASSERT_FALSE(folder.ok());
  EXPECT_EQ(folder.error().rfind(dir_.string() + ": ", 0), 0u) << folder.error();
}

}  // namespace
}  // namespace hydra_multi::store
