#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <utility>

#include "hydra_multi/optim/fill_reducing_ordering.h"
#include "hydra_multi/optim/io/g2o_format.h"
#include "support/random_graphs.h"

namespace hydra_multi {
namespace {

// The upper triangle of the pattern of n nodes joined by `edges`: per node, itself and the nodes
// an edge joins it to from before.
std::vector<std::vector<long>> pattern(long n, const std::vector<std::pair<long, long>>& edges) {
  std::vector<std::vector<long>> rows(n);
  for (long c = 0; c < n; ++c) rows[c].push_back(c);
  for (const auto& [a, b] : edges) {
    if (a != b) rows[std::max(a, b)].push_back(std::min(a, b));
  }
  for (auto& column : rows) {
    std::sort(column.begin(), column.end());
    column.erase(std::unique(column.begin(), column.end()), column.end());
  }
  return rows;
}

// A pose graph's pattern, one node per pose.
std::vector<std::vector<long>> posePattern(const std::string& file) {
  auto g2o = io::readG2o(testing::dataDir() + "/pgo/" + file);
  EXPECT_TRUE(g2o.ok()) << g2o.error();
  if (!g2o.ok()) return {};
  std::map<NodeId, long> index;
  for (const auto& [id, pose] : g2o.value().graph.poses)
    index.emplace(id, static_cast<long>(index.size()));
  std::vector<std::pair<long, long>> edges;
  for (const PoseGraphEdge& e : g2o.value().graph.edges)
    edges.emplace_back(index.at(e.from), index.at(e.to));
  return pattern(static_cast<long>(index.size()), edges);
}

// A square lattice of side nodes, each joined to its right and lower neighbour (a mesh's
// control points are such a lattice).
std::vector<std::vector<long>> lattice(long side) {
  std::vector<std::pair<long, long>> edges;
  for (long y = 0; y < side; ++y) {
    for (long x = 0; x < side; ++x) {
      const long v = y * side + x;
      if (x + 1 < side) edges.emplace_back(v, v + 1);
      if (y + 1 < side) edges.emplace_back(v, v + side);
    }
  }
  return pattern(side * side, edges);
}

bool isPermutation(std::vector<long> column, size_t n) {
  std::sort(column.begin(), column.end());
  for (size_t k = 0; k < column.size(); ++k) {
    if (column[k] != static_cast<long>(k)) return false;
  }
  return column.size() == n;
}

// Of AMD and METIS, the ordering kept is the one with fewer flops, whichever wins: METIS on
// torus3D, AMD on parking-garage.
TEST(FillReducingOrdering, KeepsTheMethodWithFewerFlops) {
  for (const std::string file : {"torus3D.g2o", "parking-garage.g2o"}) {
    const std::vector<std::vector<long>> rows = posePattern(file);
    ASSERT_FALSE(rows.empty());
    const auto amd = orderForCholesky(rows, 0, OrderingMethod::kAmd);
    const auto metis = orderForCholesky(rows, 0, OrderingMethod::kMetis);
    const auto both = orderForCholesky(rows, 0);
    ASSERT_TRUE(amd && metis && both);
    ASSERT_NE(amd->flops, metis->flops) << file;
    const auto& fewer = amd->flops < metis->flops ? *amd : *metis;
    EXPECT_EQ(both->method, fewer.method) << file;
    EXPECT_EQ(both->column, fewer.column) << file;
    EXPECT_EQ(both->flops, fewer.flops) << file;
    EXPECT_TRUE(isPermutation(both->column, rows.size())) << file;
  }
  EXPECT_EQ(orderForCholesky(posePattern("torus3D.g2o"), 0)->method, OrderingMethod::kMetis);
  EXPECT_EQ(orderForCholesky(posePattern("parking-garage.g2o"), 0)->method, OrderingMethod::kAmd);
}

// The choice is by flops, not by the factor's nonzeros (CHOLMOD's own rule): on a 52 x 52
// lattice METIS' factor has more nonzeros than AMD's and takes fewer flops.
TEST(FillReducingOrdering, ChoosesByFlopsNotByNonzeros) {
  const std::vector<std::vector<long>> rows = lattice(52);
  const auto amd = orderForCholesky(rows, 0, OrderingMethod::kAmd);
  const auto metis = orderForCholesky(rows, 0, OrderingMethod::kMetis);
  ASSERT_TRUE(amd && metis);
  ASSERT_GT(metis->nonzeros, amd->nonzeros);
  ASSERT_LT(metis->flops, amd->flops);
  const auto both = orderForCholesky(rows, 0);
  ASSERT_TRUE(both);
  EXPECT_EQ(both->method, OrderingMethod::kMetis);
  EXPECT_EQ(both->flops, metis->flops);
}

// Below `both_from` columns only AMD runs, even where METIS would take fewer flops.
TEST(FillReducingOrdering, SmallPatternsTakeAmdAlone) {
  const std::vector<std::vector<long>> rows = lattice(52);
  const auto small = orderForCholesky(rows, rows.size() + 1);
  const auto amd = orderForCholesky(rows, 0, OrderingMethod::kAmd);
  ASSERT_TRUE(small && amd);
  EXPECT_EQ(small->method, OrderingMethod::kAmd);
  EXPECT_EQ(small->column, amd->column);
  EXPECT_TRUE(isPermutation(small->column, rows.size()));
}

}  // namespace
}  // namespace hydra_multi
