#include "hydra_multi/web/view_state.h"

#include <gtest/gtest.h>

#include <cstring>

#include "hydra_multi/web/viewer_mesh.h"
#include "web/round_fixture.h"

namespace hydra_multi::web {
namespace {

using nlohmann::json;
using testing::RoundFixture;

TEST(ViewState, HoldsEveryNodeClosureMergeAndTheMeshExtents) {
  const RoundFixture f(1);
  const ViewState view = viewOfRound(f.output());
  EXPECT_EQ(view.round, 3u);
  EXPECT_EQ(view.tables.at("nodes").size(), f.graph.numNodes());
  size_t intra_layer = 0;
  for (const auto& [key, info] : f.graph.edges())
    intra_layer += f.graph.getNode(key.first()).layer() == f.graph.getNode(key.second()).layer();
  EXPECT_EQ(view.tables.at("edges").size(), intra_layer);
  EXPECT_EQ(view.tables.at("loop_closures").size(), 2u);
  ASSERT_EQ(view.tables.at("merges").size(), 1u);
  const json& merge = view.tables.at("merges").begin()->second;
  EXPECT_EQ(merge[3], 100);  // cm
  EXPECT_EQ(merge[6], 120);
  // A node's row: id, layer, robot, position in cm, parent.
  const Node& agent = f.graph.getNode(f.graph.nodesInLayer(Layer::kAgents).front());
  const json& row = view.tables.at("nodes").at(agent.id.str());
  EXPECT_EQ(row[1], "agents");
  EXPECT_EQ(row[2], agent.robot()->str());
  EXPECT_EQ(row[3], std::llround(agent.position.x() * 100));
  const std::optional<NodeId> parent = f.graph.parent(agent.id);
  EXPECT_EQ(row[6], parent ? parent->str() : "");
  EXPECT_EQ(row[7]["k"], agent.find<AgentAttributes>()->keyframe_id);
  // The mesh extents add up to the mesh.
  uint64_t vertices = 0, faces = 0;
  for (const auto& [robot, range] : view.mesh.items()) {
    vertices += range[1].get<uint64_t>();
    faces += range[3].get<uint64_t>();
  }
  EXPECT_EQ(vertices, f.graph.mesh().vertices.size());
  EXPECT_EQ(faces, f.graph.mesh().faces.size());
  EXPECT_EQ(view.robots["a"]["applied"], 12);
  EXPECT_EQ(view.robots["a"]["aligned"], true);
}

TEST(ViewState, DeltaTurnsOneRoundIntoTheNext) {
  RoundFixture f(2);
  const ViewState before = viewOfRound(f.output());
  // Move one node a metre, another by 2 mm (under the rounding), remove one, add one.
  const std::vector<NodeId> places = f.graph.nodesInLayer(Layer::kPlaces);
  f.graph.findMutableNode(places[2])->position.x() += 1.0;
  f.graph.findMutableNode(places[3])->position.x() += 0.002;
  f.graph.removeNode(places[4]);
  f.graph.addOrUpdateNode(makeNode(NodeId('O', 77), Layer::kObjects, {1, 2, 3}));
  f.closures.pop_back();
  f.timing.round = 4;
  const ViewState after = viewOfRound(f.output());
  const json delta = diffViews(before, after);
  std::set<std::string> set;
  for (const json& row : delta["set"]["nodes"]) set.insert(row[0].get<std::string>());
  EXPECT_TRUE(set.count(places[2].str()));
  EXPECT_TRUE(set.count("O(77)"));
  EXPECT_FALSE(set.count(places[3].str())) << "a 2 mm move is under the view's centimetres";
  EXPECT_EQ(delta["del"]["nodes"], json::array({places[4].str()}));
  EXPECT_EQ(delta["del"]["loop_closures"].size(), 1u);

  ViewState applied = before;
  ASSERT_TRUE(applyViewDelta(applied, delta));
  EXPECT_EQ(applied, after);
  ViewState fresh;
  ASSERT_TRUE(applyViewDelta(fresh, snapshotOfView(after)));
  EXPECT_EQ(fresh, after);
  // A snapshot replaces whatever was held.
  ASSERT_TRUE(applyViewDelta(applied, snapshotOfView(before)));
  EXPECT_EQ(applied, before);
}

TEST(ViewState, MalformedDeltaIsRefusedAndChangesNothing) {
  const RoundFixture f(3);
  const ViewState view = viewOfRound(f.output());
  const json good = diffViews(view, view);
  const auto refused = [&](json delta, const std::string& names) {
    ViewState copy = view;
    const Status s = applyViewDelta(copy, delta);
    EXPECT_FALSE(s) << delta.dump();
    EXPECT_NE(s.message().find(names), std::string::npos) << s.message();
    EXPECT_EQ(copy, view);
  };
  refused(json::array(), "not a JSON object");
  json d = good;
  d.erase("seq");
  refused(d, "'seq'");
  d = good;
  d["set"]["walls"] = json::array();
  refused(d, "unknown table 'walls'");
  d = good;
  d["set"]["nodes"] = json::array({json::array({1, 2})});
  refused(d, "set.nodes");
  d = good;
  d["del"]["nodes"] = json::array({"O(12345)"});
  refused(d, "O(12345)");
  d = good;
  d["info"] = nullptr;
  refused(d, "'info'");
}

TEST(ViewerMesh, RoundTripsAndRefusesShortOrBadBuffers) {
  const RoundFixture f(4);
  const Mesh& mesh = f.graph.mesh();
  const std::string bytes = encodeViewerMesh(mesh, 9);
  uint64_t seq = 0;
  auto decoded = decodeViewerMesh(bytes, &seq);
  ASSERT_TRUE(decoded) << decoded.error();
  EXPECT_EQ(seq, 9u);
  ASSERT_EQ(decoded.value().vertices.size(), mesh.vertices.size());
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    EXPECT_EQ(decoded.value().vertices[i].position, mesh.vertices[i].position);
    EXPECT_EQ(decoded.value().vertices[i].color, mesh.vertices[i].color);
    EXPECT_EQ(decoded.value().vertices[i].label, mesh.vertices[i].label);
    EXPECT_EQ(decoded.value().vertices[i].robot, mesh.vertices[i].robot);
  }
  EXPECT_EQ(decoded.value().faces, mesh.faces);
  EXPECT_FALSE(decodeViewerMesh(bytes.substr(0, bytes.size() - 1)));
  EXPECT_FALSE(decodeViewerMesh(bytes.substr(0, 3)));
  std::string bad = bytes;
  const uint32_t huge = mesh.vertices.size() + 5;
  std::memcpy(bad.data() + bad.size() - 4, &huge, 4);  // the last face's last index
  auto refused = decodeViewerMesh(bad);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().find("names vertex"), std::string::npos) << refused.error();
}

}  // namespace
}  // namespace hydra_multi::web
