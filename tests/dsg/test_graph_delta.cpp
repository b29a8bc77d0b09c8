#include <gtest/gtest.h>

#include <random>

#include "hydra_multi/dsg/graph_delta.h"
#include "support/random_graphs.h"

namespace hydra_multi {
namespace {

// Changes a graph at random: moves, removals, new nodes and edges, mesh growth and edits.
SceneGraph mutate(SceneGraph g, std::mt19937& rng) {
  std::vector<NodeId> ids;
  for (const auto& [id, node] : g.nodes()) ids.push_back(id);
  for (int i = 0; i < 5 && !ids.empty(); ++i) {
    const NodeId id = ids[rng() % ids.size()];
    if (Node* node = g.findMutableNode(id)) node->position.x() += 1.0;
  }
  for (int i = 0; i < 3 && !ids.empty(); ++i) g.removeNode(ids[rng() % ids.size()]);
  g.addOrUpdateNode(makeNode(NodeId('O', 500), Layer::kObjects, {1, 2, 3}));
  if (g.hasNode(NodeId('p', 3))) g.addOrUpdateEdge(NodeId('p', 3), NodeId('O', 500));
  if (!g.edges().empty()) {
    const EdgeKey key = g.edges().begin()->first;
    g.addOrUpdateEdge(key.first(), key.second(), {9.0, true});
  }
  Mesh& mesh = g.mesh();
  if (!mesh.vertices.empty()) mesh.vertices[mesh.vertices.size() / 2].color.r ^= 1;
  mesh.vertices.push_back(mesh.vertices.front());
  mesh.faces.push_back({0, 1, static_cast<uint32_t>(mesh.vertices.size() - 1)});
  return g;
}

// applyDelta(a, diffGraphs(a, b)) == b for random pairs, including the empty graph both ways.
TEST(GraphDelta, DiffThenApplyReproducesTarget) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 30; ++trial) {
    const SceneGraph a = testing::makeRandomGraph(rng);
    const SceneGraph b = mutate(a, rng);
    for (const auto& [from, to] : {std::pair{a, b}, std::pair{b, a}, std::pair{SceneGraph(), a},
                                   std::pair{a, SceneGraph()}}) {
      SceneGraph result = from;
      ASSERT_TRUE(applyDelta(result, diffGraphs(from, to)).ok());
      EXPECT_EQ(result, to);
    }
  }
}

// The diff of a graph with itself changes nothing; an append-only mesh gives an append delta.
TEST(GraphDelta, MinimalDeltas) {
  std::mt19937 rng(12);
  const SceneGraph a = testing::makeRandomGraph(rng);
  const GraphDelta none = diffGraphs(a, a);
  EXPECT_TRUE(none.nodes.empty());
  EXPECT_TRUE(none.removed_nodes.empty());
  EXPECT_TRUE(none.edges.empty());
  EXPECT_TRUE(none.removed_edges.empty());
  EXPECT_TRUE(none.mesh.isNoOp(a.mesh().vertices.size(), a.mesh().faces.size()));

  SceneGraph grown = a;
  grown.mesh().vertices.push_back(MeshVertex{});
  const GraphDelta append = diffGraphs(a, grown);
  EXPECT_EQ(append.mesh.vertex_start, a.mesh().vertices.size());
  EXPECT_EQ(append.mesh.vertices.size(), 1u);
  EXPECT_EQ(append.mesh.face_start, a.mesh().faces.size());
}

// A node that changes layer is removed and re-added, and its edges come back.
TEST(GraphDelta, LayerChangeIsRemoveAndAdd) {
  SceneGraph a, b;
  a.addOrUpdateNode(makeNode(NodeId('x', 1), Layer::kObjects));
  a.addOrUpdateNode(makeNode(NodeId('p', 1), Layer::kPlaces));
  a.addOrUpdateEdge(NodeId('x', 1), NodeId('p', 1));
  b.addOrUpdateNode(makeNode(NodeId('x', 1), Layer::kPlaces));
  b.addOrUpdateNode(makeNode(NodeId('p', 1), Layer::kPlaces));
  b.addOrUpdateEdge(NodeId('x', 1), NodeId('p', 1), {2.0, true});
  ASSERT_TRUE(applyDelta(a, diffGraphs(a, b)).ok());
  EXPECT_EQ(a, b);
}

// A bad delta is rejected whole, with a message naming the item, and the graph is untouched.
TEST(GraphDelta, BadDeltaLeavesGraphUntouched) {
  std::mt19937 rng(13);
  const SceneGraph original = testing::makeRandomGraph(rng);
  auto expectRejected = [&](const GraphDelta& delta, const std::string& needle) {
    SceneGraph g = original;
    const Status status = applyDelta(g, delta);
    ASSERT_FALSE(status.ok());
    EXPECT_NE(status.message().find(needle), std::string::npos) << status.message();
    EXPECT_EQ(g, original);
  };
  GraphDelta dangling;
  dangling.nodes.push_back(makeNode(NodeId('O', 77), Layer::kObjects));
  dangling.edges.push_back({NodeId('O', 77), NodeId('p', 999), {}});
  dangling.mesh.vertex_start = original.mesh().vertices.size();
  dangling.mesh.face_start = original.mesh().faces.size();
  expectRejected(dangling, "endpoint p(999) does not exist");

  GraphDelta nan = dangling;
  nan.edges.clear();
  nan.nodes[0].position.y() = std::nan("");
  expectRejected(nan, "position is not finite");

  GraphDelta layer_change = dangling;
  layer_change.edges.clear();
  layer_change.nodes = {makeNode(NodeId('p', 1), Layer::kRooms)};
  expectRejected(layer_change, "exists in layer places");

  GraphDelta bad_face = dangling;
  bad_face.edges.clear();
  bad_face.mesh.faces.push_back({0, 1, 100000});
  expectRejected(bad_face, "vertex 100000 does not exist");

  GraphDelta past_end = bad_face;
  past_end.mesh.faces.clear();
  past_end.mesh.vertex_start = original.mesh().vertices.size() + 5;
  expectRejected(past_end, "vertex_start");

  GraphDelta cut = past_end;
  cut.mesh.vertex_start = 0;  // removing every vertex strands the kept faces
  expectRejected(cut, "leaves face");

  GraphDelta twice = past_end;
  twice.mesh.vertex_start = original.mesh().vertices.size();
  twice.nodes.push_back(twice.nodes[0]);
  expectRejected(twice, "given twice");
}

}  // namespace
}  // namespace hydra_multi
