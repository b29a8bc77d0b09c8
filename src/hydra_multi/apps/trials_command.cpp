// `hydra-multi trials --preset NAME --seeds A-B --out DIR [--methods LIST]`: the paper's
// evaluation in one command. For every seed it simulates the preset (DIR/datasets/NAME-SEED,
// reused when it exists), runs every method on it (DIR/runs/METHOD/seed-SEED, `run`'s outputs,
// reused when metrics.json exists unless --redo), then writes
//   DIR/table.md          Table I (full system and baselines) and Table II (ablations) in form:
//                         mean +- std over the seeds;
//   DIR/objects.svg       objects found and correct per method (Fig. 7 and 8 in form);
//   DIR/places.svg        places position error per method;
//   DIR/rooms.svg         rooms precision and recall per method;
//   DIR/backend_time.svg  backend seconds per round against deformation-graph poses;
//   DIR/trials.json       every run's metrics.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "hydra_multi/apps/commands.h"
#include "hydra_multi/core/result.h"
#include "hydra_multi/eval/trials_report.h"
#include "hydra_multi/sim/dataset_recipe.h"
#include "hydra_multi/station/station_config.h"

namespace hydra_multi::apps {
namespace {

namespace fs = std::filesystem;

// A run's metrics.json (numbers only) and its backend rounds from timing.csv.
Result<TrialRun> readRun(const fs::path& dir, const std::string& method, uint64_t seed) {
  TrialRun run;
  run.method = method;
  run.seed = seed;
  std::ifstream metrics(dir / "metrics.json");
  const nlohmann::json json = nlohmann::json::parse(metrics, nullptr, false);
  if (json.is_discarded() || !json.is_object())
    return Error{(dir / "metrics.json").string() + ": not a JSON object"};
  for (const auto& [key, value] : json.items()) {
    if (value.is_number()) run.metrics[key] = value.get<double>();
  }
  std::ifstream timing(dir / "timing.csv");
  std::string line;
  std::getline(timing, line);  // header
  size_t number = 1;
  while (std::getline(timing, line)) {
    ++number;
    if (line.rfind("backend,", 0) != 0) continue;
    std::vector<std::string> cells;
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) cells.push_back(cell);
    char* end_poses = nullptr;
    char* end_ms = nullptr;
    const double poses = cells.size() >= 10 ? std::strtod(cells[9].c_str(), &end_poses) : 0.0;
    const double ms = cells.size() >= 10 ? std::strtod(cells[5].c_str(), &end_ms) : 0.0;
    if (cells.size() < 10 || cells[5].empty() || cells[9].empty() || *end_poses != '\0' ||
        *end_ms != '\0' || !std::isfinite(poses) || !std::isfinite(ms))
      return Error{(dir / "timing.csv").string() + ":" + std::to_string(number) +
                   ": not a backend row of run's timing.csv (use --redo)"};
    run.rounds.push_back({poses, ms / 1e3});
  }
  return run;
}

using Json = nlohmann::ordered_json;  // keys in the order they were written, for firstDifference

// Where two JSON documents first differ: "parameters/mapper/detection/confusion_probability 0.1,
// not 0.0" (the recorded value, then the wanted one).
std::string firstDifference(const Json& recorded, const Json& wanted) {
  const Json patch = Json::diff(recorded, wanted);
  if (patch.empty()) return "";
  const Json::json_pointer at(patch.front().at("path").get<std::string>());
  const auto value = [&at](const Json& j) {
    return j.contains(at) ? j.at(at).dump() : std::string("nothing");
  };
  return at.to_string().substr(1) + " " + value(recorded) + ", not " + value(wanted);
}

Json parseOrNull(const std::string& text) {
  const Json j = Json::parse(text, nullptr, false);
  return j.is_discarded() ? Json(nullptr) : j;
}

// A dataset is reused only when dataset.json records the recipe asked for.
Status checkDatasetReuse(const fs::path& dataset, const std::string& wanted) {
  auto recorded = sim::readDatasetRecipe(dataset.string());
  if (!recorded) return Error{recorded.error() + "; use another --out"};
  if (recorded.value() == wanted) return Status::Ok();
  return Error{(dataset / "dataset.json").string() + " was simulated with " +
               firstDifference(parseOrNull(recorded.value()), parseOrNull(wanted)) +
               "; use another --out"};
}

// A run is reused only when its inputs.json records the method, configuration and dataset
// recipe asked for.
Status checkRunReuse(const fs::path& dir, const std::string& wanted,
                     const std::string& config_path) {
  std::ifstream in(dir / "inputs.json");
  const Json recorded = in ? Json::parse(in, nullptr, false) : Json(nullptr);
  if (!recorded.is_object())
    return Error{dir.string() +
                 " holds a run that does not record what it was made from (no inputs.json: an "
                 "earlier version); use --redo or another --out"};
  const Json asked = parseOrNull(wanted);
  if (recorded.value("config", Json()) != asked.at("config"))
    return Error{dir.string() + " was run with the configuration " +
                 recorded.value("config", Json()).dump() + ", not " + asked.at("config").dump() +
                 (config_path.empty() ? "" : " (" + config_path + ")") +
                 "; use --redo or another --out"};
  if (recorded != asked)
    return Error{dir.string() + " was made from other inputs: " + firstDifference(recorded, asked) +
                 "; use --redo or another --out"};
  return Status::Ok();
}

std::string show(const TrialRun& run, const std::string& key, int decimals) {
  const auto it = run.metrics.find(key);
  if (it == run.metrics.end()) return "n/a";
  std::ostringstream s;
  s << std::fixed << std::setprecision(decimals) << it->second;
  return s.str();
}

}  // namespace

