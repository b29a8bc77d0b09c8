// Mesh deformation: vertices carried with their control points, those of their own time; a binding
// kept from round to round gives a fresh one's result.

#include <gtest/gtest.h>

#include <random>

#include "hydra_multi/backend/deformation_graph.h"
#include "hydra_multi/backend/mesh_deformation.h"
#include "hydra_multi/core/se3.h"

namespace hydra_multi {
namespace {

// Vertices follow their control points: a rigid motion of all of them moves the vertices by it;
// no motion leaves them in place.
TEST(MeshDeformation, VerticesFollowControlPoints) {
  std::vector<Eigen::Isometry3d> initial;
  for (int x = 0; x < 5; ++x)
    for (int y = 0; y < 5; ++y) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() << x, y, 0.0;
      initial.push_back(T);
    }
  std::vector<MeshVertex> vertices(3);
  vertices[0].position = Eigen::Vector3f(1.3f, 2.2f, 0.4f);
  vertices[1].position = Eigen::Vector3f(3.9f, 0.1f, -0.2f);
  vertices[2].position = Eigen::Vector3f(2.0f, 2.0f, 0.0f);
  const std::vector<int64_t> times(initial.size(), 0);
  std::vector<MeshVertex> same = vertices;
  deformMesh(same, initial, initial, times, 10.0);
  for (size_t i = 0; i < vertices.size(); ++i)
    EXPECT_LT((same[i].position - vertices[i].position).norm(), 1e-5);
  Vector6d xi;
  xi << 0.5, -0.2, 0.1, 0.0, 0.0, 0.3;
  const Eigen::Isometry3d motion = expSE3(xi);
  std::vector<Eigen::Isometry3d> moved;
  for (const Eigen::Isometry3d& T : initial) moved.push_back(motion * T);
  std::vector<MeshVertex> carried = vertices;
  deformMesh(carried, initial, moved, times, 10.0);
  for (size_t i = 0; i < vertices.size(); ++i) {
    const Eigen::Vector3d expected = motion * vertices[i].position.cast<double>();
    EXPECT_LT((carried[i].position.cast<double>() - expected).norm(), 1e-5);
  }
}

// Two passes of one robot over the same place, each with its control points, moved differently by
// the solve: a vertex moves with the control points of its own pass, made within the window of
// its time, though the other pass's lie as near.
TEST(MeshDeformation, VerticesFollowTheControlPointsOfTheirTime) {
  constexpr int64_t kS = 1000000000;
  std::vector<Eigen::Isometry3d> initial, optimized;
  std::vector<int64_t> times;
  const Eigen::Isometry3d first_motion(Eigen::Translation3d(0.5, 0.0, 0.0));
  const Eigen::Isometry3d second_motion(Eigen::Translation3d(0.0, -0.8, 0.0));
  for (int pass = 0; pass < 2; ++pass) {
    for (int x = 0; x < 4; ++x) {
      for (int y = 0; y < 4; ++y) {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.translation() << x + 0.05 * pass, y, 0.0;
        initial.push_back(T);
        optimized.push_back((pass == 0 ? first_motion : second_motion) * T);
        times.push_back(pass == 0 ? 5 * kS : 200 * kS);
      }
    }
  }
  MeshVertex vertex;
  vertex.position = Eigen::Vector3f(1.4f, 1.6f, 0.2f);
  for (const auto& [time, motion] :
       {std::pair<int64_t, Eigen::Isometry3d>{3 * kS, first_motion}, {205 * kS, second_motion}}) {
    std::vector<MeshVertex> vertices = {vertex};
    vertices[0].time_ns = time;
    deformMesh(vertices, initial, optimized, times, 10.0);
    const Eigen::Vector3d expected = motion * vertex.position.cast<double>();
    EXPECT_LT((vertices[0].position.cast<double>() - expected).norm(), 1e-5);
  }
  // Without the window the two passes' motions blend.
  std::vector<MeshVertex> blended = {vertex};
  blended[0].time_ns = 205 * kS;
  deformMesh(blended, initial, optimized, times, 0.0);
  EXPECT_GT(
      (blended[0].position.cast<double>() - second_motion * vertex.position.cast<double>()).norm(),
      0.1);
}

// A robot's mesh bound round after round, as it maps on: each round's binding and blend are those
// of a fresh deformMesh, while vertices nothing new can reach keep their binding, and those whose
// control points kept their poses keep their result.
TEST(MeshDeformation, AKeptBindingIsAFreshOne) {
  constexpr int64_t kS = 1000000000;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  // Control points along a path, one a second; vertices around them, of about their time.
  std::vector<Eigen::Vector3d> points;
  std::vector<int64_t> point_times;
  std::vector<MeshVertex> vertices;
  const auto map = [&](int from_s, int to_s) {
    for (int t = from_s; t < to_s; ++t) {
      points.emplace_back(0.5 * t, 2.0 * std::sin(0.1 * t), 0.0);
      point_times.push_back(t * kS);
      for (int v = 0; v < 6; ++v) {
        MeshVertex vertex;
        vertex.position = (points.back() + Eigen::Vector3d(u(rng), u(rng), u(rng))).cast<float>();
        vertex.time_ns = (t + 0.5 * (u(rng) + 1.0)) * kS;
        vertices.push_back(vertex);
      }
    }
  };
  MeshVertex lone;  // made long after the control points so far: its window holds none
  lone.position = Eigen::Vector3f(3.0f, 0.0f, 0.0f);
  lone.time_ns = 100 * kS;
  Eigen::Isometry3d T_global_robot = expSE3((Vector6d() << 1, -2, 0.3, 0, 0, 0.7).finished());
  std::vector<Eigen::Isometry3d> optimized;
  MeshBinding binding;
  size_t bound_before = 0;
  for (int round = 0; round < 4; ++round) {
    map(20 * round, 20 * round + 20);
    if (round == 1) vertices.push_back(lone);
    if (round == 2) vertices[5].position.x() += 0.3f;  // a vertex the robot revised
    if (round == 3) {  // the robot re-aligned: every control point starts elsewhere
      T_global_robot = expSE3((Vector6d() << 0.5, 0.5, 0, 0, 0, 0.2).finished()) * T_global_robot;
      optimized.clear();
    }
    std::vector<Eigen::Isometry3d> initial;
    for (const Eigen::Vector3d& p : points)
      initial.push_back(T_global_robot * Eigen::Translation3d(p));
    // The solve moves the newest 30 control points; the others keep last round's poses.
    for (size_t c = 0; c < points.size(); ++c) {
      if (c >= optimized.size()) {
        optimized.push_back(initial[c]);
      } else if (c + 30 < points.size()) {
        continue;
      }
      optimized[c] =
          expSE3((Vector6d() << 0.1 * u(rng), 0.1 * u(rng), 0, 0, 0, 0.05 * u(rng)).finished()) *
          initial[c];
    }
    std::vector<MeshVertex> aligned = vertices;
    std::vector<Eigen::Vector3f> positions;
    for (MeshVertex& v : aligned) {
      v.position = (T_global_robot * v.position.cast<double>()).cast<float>();
      positions.push_back(v.position);
    }
    std::vector<MeshVertex> fresh = aligned;
    deformMesh(fresh, initial, optimized, point_times, 10.0);
    bindMesh(binding, vertices, points, point_times, 10.0, 4);
    const std::vector<Eigen::Vector3f> kept = blendMesh(binding, positions, initial, optimized);
    ASSERT_EQ(kept.size(), fresh.size());
    double worst = 0.0;
    for (size_t i = 0; i < kept.size(); ++i)
      worst = std::max(worst, double((kept[i] - fresh[i].position).norm()));
    EXPECT_LT(worst, 1e-5) << "round " << round;
    // Bound again: new vertices, those within 10 s of the new control points (made from 20 *
    // round s on), the revised one and the lone one (any new control point may be the nearest in
    // time); the rest kept.
    size_t expected = 0;
    for (size_t i = 0; i < vertices.size(); ++i) {
      expected += i >= bound_before || vertices[i].time_ns >= (20 * round - 10) * kS ||
                  vertices[i].time_ns == lone.time_ns || (round == 2 && i == 5);
    }
    EXPECT_EQ(binding.bound, expected) << "round " << round;
    // Blended again: what was bound again, and the vertices of the control points the solve
    // moved (the newest 30 of 60 in round 2: those of the first 30 s stay).
    if (round == 2) {
      EXPECT_GE(binding.reblended, binding.bound);
      EXPECT_LT(binding.reblended, vertices.size() * 2 / 3);
    }
    if (round == 3) {
      EXPECT_EQ(binding.reblended, vertices.size());  // re-aligned: all move
    }
    bound_before = vertices.size();
  }
}

}  // namespace
}  // namespace hydra_multi
