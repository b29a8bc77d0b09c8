#include "hydra_multi/station/time_order.h"

namespace hydra_multi {

void TimeOrder::add(RobotUpdate update, Clock::time_point now) {
  known_.insert(update.robot);
  ++held_per_robot_[update.robot];
  const Key key{update.time_ns, update.robot, update.sequence};
  held_.emplace(key, Held{std::move(update), now});
}

void TimeOrder::finish(RobotId robot) {
  known_.insert(robot);
  finished_.insert(robot);
}

bool TimeOrder::releasable(const Key& key, Clock::time_point now) const {
  // Nothing waits longer than `hold`: while one has, the updates before it in time go on too.
  if (const auto due = deadline(); due && now >= *due) return true;
  if (known_.size() < expected_) return false;
  const RobotId robot = std::get<1>(key);
  for (const RobotId other : known_) {
    if (other == robot || finished_.count(other)) continue;
    const auto it = held_per_robot_.find(other);
    if (it == held_per_robot_.end() || it->second == 0) return false;  // it may send earlier
  }
  return true;
}

std::vector<RobotUpdate> TimeOrder::release(Clock::time_point now, bool everything) {
  std::vector<RobotUpdate> out;
  while (!held_.empty()) {
    auto first = held_.begin();
    if (!everything && !releasable(first->first, now)) break;
    --held_per_robot_[first->second.update.robot];
    if (latest_ && first->first < *latest_)
      ++late_[first->second.update.robot];
    else
      latest_ = first->first;
    out.push_back(std::move(first->second.update));
    held_.erase(first);
  }
  return out;
}

std::optional<TimeOrder::Clock::time_point> TimeOrder::deadline() const {
  std::optional<Clock::time_point> earliest;
  for (const auto& [key, h] : held_) {
    if (!earliest || h.arrived < *earliest) earliest = h.arrived;
  }
  if (!earliest) return std::nullopt;
  return *earliest + hold_;
}

}  // namespace hydra_multi
