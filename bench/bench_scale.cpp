// The station at team scale (issue 22): for each run folder of `run` (metrics.json, timing.csv),
// the final graph's size, the backend's time per round (median, max while the robots mapped; the
// last round, from scratch on the final state once they are done, apart) and per stage (the last
// round's, and each stage's share of all rounds; and so for the time in its pose-graph solves,
// their factorizations and analyses), the frontend's time per update, the peak memory (and
// per robot) and the accuracy; and a plot of the rounds' backend time against the deformation
// graph's poses (the slowest round per 500 poses while the robots mapped, and the last round), one
// colour per team; then which of issue 22's targets the teams that have one meet (a team known by
// the dataset in its run's inputs.json: office-3 seed 1, 10 robots at scale 2, 20 at scale 3): the
// targets of online rounds on the rounds while the robots mapped, the last round shown beside
// them. Build in Release (`make bench-scale` runs the teams first).
//
//   bench_scale OUT.svg LABEL=RUN_DIR [LABEL=RUN_DIR ...]

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "hydra_multi/eval/trials_report.h"

using namespace hydra_multi;

namespace {

struct Round {
  double ms = 0, poses = 0, factors = 0, nodes = 0;
  std::vector<double> stages_ms;  // alignment, build, gnc, whole graph, graph, rooms
  bool from_scratch = false;      // the last round, on the final state
  std::vector<double> solver_ms;  // the solves, their factorizations, analyses (if recorded)
};

struct Team {
  std::string label;
  nlohmann::json metrics;
  nlohmann::json dataset;  // inputs.json's "dataset": preset, seed, robots, scale
  std::vector<Round> rounds;
  std::vector<double> frontend_ms;
};

const std::vector<std::string> kStages = {"alignment",   "proposals+assembly", "GNC",
                                          "whole graph", "backend graph",      "rooms"};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

bool readTeam(const std::string& label, const std::string& dir, Team& team, std::string& error) {
  team.label = label;
  std::ifstream metrics(dir + "/metrics.json");
  team.metrics = nlohmann::json::parse(metrics, nullptr, false);
  if (team.metrics.is_discarded() || !team.metrics.is_object()) {
    error = dir + "/metrics.json: not a JSON object (did the run finish?)";
    return false;
  }
  std::ifstream inputs(dir + "/inputs.json");
  const nlohmann::json run = nlohmann::json::parse(inputs, nullptr, false);
  if (!run.is_discarded() && run.is_object() && run.contains("dataset"))
    team.dataset = run["dataset"];
  std::ifstream timing(dir + "/timing.csv");
  std::string line;
  std::getline(timing, line);
  while (std::getline(timing, line)) {
    std::vector<std::string> cells;
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) cells.push_back(cell);
    if (cells.size() >= 6 && cells[0] == "update") team.frontend_ms.push_back(std::stod(cells[5]));
    if (cells.size() >= 17 && cells[0] == "backend") {
      Round r;
      r.ms = std::stod(cells[5]);
      r.nodes = std::stod(cells[8]);
      r.poses = std::stod(cells[9]);
      r.factors = std::stod(cells[10]);
      for (size_t k = 11; k < 17; ++k) r.stages_ms.push_back(std::stod(cells[k]));
      r.from_scratch = cells.size() >= 18 && cells[17] == "1";
      for (size_t k = 20; k < 23 && cells.size() >= 23; ++k)
        r.solver_ms.push_back(std::stod(cells[k]));
      team.rounds.push_back(r);
    }
  }
  if (team.rounds.empty()) {
    error = dir + "/timing.csv: no backend round with its stages (a run of an older build?)";
    return false;
  }
  return true;
}

double number(const nlohmann::json& j, const char* key) {
  return j.contains(key) && j[key].is_number() ? j[key].get<double>() : std::nan("");
}

