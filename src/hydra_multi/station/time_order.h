#pragma once
// Robots' updates put in robot-time order, whatever order the network delivers them in: the order
// the file replay gives them (time, then robot, then sequence; dataset_replay.h), so that a
// networked station builds the map `run` builds. The earliest update held is released once every
// other robot of the team has a later one held or has finished its mission; none waits longer than
// `hold` (while one has, it and every update before it in time go on: a silent robot delays the
// others by at most that). Until `expected_robots` have
// sent something, the team is not complete and only `hold` releases. An update released after
// one later in robot time has gone on (its robot was silent longer than `hold`) is counted late:
// there the order is not the replay's. Not thread-safe: the station calls it
// under its ingest lock.

#include <chrono>
#include <cstddef>
#include <map>
#include <optional>
#include <set>
#include <tuple>
#include <vector>

#include "hydra_multi/dsg/robot_update.h"

namespace hydra_multi {

class TimeOrder {
 public:
  using Clock = std::chrono::steady_clock;

  TimeOrder(Clock::duration hold, size_t expected_robots = 0)
      : hold_(hold), expected_(expected_robots) {}

  void add(RobotUpdate update, Clock::time_point now = Clock::now());
  /// Robot `robot` sends nothing more (its BYE): the others no longer wait for it.
  void finish(RobotId robot);
  /// What may go on now, in order; with `everything`, all that is held.
  std::vector<RobotUpdate> release(Clock::time_point now = Clock::now(), bool everything = false);
  /// When release() may next give something without another add() or finish(): the hold of the
  /// update that arrived first running out (none when nothing is held).
  std::optional<Clock::time_point> deadline() const;
  size_t held() const { return held_.size(); }
  /// Updates released after one later in robot time had gone on, per robot.
  const std::map<RobotId, size_t>& late() const { return late_; }

 private:
  using Key = std::tuple<int64_t, RobotId, uint64_t>;  // time, robot, sequence
  struct Held {
    RobotUpdate update;
    Clock::time_point arrived;
  };
  bool releasable(const Key& key, Clock::time_point now) const;

  Clock::duration hold_;
  size_t expected_;
  std::multimap<Key, Held> held_;
  std::map<RobotId, size_t> held_per_robot_;
  std::set<RobotId> known_, finished_;
  std::optional<Key> latest_;  ///< the latest in robot time released so far
  std::map<RobotId, size_t> late_;
};

}  // namespace hydra_multi
