#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>

#include "hydra_multi/dsg/io/graph_file.h"
#include "hydra_multi/optim/io/g2o_format.h"
#include "support/mutations.h"
#include "support/random_graphs.h"

namespace hydra_multi::io {
namespace {

const std::string kData = testing::dataDir();

// Every tag is parsed into the right pose and information entries.
TEST(G2o, ParsesEveryTag) {
  const std::string text =
      "VERTEX_SE3:QUAT 0 1 2 3 0 0 0 1\n"
      "VERTEX_SE3:QUAT 1 4 5 6 0 0 0.70710678118654752 0.70710678118654752\n"
      "EDGE_SE3:QUAT 0 1 1 2 3 0 0 0 1 1001 2 3 4 5 6 1007 8 9 10 11 1012 13 14 15 1016 17 18 1019 "
      "20 1021\n"
      "VERTEX_SE2 5 1 2 0.5\n"
      "EDGE_SE2 5 6 0.1 0.2 0.3 10 1 2 20 3 30\n"
      "VERTEX3 7 1 2 3 0 0 1.5707963267948966\n"
      "EDGE3 7 8 1 2 3 0 0 0 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1\n"
      "FIX 0\n";
  auto file = parseG2o(text, "test.g2o");
  ASSERT_TRUE(file.ok()) << file.error();
  const PoseGraph& g = file.value().graph;
  EXPECT_EQ(file.value().skipped_lines, 1u);  // FIX
  EXPECT_EQ(file.value().skipped_tags, (std::map<std::string, size_t>{{"FIX", 1}}));
  ASSERT_EQ(file.value().warnings.size(), 1u);
  EXPECT_EQ(file.value().warnings[0],
            "test.g2o: 1 of 8 lines not read, their tags unknown to this reader (FIX 1), first at "
            "line 8");
  ASSERT_EQ(g.poses.size(), 4u);
  EXPECT_EQ(g.poses.at(NodeId(0, 0)).translation(), Eigen::Vector3d(1, 2, 3));
  EXPECT_TRUE(
      g.poses.at(NodeId(0, 1))
          .linear()
          .isApprox(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix()));
  ASSERT_EQ(g.edges.size(), 3u);
  EXPECT_EQ(g.edges[0].T_from_to.translation(), Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(g.edges[0].information(0, 5), 6);
  EXPECT_EQ(g.edges[0].information(5, 0), 6);
  EXPECT_EQ(g.edges[0].information(1, 1), 1007);
  EXPECT_EQ(g.edges[0].information(5, 5), 1021);
  // SE(2) lifted: x, y, yaw information in place, z/roll/pitch get the largest 2D entry.
  const Matrix6d& info2 = g.edges[1].information;
  EXPECT_EQ(info2(0, 0), 10);
  EXPECT_EQ(info2(0, 1), 1);
  EXPECT_EQ(info2(0, 5), 2);
  EXPECT_EQ(info2(1, 5), 3);
  EXPECT_EQ(info2(5, 5), 30);
  EXPECT_EQ(info2(2, 2), 30);
  EXPECT_EQ(g.edges[1].T_from_to.translation(), Eigen::Vector3d(0.1, 0.2, 0));
  EXPECT_NEAR(Eigen::AngleAxisd(g.edges[1].T_from_to.linear()).angle(), 0.3, 1e-12);
  EXPECT_TRUE(
      g.poses.at(NodeId(0, 7))
          .linear()
          .isApprox(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix()));
  EXPECT_EQ(g.edges[2].T_from_to.translation(), Eigen::Vector3d(1, 2, 3));
}

// A malformed line names file and line; --skip-bad-lines reports and goes on.
TEST(G2o, BadLinesNameFileAndLine) {
  const std::string text =
      "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nEDGE_SE3:QUAT 0 1 1 x 3\n"
      "VERTEX_SE3:QUAT 1 0 0 nan 0 0 0 1\nVERTEX_SE3:QUAT 2 0 0 0 0 0 0 1 9\n";
  auto strict = parseG2o(text, "bad.g2o");
  ASSERT_FALSE(strict.ok());
  EXPECT_EQ(strict.error(), "bad.g2o:2: 'x' is not a number (y)");
  auto lenient = parseG2o(text, "bad.g2o", {true});
  ASSERT_TRUE(lenient.ok());
  ASSERT_EQ(lenient.value().warnings.size(), 3u);
  EXPECT_EQ(lenient.value().warnings[1], "bad.g2o:3: z is not finite");
  EXPECT_EQ(lenient.value().warnings[2], "bad.g2o:4: unexpected extra value '9'");
  EXPECT_EQ(lenient.value().graph.poses.size(), 1u);
  EXPECT_FALSE(parseG2o("VERTEX_SE3:QUAT 0 0 0 0 0 0 0 3\n", "q.g2o").ok());  // not unit
  EXPECT_FALSE(parseG2o("EDGE_SE3:QUAT -1 2 0 0 0 0 0 0 1\n", "id.g2o").ok());
  EXPECT_FALSE(readG2o(kData + "/no/such/file.g2o").ok());
}

// Input that is not what it claims: random bytes, text with no record, an information matrix
// from which no weight can be derived (2D and 3D: a block not positive definite) are refused,
// naming the file (and line).
TEST(G2o, RefusesWhatItCannotUse) {
  std::string bytes = "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\n";
  bytes += std::string("\x17\x00\x8f", 3);
  auto binary = parseG2o(bytes, "r.g2o");
  ASSERT_FALSE(binary.ok());
  EXPECT_EQ(binary.error(), "r.g2o: not a text file (byte 33 is 0): not a g2o or TORO file");
  auto text = parseG2o("hello world\nfoo 1 2\n", "t.g2o");
  ASSERT_FALSE(text.ok());
  EXPECT_EQ(text.error(),
            "t.g2o: no vertex or edge in 2 lines (line 1 starts with 'hello'): not a g2o or TORO "
            "file");
  auto indefinite = parseG2o(
      "EDGE_SE3:QUAT 0 1 0 0 0 0 0 0 1 -5 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1\n", "i.g2o");
  ASSERT_FALSE(indefinite.ok());
  EXPECT_EQ(indefinite.error(),
            "i.g2o:1: the information matrix is not positive definite (smallest eigenvalue -5), "
            "nor is its translation block: no weight can be derived from it");
  auto singular = parseG2o("EDGE_SE2 0 1 1 0 0 1 0 0 1 0 0\n", "s.g2o");
  ASSERT_FALSE(singular.ok());
  EXPECT_NE(singular.error().find("s.g2o:1: the information matrix is not positive definite"),
            std::string::npos)
      << singular.error();
  // With --skip-bad-lines such an edge is left out and named; the rest is read.
  auto lenient = parseG2o(
      "VERTEX_SE2 0 0 0 0\nEDGE_SE2 0 1 1 0 0 1 0 0 1 0 0\nEDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n",
      "s.g2o", {true});
  ASSERT_TRUE(lenient.ok()) << lenient.error();
  EXPECT_EQ(lenient.value().graph.edges.size(), 1u);
  ASSERT_EQ(lenient.value().warnings.size(), 1u);
  EXPECT_EQ(lenient.value().warnings[0].rfind("s.g2o:2: the information matrix", 0), 0u);
}

// Reading never crashes: 3000 seeded mutations of a real benchmark file are each read into
// poses and edges the solver can use (finite; information positive definite, or its translation
// and rotation blocks so, with a note for each such edge) or refused with a message naming the
// file.
TEST(G2o, MutatedFilesAreReadOrRefused) {
  const std::string text = readFile(kData + "/pgo/tinyGrid3D.g2o").value();
  std::mt19937 rng(18);
  size_t read = 0, refused = 0;
  for (int i = 0; i < 3000; ++i) {
    const std::string mutated = testing::mutateBytes(text, rng);
    Result<G2oFile> file = Error{""};
    ASSERT_NO_THROW(file = parseG2o(mutated, "m.g2o"));
    if (!file) {
      ++refused;
      ASSERT_EQ(file.error().rfind("m.g2o", 0), 0u) << file.error();
      continue;
    }
    ++read;
    size_t odd = 0;
    for (const PoseGraphEdge& e : file.value().graph.edges) {
      ASSERT_TRUE(e.T_from_to.matrix().allFinite());
      const Eigen::Matrix3d translation = e.information.topLeftCorner<3, 3>();
      const Eigen::Matrix3d rotation = e.information.bottomRightCorner<3, 3>();
      ASSERT_EQ(translation.llt().info(), Eigen::Success);
      ASSERT_EQ(rotation.llt().info(), Eigen::Success);
      odd += e.information.llt().info() != Eigen::Success;
    }
    ASSERT_EQ(file.value().notes.size(), odd);
    for (const auto& [id, T] : file.value().graph.poses) ASSERT_TRUE(T.matrix().allFinite());
  }
  EXPECT_GT(read, 100u);
  EXPECT_GT(refused, 100u);
}

// Writing and reading back keeps every pose and edge (to 17 digits).
TEST(G2o, WriteReadRoundTrip) {
  auto file = readG2o(kData + "/pgo/smallGrid3D.g2o");
  ASSERT_TRUE(file.ok()) << file.error();
  const PoseGraph& g = file.value().graph;
  auto back = parseG2o(writeG2o(g), "written");
  ASSERT_TRUE(back.ok()) << back.error();
  ASSERT_EQ(back.value().graph.poses.size(), g.poses.size());
  ASSERT_EQ(back.value().graph.edges.size(), g.edges.size());
  for (const auto& [id, T] : g.poses) {
    EXPECT_LT((back.value().graph.poses.at(id).matrix() - T.matrix()).norm(), 1e-12);
  }
  for (size_t k = 0; k < g.edges.size(); ++k) {
    EXPECT_LT((back.value().graph.edges[k].information - g.edges[k].information).norm(), 1e-9);
  }
}

// The real files load with the sizes of data/README.md.
TEST(G2o, ReadsTheRealBenchmarks) {
  struct Expected {
    const char* path;
    size_t poses, edges;
  };
  for (const Expected& e :
       {Expected{"/pgo/sphere2500.g2o", 2500, 4949},
        Expected{"/pgo/parking-garage.g2o", 1661, 6275}, Expected{"/pgo/smallGrid3D.g2o", 125, 297},
        Expected{"/pgo/tinyGrid3D.g2o", 9, 11},
        Expected{"/pgo/sphere2500_groundtruth.txt", 0, 4949},
        Expected{"/pgo/grid1000_10p_outliers/measurements.g2o", 0, 0}}) {
    auto file = readG2o(kData + e.path);
    ASSERT_TRUE(file.ok()) << file.error();
    EXPECT_EQ(file.value().graph.poses.size(), e.poses) << e.path;
    if (e.edges > 0) {
      EXPECT_EQ(file.value().graph.edges.size(), e.edges) << e.path;
    }
  }
  auto csail = readG2o(kData + "/multirobot/csail_2robots/CSAIL_robot2.g2o");
  ASSERT_TRUE(csail.ok()) << csail.error();
  EXPECT_EQ(csail.value().graph.edges.front().from.value(), 523u);
  auto symbols = readG2o(kData + "/multirobot/grid3d_2robots/1.g2o");
  ASSERT_TRUE(symbols.ok()) << symbols.error();
  EXPECT_EQ(symbols.value().graph.poses.begin()->first.category(), 'b');
}

// grid1000's first 999 edges (a spanning tree over non-consecutive ids) are the known inliers.
TEST(PoseGraph, ClassifiesSpanningTreePrefixAsOdometry) {
  auto file = readG2o(kData + "/pgo/grid1000_10p_outliers/measurements.g2o");
  ASSERT_TRUE(file.ok()) << file.error();
  PoseGraph g = file.value().graph;
  classifyEdges(g);
  for (size_t k = 0; k < 999; ++k) {
    ASSERT_EQ(g.edges[k].kind, PoseGraphEdge::Kind::kOdometry) << k;
  }
  EXPECT_EQ(g.edges[999].kind, PoseGraphEdge::Kind::kLoopClosure);
  EXPECT_EQ(g.numLoopClosures(), g.edges.size() - 999);
  EXPECT_EQ(odometryInitialization(g, NodeId(0, 0)).size(), 1000u);
}

}  // namespace
}  // namespace hydra_multi::io
