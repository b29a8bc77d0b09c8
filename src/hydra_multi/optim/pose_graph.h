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
/// are the edges between consecutive indices of one category (i, i+1). When those edges leave the
/// graph in more than `max_odometry_components` pieces (files such as grid1000 list a spanning tree
/// first, whose edges do not join consecutive ids; data/README.md), the longest acyclic prefix of
/// the edge list counts as odometry too.
void classifyEdges(PoseGraph& graph, size_t max_odometry_components = 1);

/// The poses reached from `root` by composing odometry edges along a breadth-first spanning tree;
/// poses the odometry does not reach are missing from the result.
std::map<NodeId, Eigen::Isometry3d> odometryInitialization(const PoseGraph& graph, NodeId root);

/// Like odometryInitialization, but a node the odometry does not reach is reached through loop
/// closures too, with as few of them on its path as possible (0-1 breadth-first search: odometry
/// costs 0, a loop closure 1). For robots whose own edges are not a chain (e.g. the grid3d data).
std::map<NodeId, Eigen::Isometry3d> spanningInitialization(const PoseGraph& graph, NodeId root);

}  // namespace hydra_multi
