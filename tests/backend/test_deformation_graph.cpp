// The deformation graph: drifted robots pulled onto the truth by inter-robot loop closures, with
// wrong ones rejected by GNC; mesh vertices carried along with their control points.

#include <gtest/gtest.h>

#include <random>

#include "hydra_multi/backend/deformation_graph.h"
#include "hydra_multi/core/se3.h"

namespace hydra_multi {
namespace {

Eigen::Isometry3d circle(double angle, double radius = 10.0) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() << radius * std::cos(angle), radius * std::sin(angle), 0.0;
  T.linear() = Eigen::AngleAxisd(angle + M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}

struct Robot {
  RobotId id;
  std::vector<Eigen::Isometry3d> truth;  // global frame
  std::vector<Eigen::Isometry3d> odom;   // own frame, drifting
  std::vector<PoseGraphEdge> pose_graph;
  std::vector<ControlPoint> control_points;
  std::vector<ControlPointEdge> control_point_edges;
};

// Robot r drives 60 keyframes around a circle from its own start, with a yaw drift; one control
// point 1 m beside each keyframe, chained.
Robot drive(RobotId id, double start_angle, double yaw_drift, SceneGraph& frontend) {
  Robot r;
  r.id = id;
  for (int k = 0; k < 60; ++k) r.truth.push_back(circle(start_angle + 2 * M_PI * k / 60.0));
  r.odom.push_back(Eigen::Isometry3d::Identity());
  for (size_t k = 1; k < r.truth.size(); ++k) {
    Vector6d xi = Vector6d::Zero();
    xi[5] = yaw_drift;
    r.odom.push_back(r.odom.back() * (r.truth[k - 1].inverse() * r.truth[k]) * expSE3(xi));
  }
  for (size_t k = 0; k < r.truth.size(); ++k) {
    const NodeId kf = NodeId::station(id.prefix(), id, k);
    Node node = makeNode(kf, Layer::kAgents, r.odom[k].translation());
    node.find<AgentAttributes>()->orientation = Eigen::Quaterniond(r.odom[k].linear());
    node.find<AgentAttributes>()->timestamp_ns = static_cast<int64_t>(k) * 1000000000;
    frontend.addOrUpdateNode(node);
    if (k > 0) {
      PoseGraphEdge e;
      e.from = NodeId::station(id.prefix(), id, k - 1);
      e.to = kf;
      e.T_from_to = r.odom[k - 1].inverse() * r.odom[k];
      e.information = Matrix6d::Identity() * 100.0;
      r.pose_graph.push_back(e);
    }
    ControlPoint cp;
    cp.id = k;
    cp.position = r.odom[k] * Eigen::Vector3d(0, 1, 0);
    cp.keyframe = kf;
    r.control_points.push_back(cp);
    if (k > 0) r.control_point_edges.push_back({k - 1, k});
  }
  return r;
}

TEST(DeformationGraph, LoopClosuresCorrectDriftAndOutliersAreRejected) {
  SceneGraph frontend;
  // Robot a's odometry is exact, robot b's turns 0.3 degrees too much at every keyframe: the
  // loop closures with a are what can straighten b.
  Robot a = drive(RobotId(0), 0.0, 0.0, frontend);
  Robot b = drive(RobotId(1), M_PI, 0.005, frontend);
  const auto kf = [](const Robot& r, size_t k) { return NodeId::station(r.id.prefix(), r.id, k); };
  // True closures wherever both robots pass the same place, and wrong ones.
  std::vector<PoseGraphEdge> inter;
  std::mt19937_64 rng(3);
  for (size_t k = 0; k < 60; k += 3) {
    PoseGraphEdge e;
    e.from = kf(a, k);
    e.to = kf(b, (k + 30) % 60);  // b started half a circle on
    e.T_from_to = a.truth[k].inverse() * b.truth[(k + 30) % 60];
    e.information = Matrix6d::Identity() * 100.0;
    inter.push_back(e);
  }
  const size_t good = inter.size();
  std::uniform_int_distribution<size_t> pick(0, 59);
  for (int i = 0; i < 8; ++i) {
    // Wrong by 3 m and 45 degrees (what a look-alike place gives).
    PoseGraphEdge e = inter.front();
    const size_t ka = pick(rng), kb = pick(rng);
    e.from = kf(a, ka);
    e.to = kf(b, kb);
    Vector6d wrong;
    wrong << 3.0 * std::cos(i), 3.0 * std::sin(i), 0.0, 0.0, 0.0, (i % 2 ? 1 : -1) * M_PI / 4;
    e.T_from_to = a.truth[ka].inverse() * b.truth[kb] * expSE3(wrong);
    inter.push_back(e);
  }
  // The alignment is the truth of the starts (what initial alignment would estimate).
  const Eigen::Isometry3d T_global_b = a.truth.front().inverse() * b.truth.front();
  std::vector<RobotDeformationInput> inputs = {
      {a.id, Eigen::Isometry3d::Identity(), &a.pose_graph, &a.control_points,
       &a.control_point_edges},
      {b.id, T_global_b, &b.pose_graph, &b.control_points, &b.control_point_edges}};
  // The edges here carry calibrated information (robot b's drift is in its odometry edges' noise
  // model only as far as their values go): use it rather than Kimera-PGMO's variances.
  DeformationGraphOptions options;
  options.use_sent_information = true;
  const DeformationGraph graph = buildDeformationGraph(frontend, inputs, inter, {}, options);
  EXPECT_EQ(graph.inter_robot_factors, inter.size());
  EXPECT_EQ(graph.anchor, kf(a, 0));
  const DeformationResult result = optimizeDeformationGraph(graph, options);
  // Error of the keyframes against the truth (global = robot a's start), before and after.
  const Eigen::Isometry3d T_global_world = a.truth.front().inverse();
  double before = 0.0, after = 0.0;
  for (const Robot* r : {&a, &b}) {
    for (size_t k = 0; k < 60; ++k) {
      const Eigen::Vector3d truth = (T_global_world * r->truth[k]).translation();
      before = std::max(before, (graph.initial.at(kf(*r, k)).translation() - truth).norm());
      after = std::max(after, (result.poses.at(kf(*r, k)).translation() - truth).norm());
    }
  }
  EXPECT_GT(before, 1.0);
  EXPECT_LT(after, 0.3);
  size_t accepted_good = 0, accepted_bad = 0;
  for (size_t i = 0; i < inter.size(); ++i) {
    const bool inlier = result.robust_inlier.at({inter[i].from, inter[i].to});
    (i < good ? accepted_good : accepted_bad) += inlier;
  }
  EXPECT_EQ(accepted_good, good);
  EXPECT_EQ(accepted_bad, 0u);
}

// Vertices follow their control points: a rigid motion of all of them moves the vertices by it;
// no motion leaves them in place.
TEST(DeformationGraph, MeshFollowsControlPoints) {
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
  std::vector<MeshVertex> same = vertices;
  deformMesh(same, initial, initial);
  for (size_t i = 0; i < vertices.size(); ++i)
    EXPECT_LT((same[i].position - vertices[i].position).norm(), 1e-5);
  Vector6d xi;
  xi << 0.5, -0.2, 0.1, 0.0, 0.0, 0.3;
  const Eigen::Isometry3d motion = expSE3(xi);
  std::vector<Eigen::Isometry3d> moved;
  for (const Eigen::Isometry3d& T : initial) moved.push_back(motion * T);
  std::vector<MeshVertex> carried = vertices;
  deformMesh(carried, initial, moved);
  for (size_t i = 0; i < vertices.size(); ++i) {
    const Eigen::Vector3d expected = motion * vertices[i].position.cast<double>();
    EXPECT_LT((carried[i].position.cast<double>() - expected).norm(), 1e-5);
  }
}

}  // namespace
}  // namespace hydra_multi