int runTrials(const TrialsOptions& o) {
  if (o.last_seed < o.first_seed) return fail("--seeds: the last seed is below the first");
  for (const std::string& method : o.methods) {
    if (std::find(trialMethods().begin(), trialMethods().end(), method) == trialMethods().end())
      return fail("--methods: unknown method " + method);
  }
  const fs::path out(o.out);
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) return fail("cannot create " + o.out + ": " + ec.message());
  const auto config = canonicalStationConfig(o.config);
  if (!config) return fail(config.error());
  const size_t total = (o.last_seed - o.first_seed + 1) * o.methods.size();
  size_t done = 0;
  std::vector<TrialRun> runs;
  // By count: a last seed of 2^64 - 1 must not wrap the loop around.
  for (uint64_t k = 0; k <= o.last_seed - o.first_seed; ++k) {
    const uint64_t seed = o.first_seed + k;
    const fs::path dataset = out / "datasets" / (o.preset + "-" + std::to_string(seed));
    SimulateOptions simulate;
    simulate.preset = o.preset;
    simulate.seed = seed;
    simulate.out = dataset.string();
    simulate.quiet = true;
    simulate.label_confusion = o.label_confusion;
    const auto recipe = simulateRecipe(simulate);
    if (!recipe) return fail(recipe.error());
    if (fs::exists(dataset / "dataset.json")) {
      // A dataset is reused: it must be the one asked for.
      if (Status s = checkDatasetReuse(dataset, recipe.value()); !s) return fail(s.message());
    } else {
      std::cerr << "trials: simulating " << o.preset << " seed " << seed << std::endl;
      std::ostringstream discard;
      std::streambuf* old = std::cout.rdbuf(discard.rdbuf());
      const int code = runSimulate(simulate);
      std::cout.rdbuf(old);
      if (code != 0) return fail("simulating " + o.preset + " seed " + std::to_string(seed));
    }
    for (const std::string& method : o.methods) {
      const fs::path dir = out / "runs" / method / ("seed-" + std::to_string(seed));
      ++done;
      const bool reuse = !o.redo && fs::exists(dir / "metrics.json");
      if (reuse) {
        const std::string wanted = runInputs(recipe.value(), method, config.value());
        if (Status s = checkRunReuse(dir, wanted, o.config); !s) return fail(s.message());
      }
      if (!reuse) {
        RunOptions run;
        run.dataset = dataset.string();
        run.out = dir.string();
        run.speed = o.speed;
        run.config = o.config;
        run.quiet = true;
        run.print_summary = false;
        run.bandwidth = false;  // seconds per run that no table uses
        run.viewer = false;     // likewise
        if (method == "full" || method == "no-ia" || method == "no-rec")
          run.ablation = method;
        else
          run.baseline = method;
        if (runRun(run) != 0)
          return fail("run " + method + " on " + o.preset + " seed " + std::to_string(seed));
      }
      auto result = readRun(dir, method, seed);
      if (!result) return fail(result.error());
      const TrialRun& r = result.value();
      std::cerr << "[" << done << "/" << total << "] " << o.preset << " seed " << seed << " "
                << method << (reuse ? " (reused)" : "") << ": ATE " << show(r, "ate_rmse_m", 2)
                << " m, objects found " << show(r, "objects_found_pct", 1) << " % correct "
                << show(r, "objects_correct_pct", 1) << " %, rooms P "
                << show(r, "rooms_precision", 2) << " R " << show(r, "rooms_recall", 2)
                << ", aligned " << show(r, "robots_aligned", 0) << "/" << show(r, "robots", 0)
                << ", " << show(r, "wall_s", 1) << " s" << std::endl;
      runs.push_back(std::move(result.value()));
    }
  }

  // Table I: the system against the baselines; Table II: the ablations.
  const auto present = [&](const std::vector<std::string>& wanted) {
    std::vector<std::string> methods;
    for (const std::string& m : wanted) {
      if (std::find(o.methods.begin(), o.methods.end(), m) != o.methods.end()) methods.push_back(m);
    }
    return methods;
  };
  const std::vector<std::string> table1 = present({"full", "gt-align", "hm-align", "oracle-lc"});
  const std::vector<std::string> table2 = present({"full", "no-rec", "no-ia"});
  const std::vector<TableColumn> accuracy = {{"objects_found_pct", "objects found %", 1},
                                             {"objects_correct_pct", "objects correct %", 1},
                                             {"places_position_error_m", "places error m", 3},
                                             {"rooms_precision", "rooms precision", 2},
                                             {"rooms_recall", "rooms recall", 2},
                                             {"ate_rmse_m", "ATE m", 3}};
  std::vector<TableColumn> system = accuracy;
  system.push_back({"robots_aligned", "robots aligned", 1});
  system.push_back({"lc_inter_precision", "LC precision", 2});
  system.push_back({"backend_ms_max", "backend max ms", 0});
  system.push_back({"wall_s", "wall s", 1});
  const std::vector<std::string> all_methods =
      present({"full", "gt-align", "hm-align", "oracle-lc", "no-rec", "no-ia"});
  std::ostringstream table;
  table << "# Trials: " << o.preset << ", seeds " << o.first_seed << "-" << o.last_seed << "\n\n"
        << "Mean ± standard deviation over the seeds (`hydra-multi trials`). Objects and rooms as "
           "`evaluate` scores them; baselines and oracle read ground truth (evaluation only).\n\n"
        << "## Table I: the system and the baselines\n\n"
        << markdownTable(runs, table1, system) << "\n## Table II: ablations\n\n"
        << markdownTable(runs, table2, accuracy)
        << "\n## Objects by verdict\n\n"
           "Counts per run (`evaluate --objects` lists them). The paper's objects correct % counts "
           "a duplicate (a second object on a true object already matched) as correct, so merging "
           "duplicates lowers it while wrong objects stay.\n\n"
        << markdownTable(runs, all_methods,
                         {{"num_objects", "objects", 1},
                          {"objects_correct", "correct", 1},
                          {"objects_duplicates", "of them duplicates", 1},
                          {"objects_wrong_label", "wrong label", 1},
                          {"objects_misplaced", "misplaced", 1}});
  std::ofstream(out / "table.md") << table.str();
  std::vector<std::string> all = o.methods;
  const std::string name =
      o.preset + ", seeds " + std::to_string(o.first_seed) + "-" + std::to_string(o.last_seed);
  std::ofstream(out / "objects.svg") << barChartSvg(
      "Objects (" + name + ")", runs, all,
      {{"objects_found_pct", "found", 1}, {"objects_correct_pct", "correct", 1}}, "%");
  std::ofstream(out / "places.svg") << barChartSvg(
      "Places (" + name + ")", runs, all, {{"places_position_error_m", "position error", 3}}, "m");
  std::ofstream(out / "rooms.svg")
      << barChartSvg("Rooms (" + name + ")", runs, all,
                     {{"rooms_precision", "precision", 2}, {"rooms_recall", "recall", 2}}, "");
  std::ofstream(out / "backend_time.svg") << backendTimeSvg(runs, all);
  nlohmann::json json = nlohmann::json::array();
  for (const TrialRun& r : runs)
    json.push_back({{"method", r.method}, {"seed", r.seed}, {"metrics", r.metrics}});
  std::ofstream(out / "trials.json") << json.dump(1) << "\n";
  std::cout << table.str() << "\noutputs in " << o.out
            << ": table.md, objects.svg, places.svg, rooms.svg, backend_time.svg, trials.json, "
               "runs/METHOD/seed-N/, datasets/\n";
  return 0;
}

const std::vector<std::string>& trialMethods() {
  static const std::vector<std::string> methods = {"full",   "gt-align", "hm-align",
                                                   "no-rec", "no-ia",    "oracle-lc"};
  return methods;
}

}  // namespace hydra_multi::apps
