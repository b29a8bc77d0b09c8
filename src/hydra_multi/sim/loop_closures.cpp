#include "hydra_multi/sim/loop_closures.h"

#include <cmath>
#include <limits>
#include <random>

namespace hydra_multi::sim {
namespace {

double yawOf(const Eigen::Isometry3d& T) { return std::atan2(T.linear()(1, 0), T.linear()(0, 0)); }

double angleBetween(double a, double b) { return std::abs(std::remainder(a - b, 2.0 * M_PI)); }

}  // namespace

std::vector<SimulatedLoopClosure> simulateLoopClosures(const World& world,
                                                       const std::vector<StampedPose>& truth,
                                                       const std::vector<int>& rooms,
                                                       const LoopClosureOptions& options) {
  std::vector<SimulatedLoopClosure> closures;
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const double max_yaw = options.max_yaw_deg * M_PI / 180.0;
  const auto roomPose = [&](size_t k) -> Eigen::Isometry3d {
    return world.roomFrame(world.room(rooms[k])).inverse() * truth[k].T_world_body;
  };
  const auto aliased = [&](size_t k) { return rooms[k] >= 0 && world.room(rooms[k]).layout >= 0; };
  int64_t last_time = INT64_MIN / 2;
  for (size_t k = 0; k < truth.size(); ++k) {
    const int64_t t_k = truth[k].time_ns;
    if (t_k - last_time < static_cast<int64_t>(options.cooldown_s * 1e9)) continue;
    // The candidates nearest in pose (position + 1 m per radian of yaw) among earlier keyframes:
    // the best true revisit and the best look-alike in another identical room.
    double best[2] = {std::numeric_limits<double>::infinity(),
                      std::numeric_limits<double>::infinity()};
    size_t best_j[2] = {0, 0};
    for (size_t j = 0; j < k; ++j) {
      if (t_k - truth[j].time_ns < static_cast<int64_t>(options.min_time_gap_s * 1e9)) break;
      Eigen::Isometry3d a = truth[j].T_world_body, b = truth[k].T_world_body;
      int alias = 0;
      if (rooms[j] != rooms[k] && aliased(j) && aliased(k) &&
          world.room(rooms[j]).layout == world.room(rooms[k]).layout) {
        a = roomPose(j);
        b = roomPose(k);
        alias = 1;
      }
      const double distance = (a.translation() - b.translation()).norm();
      const double yaw = angleBetween(yawOf(a), yawOf(b));
      if (distance > options.max_distance || yaw > max_yaw) continue;
      if (distance + yaw < best[alias]) {
        best[alias] = distance + yaw;
        best_j[alias] = j;
      }
    }
    // A look-alike that looks better than the true revisit fools the robot now and then.
    bool best_is_alias =
        std::isfinite(best[1]) && best[1] < best[0] && unit(rng) < options.aliasing_acceptance;
    if (!best_is_alias && !std::isfinite(best[0])) continue;
    SimulatedLoopClosure closure;
    const size_t from = best_j[best_is_alias ? 1 : 0];
    closure.from = from;
    closure.to = k;
    closure.T_from_to = best_is_alias ? roomPose(from).inverse() * roomPose(k)
                                      : truth[from].T_world_body.inverse() * truth[k].T_world_body;
    closure.kind = best_is_alias ? SimulatedLoopClosure::Kind::kAliasing
                                 : SimulatedLoopClosure::Kind::kRevisit;
    closure.correct = !best_is_alias;
    if (!best_is_alias && unit(rng) < options.gross_error_share) {
      // A gross mistake: 1-3 m off and 20-60 degrees of yaw, in a random direction.
      const double angle = 2.0 * M_PI * unit(rng);
      Vector6d error = Vector6d::Zero();
      const double metres = 1.0 + 2.0 * unit(rng);
      error.head<2>() << metres * std::cos(angle), metres * std::sin(angle);
      error[5] = (unit(rng) < 0.5 ? -1 : 1) * (20.0 + 40.0 * unit(rng)) * M_PI / 180.0;
      closure.T_from_to = closure.T_from_to * expSE3(error);
      closure.kind = SimulatedLoopClosure::Kind::kGrossError;
      closure.correct = false;
    }
    Vector6d noise;
    for (int i = 0; i < 3; ++i) noise[i] = options.translation_sigma * gauss(rng);
    for (int i = 3; i < 6; ++i) noise[i] = options.rotation_sigma_deg * M_PI / 180.0 * gauss(rng);
    closure.T_from_to = closure.T_from_to * expSE3(noise);
    closures.push_back(closure);
    last_time = t_k;
  }
  return closures;
}

}  // namespace hydra_multi::sim
