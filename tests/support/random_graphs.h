#pragma once
// Random scene graphs and robot updates for tests: every layer, every attribute set to a random
// value (so a round trip that drops one is caught), deterministic from the generator's seed.

#include <map>
#include <random>

#include "hydra_multi/dsg/robot_update.h"
#include "hydra_multi/dsg/scene_graph.h"

namespace hydra_multi::testing {

struct RandomGraphSize {
  int agents = 20;
  int objects = 8;
  int places = 30;
  int rooms = 3;
  int mesh_vertices = 200;
  int mesh_faces = 300;
};

/// A valid graph: agents of two robots in a chain under places, places joined among themselves
/// and under rooms, objects under places, rooms under one building; a mesh.
SceneGraph makeRandomGraph(std::mt19937& rng, const RandomGraphSize& size = {});

/// A valid robot update with every field filled.
RobotUpdate makeRandomUpdate(std::mt19937& rng, uint64_t sequence = 7);

/// A random trajectory of `n` poses x0, x1, ...: steps of 1 m forward with some sideways motion
/// and turning.
std::map<NodeId, Eigen::Isometry3d> randomTrajectory(std::mt19937& rng, int n);

/// `poses` each moved by exp(xi) with xi ~ N(0, sigma^2) per coordinate, but the anchor.
std::map<NodeId, Eigen::Isometry3d> perturbPoses(std::map<NodeId, Eigen::Isometry3d> poses,
                                                 NodeId anchor, double sigma, std::mt19937& rng);

/// The directory of the shared real data (../shared/data from the project root).
std::string dataDir();

}  // namespace hydra_multi::testing
