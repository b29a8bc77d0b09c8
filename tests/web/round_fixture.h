#pragma once
// A backend round's output built around a random graph, for the viewer's tests.

#include <algorithm>
#include <random>

#include "hydra_multi/station/station.h"
#include "support/random_graphs.h"

namespace hydra_multi::testing {

struct RoundFixture {
  SceneGraph graph;
  RoundTiming timing;
  std::vector<LoopClosureVerdict> closures;
  std::vector<AcceptedMerge> merges;
  std::map<RobotId, RobotFrameAlignment> aligned;
  std::map<RobotId, RobotProgress> progress;

  explicit RoundFixture(uint32_t seed, RandomGraphSize size = {}) {
    std::mt19937 rng(seed);
    graph = makeRandomGraph(rng, size);
    // The backend appends the robots' meshes one after the other.
    Mesh& mesh = graph.mesh();
    for (size_t i = 0; i < mesh.vertices.size(); ++i)
      mesh.vertices[i].robot = RobotId(i < mesh.vertices.size() / 2 ? 0 : 1);
    std::stable_sort(mesh.faces.begin(), mesh.faces.end(),
                     [&](const MeshFace& a, const MeshFace& b) {
                       return mesh.vertices[a[0]].robot.index() < mesh.vertices[b[0]].robot.index();
                     });
    timing.round = 3;
    timing.after_update = 40;
    timing.report.time_s = 0.25;
    timing.report.merges_accepted = 1;
    std::vector<NodeId> agents = graph.nodesInLayer(Layer::kAgents);
    if (agents.size() >= 4) {
      closures.push_back({agents[0], agents[2], false, true});
      closures.push_back({agents[1], agents[3], true, false});
    }
    std::vector<NodeId> places = graph.nodesInLayer(Layer::kPlaces);
    if (places.size() >= 2) {
      AcceptedMerge m;
      m.target = places[0];
      m.source = places[1];
      m.layer = Layer::kPlaces;
      m.target_optimized = {1.0, 2.0, 0.5};
      m.source_optimized = {1.2, 2.1, 0.5};
      merges.push_back(m);
    }
    for (const RobotId r : graph.robots()) {
      aligned[r];
      progress[r] = {12, 13, 4'500'000'000};
    }
  }

  RoundOutput output() const { return {graph, timing, closures, merges, aligned, progress}; }
};

}  // namespace hydra_multi::testing