// The robots' speed the run was made at (`run --speed`; runs of older builds do not say).
std::string speedOf(const Team& t) {
  const double speed = number(t.metrics, "speed");
  if (std::isnan(speed)) return "-";
  if (speed <= 0) return "as fast as possible";
  char text[32];
  std::snprintf(text, sizeof(text), "%gx real time", speed);
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: bench_scale OUT.svg LABEL=RUN_DIR [LABEL=RUN_DIR ...]\n");
    return 2;
  }
  std::vector<Team> teams;
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    const size_t eq = arg.find('=');
    if (eq == std::string::npos) {
      std::fprintf(stderr, "bench_scale: '%s' is not LABEL=RUN_DIR\n", arg.c_str());
      return 2;
    }
    Team team;
    std::string error;
    if (!readTeam(arg.substr(0, eq), arg.substr(eq + 1), team, error)) {
      std::fprintf(stderr, "bench_scale: %s\n", error.c_str());
      return 1;
    }
    teams.push_back(std::move(team));
  }
  std::printf(
      "| team | run speed | robots aligned | final poses / factors / nodes | backend rounds | "
      "round median / max (s) | last round, from scratch (s) | frontend per update median / max "
      "(ms) | peak memory (MB), per robot | ATE (m) | objects found (%%) |\n"
      "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
  for (const Team& t : teams) {
    // The rounds while the robots mapped; the last, from scratch, apart.
    std::vector<double> ms;
    for (const Round& r : t.rounds) {
      if (!r.from_scratch || t.rounds.size() == 1) ms.push_back(r.ms);
    }
    const Round& last = t.rounds.back();
    char last_s[32] = "-";
    if (last.from_scratch) std::snprintf(last_s, sizeof(last_s), "%.2f", last.ms / 1e3);
    std::printf(
        "| %s | %s | %.0f of %.0f | %.0f / %.0f / %.0f | %zu | %.2f / %.2f | %s | %.1f / %.1f | "
        "%.0f, %.0f | %.3f | %.1f |\n",
        t.label.c_str(), speedOf(t).c_str(), number(t.metrics, "robots_aligned"),
        number(t.metrics, "robots"), last.poses, last.factors, last.nodes, t.rounds.size(),
        median(ms) / 1e3, *std::max_element(ms.begin(), ms.end()) / 1e3, last_s,
        median(t.frontend_ms),
        t.frontend_ms.empty() ? 0.0 : *std::max_element(t.frontend_ms.begin(), t.frontend_ms.end()),
        number(t.metrics, "peak_memory_mb"),
        number(t.metrics, "peak_memory_mb") / std::max(1.0, number(t.metrics, "robots")),
        number(t.metrics, "ate_rmse_m"), number(t.metrics, "objects_found_pct"));
  }
  std::printf(
      "\nWhere the backend's time went: the last round's stages in s, and (in brackets) each "
      "stage's share of all rounds' time\n\n| team |");
  for (const std::string& s : kStages) std::printf(" %s |", s.c_str());
  std::printf("\n| --- |");
  for (size_t k = 0; k < kStages.size(); ++k) std::printf(" --- |");
  std::printf("\n");
  // A team's row: per column of `of` (a round's times in ms, `columns` of them; a round that
  // lacks them, from an older build: "-"), the last round's in s and its share of all rounds'.
  const auto shareRow = [](const Team& t, size_t columns, const std::vector<double> Round::*of) {
    std::vector<double> total(columns, 0.0);
    double all = 0.0;
    bool recorded = true;
    for (const Round& r : t.rounds) {
      recorded = recorded && (r.*of).size() == columns;
      for (size_t k = 0; k < (r.*of).size() && k < columns; ++k) total[k] += (r.*of)[k];
      all += r.ms;
    }
    std::printf("| %s |", t.label.c_str());
    for (size_t k = 0; k < columns; ++k) {
      if (recorded) {
        std::printf(" %.2f (%.0f %%) |", (t.rounds.back().*of)[k] / 1e3,
                    all > 0 ? 100.0 * total[k] / all : 0.0);
      } else {
        std::printf(" - |");
      }
    }
    std::printf("\n");
  };
  for (const Team& t : teams) shareRow(t, kStages.size(), &Round::stages_ms);
  // The solves within those stages (timing.csv's solve_ms, factorization_ms, analysis_ms; runs of
  // older builds lack them).
  std::printf(
      "\nThe rounds' pose-graph solves: the last round's in s, and (in brackets) the share of all "
      "rounds' time\n\n| team | Levenberg-Marquardt | of it factorizations | analyses |\n| --- | "
      "--- | --- | --- |\n");
  for (const Team& t : teams) shareRow(t, 3, &Round::solver_ms);
  // Issue 22's targets, for the teams that have one (by the dataset in the run's inputs.json): the
  // targets of online rounds on the rounds while the robots mapped; the last round, from scratch
  // once they are done (docs/DECISIONS.md "The station's last round starts from scratch"), beside
  // them.
  std::printf(
      "\nIssue 22's targets: the rounds while the robots mapped (the last round, from scratch once "
      "they are done, beside them)\n\n| target | measured | met |\n| --- | --- | --- |\n");
  double frontend_low = INFINITY, frontend_high = 0.0;
  for (const Team& t : teams) {
    const double frontend = median(t.frontend_ms);
    frontend_low = std::min(frontend_low, frontend);
    frontend_high = std::max(frontend_high, frontend);
    const nlohmann::json& d = t.dataset;
    if (!d.is_object()) continue;
    const std::string preset = d.value("preset", "");
    const int seed = d.value("seed", 0), robots = d.value("robots", 0);
    const double scale = d.value("scale", 0.0);
    if (preset != "office-3") continue;
    double last = 0.0;
    std::vector<double> mapping;
    for (const Round& r : t.rounds) {
      if (r.from_scratch) {
        last = r.ms / 1e3;
      } else {
        mapping.push_back(r.ms / 1e3);
      }
    }
    if (mapping.empty()) continue;
    const double worst = *std::max_element(mapping.begin(), mapping.end());
    const std::string at = std::isnan(number(t.metrics, "speed")) ? "" : " at " + speedOf(t);
    if (robots == 3 && scale == 1.0 && seed == 1) {
      const double round_median = median(mapping);
      const char* met = round_median <= 0.2 && worst <= 0.5 ? "yes" : "no";
      std::printf(
          "| office-3 seed 1: round median within 0.2 s, max within 0.5 s | median %.2f s, max "
          "%.2f s in %zu rounds%s; the last round %.2f s | %s |\n",
          round_median, worst, mapping.size(), at.c_str(), last, met);
    }
    const double limit_s = robots == 10 && scale == 2.0   ? 2.0
                           : robots == 20 && scale == 3.0 ? 5.0
                                                          : 0;
    if (limit_s > 0) {
      const auto over = std::count_if(mapping.begin(), mapping.end(),
                                      [limit_s](double s) { return s > limit_s; });
      std::printf(
          "| %s: every round within %.0f s | max %.2f s, %td of %zu rounds over%s; the last round "
          "%.2f s | %s |\n",
          t.label.c_str(), limit_s, worst, over, mapping.size(), at.c_str(), last,
          over == 0 ? "yes" : "no");
    }
    if (robots == 20 && scale == 3.0) {
      const double mb = number(t.metrics, "peak_memory_mb");
      std::printf("| %s: peak memory within 8 GB | %.0f MB | %s |\n", t.label.c_str(), mb,
                  mb <= 8192 ? "yes" : "no");
    }
  }
  if (!teams.empty()) {
    std::printf(
        "| the frontend's median per update within 10 ms, every team | %.1f-%.1f ms | %s |\n",
        frontend_low, frontend_high, frontend_high <= 10.0 ? "yes" : "no");
  }
  // The rounds' time against the graph's size, a colour per team: of the rounds while the robots
  // mapped, the slowest in each stretch of kPlotBinPoses poses (at ten times real time a point per
  // round is thousands of them), and the last round.
  constexpr double kPlotBinPoses = 500;
  std::vector<TrialRun> runs;
  std::vector<std::string> labels;
  for (const Team& t : teams) {
    TrialRun run;
    run.method = t.label;
    if (t.dataset.is_object()) run.seed = t.dataset.value("seed", 0);
    std::map<long, TrialRun::Round> slowest;  // by stretch
    for (const Round& r : t.rounds) {
      const TrialRun::Round point{r.poses, r.ms / 1e3};
      if (r.from_scratch) {
        run.rounds.push_back(point);
        continue;
      }
      const auto [at, first] = slowest.emplace(static_cast<long>(r.poses / kPlotBinPoses), point);
      if (!first && point.seconds > at->second.seconds) at->second = point;
    }
    for (const auto& [stretch, point] : slowest) run.rounds.push_back(point);
    runs.push_back(run);
    labels.push_back(t.label);
  }
  std::ofstream svg(argv[1]);
  svg << backendTimeSvg(runs, labels);
  if (!svg) {
    std::fprintf(stderr, "bench_scale: cannot write %s\n", argv[1]);
    return 1;
  }
  std::printf("\nbackend time against graph size: %s\n", argv[1]);
  return 0;
}
