// `hydra-multi simulate --preset NAME --seed N --out DIR [--robots K] [--scale S]`: generates a
// simulated dataset (sim/dataset.h), writes it, and prints a summary per robot and the dataset's
// difficulty figures (aliasing share, what odometry alone does to the objects).

#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>

#include "hydra_multi/apps/commands.h"
#include "hydra_multi/eval/dataset_evaluation.h"
#include "hydra_multi/sim/dataset.h"
#include "hydra_multi/sim/dataset_recipe.h"

namespace hydra_multi::apps {

namespace {

Result<sim::SimulationConfig> simulationConfig(const SimulateOptions& o) {
  auto config = sim::presetConfig(o.preset, o.seed, o.robots, o.scale);
  if (!config) return Error{config.error()};
  if (o.label_confusion) config.value().mapper.detection.confusion_probability = *o.label_confusion;
  config.value().mapper.snapshot_every = o.snapshot_every;
  config.value().mapper.send_keypoints = !o.no_keypoints;
  config.value().mapper.send_own_loop_closures = !o.no_own_loop_closures;
  return config;
}

}  // namespace

Result<std::string> simulateRecipe(const SimulateOptions& options) {
  auto config = simulationConfig(options);
  if (!config) return Error{config.error()};
  return sim::datasetRecipe(config.value());
}

int runSimulate(const SimulateOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  auto config = simulationConfig(o);
  if (!config) return fail(config.error());
  const auto progress = [&](const std::string& line) {
    if (!o.quiet)
      std::cerr << "[" << std::fixed << std::setprecision(1) << elapsed() << " s] " << line
                << std::endl;
  };
  progress("simulating preset " + o.preset + ", seed " + std::to_string(o.seed) + ", " +
           std::to_string(config.value().robots) + " robots");
  auto dataset = sim::simulateDataset(config.value(), progress);
  if (!dataset) return fail(dataset.error());
  auto summaries = sim::summarizeDataset(dataset.value());
  if (!summaries) return fail("the simulated stream does not replay: " + summaries.error());
  if (Status s = sim::writeDataset(dataset.value(), o.out); !s) return fail(s.message());
  progress("written to " + o.out);

  std::cout << "dataset " << o.out << ": preset " << o.preset << ", seed " << o.seed << ", "
            << dataset.value().sensed->world.rooms.size() << " rooms, "
            << dataset.value().sensed->world.objects.size() << " objects, generated in "
            << std::fixed << std::setprecision(1) << elapsed() << " s\n";
  std::cout << "robot sensor keyframes  path_m drift_m drift_% agents objects places mesh_vertices "
               "loop_closures(wrong) updates bytes\n";
  for (const sim::RobotRunSummary& s : summaries.value()) {
    const auto& n = s.graph.nodes_per_layer;
    std::cout << std::setw(5) << s.robot.str() << " " << std::setw(6) << s.sensor << " "
              << std::setw(9) << s.keyframes << " " << std::setw(7) << std::setprecision(1)
              << s.path_length_m << " " << std::setw(7) << std::setprecision(2) << s.final_drift_m
              << " " << std::setw(7) << std::setprecision(2) << s.final_drift_pct << " "
              << std::setw(6) << n[static_cast<size_t>(Layer::kAgents)] << " " << std::setw(7)
              << n[static_cast<size_t>(Layer::kObjects)] << " " << std::setw(6)
              << n[static_cast<size_t>(Layer::kPlaces)] << " " << std::setw(13)
              << s.graph.mesh_vertices << " " << std::setw(13) << s.loop_closures << "("
              << s.wrong_loop_closures << ") " << std::setw(7) << s.updates << " " << s.bytes
              << "\n";
  }
  // The dataset's difficulty, measured on what was written (evaluation reads the ground truth).
  auto difficulty = measureDatasetDifficulty(o.out);
  if (!difficulty) return fail(difficulty.error());
  const DatasetDifficulty& d = difficulty.value();
  std::cout << std::setprecision(1) << "aliasing: of the " << d.top_pairs
            << " inter-robot keyframe pairs most alike in bag of words (mean similarity "
            << std::setprecision(2) << d.top_similarity_mean << std::setprecision(1) << "), "
            << d.aliased_pct << " % are in different true rooms\n";
  const auto pct = [](const std::optional<double>& v) {
    return v ? std::to_string(static_cast<int>(std::lround(*v))) + " %" : std::string("n/a");
  };
  std::cout << "objects by odometry alone (true start poses, no loop closures): found "
            << pct(d.odometry.objects_found_pct) << ", correct "
            << pct(d.odometry.objects_correct_pct) << "; without drift: found "
            << pct(d.no_drift.objects_found_pct) << ", correct "
            << pct(d.no_drift.objects_correct_pct) << " (threshold " << d.object_threshold_m
            << " m); odometry ATE " << std::setprecision(2) << d.odometry.ate_rmse_m.value_or(0.0)
            << " m\n";
  return 0;
}

}  // namespace hydra_multi::apps
