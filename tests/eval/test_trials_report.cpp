// The trials report: mean and sample standard deviation per method, the markdown table, and SVG
// charts with one bar per method and metric and one point per backend round.

#include <gtest/gtest.h>

#include "hydra_multi/eval/trials_report.h"

namespace hydra_multi {
namespace {

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

std::vector<TrialRun> runs() {
  std::vector<TrialRun> runs;
  for (const double v : {80.0, 90.0, 100.0})
    runs.push_back({"full", 1, {{"objects_found_pct", v}, {"ate_rmse_m", v / 100}}, {{100, 0.5}}});
  runs.push_back({"gt-align", 1, {{"objects_found_pct", 70.0}}, {{50, 0.1}, {200, 0.4}}});
  return runs;
}

TEST(TrialsReport, MeanAndSampleStandardDeviation) {
  const auto full = summarize(runs(), "full", "objects_found_pct");
  ASSERT_TRUE(full);
  EXPECT_DOUBLE_EQ(full->mean, 90.0);
  EXPECT_DOUBLE_EQ(full->std, 10.0);  // sqrt((100 + 0 + 100) / 2)
  EXPECT_EQ(full->count, 3u);
  const auto one = summarize(runs(), "gt-align", "objects_found_pct");
  EXPECT_DOUBLE_EQ(one->std, 0.0);
  EXPECT_FALSE(summarize(runs(), "gt-align", "ate_rmse_m"));
  EXPECT_FALSE(summarize(runs(), "no-ia", "objects_found_pct"));
}

TEST(TrialsReport, MarkdownTable) {
  const std::string table =
      markdownTable(runs(), {"full", "gt-align"},
                    {{"objects_found_pct", "objects found %", 1}, {"ate_rmse_m", "ATE m", 2}});
  EXPECT_NE(table.find("| method | objects found % | ATE m | runs |"), std::string::npos);
  EXPECT_NE(table.find("| full | 90.0 ± 10.0 | 0.90 ± 0.10 | 3 |"), std::string::npos) << table;
  EXPECT_NE(table.find("| gt-align | 70.0 ± 0.0 | n/a | 1 |"), std::string::npos) << table;
}

TEST(TrialsReport, Charts) {
  const std::string bars =
      barChartSvg("Objects <test>", runs(), {"full", "gt-align"},
                  {{"objects_found_pct", "found", 1}, {"ate_rmse_m", "ATE", 2}}, "%");
  EXPECT_EQ(bars.rfind("<svg", 0), 0u);
  EXPECT_NE(bars.find("</svg>"), std::string::npos);
  EXPECT_EQ(count(bars, "class=\"bar\""), 3u);  // gt-align has no ATE
  EXPECT_NE(bars.find("<title>full found: 90.0 ± 10.0</title>"), std::string::npos);
  EXPECT_NE(bars.find("Objects &lt;test&gt;"), std::string::npos);
  const std::string points = backendTimeSvg(runs(), {"full", "gt-align"});
  EXPECT_EQ(count(points, "class=\"point\""), 5u);
}

}  // namespace
}  // namespace hydra_multi
