#pragma once
// PoseGraph: SE(3) poses keyed by NodeId (GTSAM-style symbols, as in g2o files) and relative-pose
// edges T_from_to with a 6x6 information matrix (translation first). The edge type is the one
// robots send (dsg/robot_update.h), so a robot's pose graph and a g2o file are the same thing here.

#include <map>
#include <vector>

#include "hydra_multi/dsg/robot_update.h"

namespace hydra_multi {

struct PoseGraph {
  std::map<NodeId, Eigen::Isometry3d>
      poses;  ///< initial estimate (may be empty: see initialization)
  std::vector<PoseGraphEdge> edges;

  size_t numLoopClosures() const;
};

/// Marks the edges that are known inliers as odometry, the rest as loop closures. Known inliers
/// are (a) edges between consecutive indices of one category (i, i+1), and (b) the longest prefix
/// of the edge list that is acyclic: files such as grid1000 list a spanning tree first, whose
/// edges do not join consecutive ids (data/README.md).
void classifyEdges(PoseGraph& graph);

/// The poses reached from `root` by composing odometry edges along a breadth-first spanning tree;
/// poses the odometry does not reach are missing from the result.
std::map<NodeId, Eigen::Isometry3d> odometryInitialization(const PoseGraph& graph, NodeId root);

}  // namespace hydra_multi
