#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <set>

#include "hydra_multi/optim/io/g2o_format.h"
#include "hydra_multi/optim/robust_pose_graph.h"
#include "support/random_graphs.h"

namespace hydra_multi {
namespace {

struct Classification {
  double precision = 0, recall = 0;
};

// GNC on grid1000 with labelled outliers (gt_info.xml lists the 1-based indices of inlier loop
// closures).
Classification classifyGrid(const std::string& name) {
  const std::string dir = testing::dataDir() + "/pgo/" + name;
  auto file = io::readG2o(dir + "/measurements.g2o");
  EXPECT_TRUE(file.ok()) << file.error();
  PoseGraph g = file.value().graph;
  classifyEdges(g);
  std::ifstream xml(dir + "/gt_info.xml");
  const std::string text((std::istreambuf_iterator<char>(xml)), std::istreambuf_iterator<char>());
  std::set<size_t> inliers;
  const std::regex tag("<inlier_lc_indices>(\\d+)</inlier_lc_indices>");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), tag); it != std::sregex_iterator();
       ++it) {
    inliers.insert(std::stoul((*it)[1]) - 1);
  }
  EXPECT_GT(inliers.size(), 300u);
  const NodeId anchor(0, 0);
  const RobustPgoResult result = optimizePoseGraph(g, odometryInitialization(g, anchor), anchor);
  size_t true_positive = 0, predicted = 0;
  for (size_t k = 0; k < g.edges.size(); ++k) {
    if (g.edges[k].kind != PoseGraphEdge::Kind::kLoopClosure) continue;
    predicted += result.edge_inlier[k] ? 1 : 0;
    true_positive += (result.edge_inlier[k] && inliers.count(k)) ? 1 : 0;
  }
  return {double(true_positive) / double(predicted),
          double(true_positive) / double(inliers.size())};
}

// The bar on real labelled data: precision >= 0.99 and recall >= 0.98.
TEST(RobustPoseGraph, Grid1000With10PercentOutliers) {
  const Classification c = classifyGrid("grid1000_10p_outliers");
  EXPECT_GE(c.precision, 0.99);
  EXPECT_GE(c.recall, 0.98);
}

TEST(RobustPoseGraph, Grid1000With30PercentOutliers) {
  const Classification c = classifyGrid("grid1000_30p_outliers");
  EXPECT_GE(c.precision, 0.99);
  EXPECT_GE(c.recall, 0.98);
}

}  // namespace
}  // namespace hydra_multi
