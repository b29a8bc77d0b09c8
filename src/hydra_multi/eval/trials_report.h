#pragma once
// The report of `hydra-multi trials`: runs of several methods over several seeds, summarized as
// the paper does (Table I and II: mean +- standard deviation over seeds) and plotted as SVG
// (Fig. 7 and 8: objects, places and rooms metrics per method; backend time against graph size).

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace hydra_multi {

/// One run: a method on one seed, with its metrics.json values (numbers only; missing or null
/// values are absent) and its backend rounds (graph size, seconds).
struct TrialRun {
  std::string method;
  uint64_t seed = 0;
  std::map<std::string, double> metrics;
  struct Round {
    double poses = 0.0;  ///< of the deformation graph
    double seconds = 0.0;
  };
  std::vector<Round> rounds;
};

/// Mean and sample standard deviation (n - 1; 0 for one value) of a metric over a method's runs
/// that have it.
struct MeanStd {
  double mean = 0.0, std = 0.0;
  size_t count = 0;
};
std::optional<MeanStd> summarize(const std::vector<TrialRun>& runs, const std::string& method,
                                 const std::string& metric);

/// One table column: a metrics.json key, its heading and the decimals shown.
struct TableColumn {
  std::string key, heading;
  int decimals = 2;
};

/// A markdown table: one row per method (in the order given), "mean +- std" per column, "n/a"
/// where no run has the metric; the last column counts the runs.
std::string markdownTable(const std::vector<TrialRun>& runs,
                          const std::vector<std::string>& methods,
                          const std::vector<TableColumn>& columns);

/// A grouped bar chart: for each metric a group of bars, one per method (mean, with a +-std
/// whisker). Every bar is a <rect class="bar"> with a <title> "method metric: mean +- std".
std::string barChartSvg(const std::string& title, const std::vector<TrialRun>& runs,
                        const std::vector<std::string>& methods,
                        const std::vector<TableColumn>& metrics, const std::string& unit);

/// Backend seconds per round against deformation-graph poses, one colour per method; every point
/// is a <circle class="point">.
std::string backendTimeSvg(const std::vector<TrialRun>& runs,
                           const std::vector<std::string>& methods);

}  // namespace hydra_multi
