// `hydra-multi pgo`: pose-graph optimization of g2o/TORO files, robust or not, with the paper's
// initial alignment for robots of unknown frames, outlier injection and evaluation against labels
// and ground truth.

#include <charconv>
#include <chrono>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>

#include "hydra_multi/apps/commands.h"
#include "hydra_multi/dsg/io/graph_file.h"
#include "hydra_multi/eval/trajectory_error.h"
#include "hydra_multi/optim/chordal_initialization.h"
#include "hydra_multi/optim/io/g2o_format.h"
#include "hydra_multi/optim/multi_robot_alignment.h"
#include "hydra_multi/optim/outlier_injection.h"
#include "hydra_multi/optim/robust_pose_graph.h"

namespace hydra_multi::apps {
namespace {

using Json = nlohmann::ordered_json;
using Poses = std::map<NodeId, Eigen::Isometry3d>;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

bool isLoopClosure(const PoseGraphEdge& e) { return e.kind == PoseGraphEdge::Kind::kLoopClosure; }

// The inlier edge numbers (1-based) of a gt_info.xml file.
Result<std::set<size_t>> readInlierIndices(const std::string& path) {
  auto text = io::readFile(path);
  if (!text) return Error{text.error()};
  std::set<size_t> indices;
  const std::regex tag("<inlier_lc_indices>\\s*(\\d+)\\s*</inlier_lc_indices>");
  const std::string& s = text.value();
  for (auto it = std::sregex_iterator(s.begin(), s.end(), tag); it != std::sregex_iterator();
       ++it) {
    const std::string digits = (*it)[1];
    size_t index = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), index);
    if (ec != std::errc() || end != digits.data() + digits.size())
      return Error{path + ": inlier edge number " + digits + " is too large"};
    indices.insert(index);
  }
  if (indices.empty()) return Error{path + ": no <inlier_lc_indices> entries"};
  return indices;
}

// True poses: the file's vertices, or its edges chained along consecutive ids from the first.
Result<Poses> readGroundTruth(const std::string& path) {
  auto file = io::readG2o(path);
  if (!file) return Error{file.error()};
  PoseGraph truth = file.value().graph;
  if (!truth.poses.empty()) return truth.poses;
  if (truth.edges.empty()) return Error{path + ": no vertices and no edges"};
  classifyEdges(truth);
  NodeId first = truth.edges.front().from;
  for (const PoseGraphEdge& e : truth.edges) first = std::min({first, e.from, e.to});
  return odometryInitialization(truth, first);
}

// ATE of the positions of nodes present in both.
std::optional<double> ate(const Poses& estimate, const Poses& reference) {
  std::vector<Eigen::Vector3d> a, b;
  for (const auto& [id, T] : estimate) {
    if (auto it = reference.find(id); it != reference.end()) {
      a.push_back(T.translation());
      b.push_back(it->second.translation());
    }
  }
  auto error = absoluteTrajectoryError(a, b);
  if (!error) return std::nullopt;
  return error.value().statistics.rmse;
}

struct Alignment {
  Poses poses;
  size_t robots = 0;
  size_t aligned = 0;
  std::vector<RobotPairAlignment> pairs;
};

// --unknown-frames: each file that owns nodes is a robot; its poses come from its own odometry
// from identity, then the frames are aligned by eq. (1)-(2) over the edges between robots.
Alignment alignUnknownFrames(const io::MergedG2o& merged, size_t min_inliers) {
  std::map<size_t, size_t> robot_of_file;  // file -> robot index, in file order
  for (const auto& [id, file] : merged.node_owner) robot_of_file.emplace(file, 0);
  size_t next = 0;
  for (auto& [file, robot] : robot_of_file) robot = next++;
  std::unordered_map<NodeId, size_t> robot_of;
  for (const auto& [id, file] : merged.node_owner) robot_of[id] = robot_of_file.at(file);

  Alignment result;
  result.robots = robot_of_file.size();
  Poses local;
  std::vector<PoseGraphEdge> inter;
  for (size_t r = 0; r < result.robots; ++r) {
    PoseGraph own;
    NodeId first;
    bool any = false;
    for (const auto& [id, robot] : robot_of) {
      if (robot == r && (!any || id < first)) {
        first = id;
        any = true;
      }
    }
    for (const PoseGraphEdge& e : merged.graph.edges) {
      if (robot_of.count(e.from) && robot_of.count(e.to) && robot_of.at(e.from) == r &&
          robot_of.at(e.to) == r) {
        own.edges.push_back(e);
      }
    }
    if (any) {
      for (const auto& [id, T] : spanningInitialization(own, first)) local[id] = T;
    }
  }
  for (const PoseGraphEdge& e : merged.graph.edges) {
    if (isLoopClosure(e) && robot_of.count(e.from) && robot_of.count(e.to) &&
        robot_of.at(e.from) != robot_of.at(e.to)) {
      inter.push_back(e);
    }
  }
  const MultiRobotAlignment alignment =
      alignRobotFrames(result.robots, local, robot_of, inter, 0, [min_inliers] {
        MultiRobotAlignmentOptions options;
        options.min_inliers = min_inliers;
        return options;
      }());
  for (const auto& [id, T] : local) {
    const auto& T_world_robot = alignment.T_world_robot[robot_of.at(id)];
    if (T_world_robot) result.poses[id] = *T_world_robot * T;
  }
  result.aligned = alignment.numAligned();
  result.pairs = alignment.pairs;
  return result;
}

}  // namespace

int runPgo(const PgoOptions& o) {
  const auto progress = [&](const std::string& line) {
    if (!o.quiet) std::cerr << "pgo: " << line << "\n";
  };
  if (o.inputs.empty()) return fail("pgo: give at least one --input");
  if (o.residual != "geodesic" && o.residual != "chordal") {
    return fail("--residual must be geodesic or chordal, not '" + o.residual + "'");
  }
  if (o.init != "odometry" && o.init != "chordal") {
    return fail("--init must be odometry or chordal, not '" + o.init + "'");
  }
  if (o.robust != "none" && o.robust != "gnc") {
    return fail("--robust must be none or gnc, not '" + o.robust + "'");
  }
  if (o.outliers < 0.0 || o.outliers >= 1.0) return fail("--outliers must be in [0, 1)");

  auto merged = io::readAndMergeG2o(o.inputs, {o.skip_bad_lines});
  if (!merged) return fail(merged.error());
  for (const std::string& warning : merged.value().warnings)
    std::cerr << "pgo: skipped " << warning << "\n";
  for (const std::string& note : merged.value().notes) std::cerr << "pgo: " << note << "\n";
  const PoseGraph clean = merged.value().graph;
  if (clean.edges.empty()) return fail("pgo: the input has no edges");
  progress("loaded " + std::to_string(o.inputs.size()) +
           " file(s): " + std::to_string(clean.edges.size()) + " edges (" +
           std::to_string(clean.numLoopClosures()) + " loop closures), " +
           std::to_string(merged.value().duplicate_edges) + " duplicates dropped");

  // Initialization.
  const bool robust = o.robust == "gnc";
  const auto init_start = Clock::now();
  Poses initial;
  Alignment alignment;
  NodeId anchor = clean.edges.front().from;
  for (const PoseGraphEdge& e : clean.edges) anchor = std::min({anchor, e.from, e.to});
  if (o.unknown_frames) {
    alignment = alignUnknownFrames(merged.value(), o.min_inliers);
    initial = alignment.poses;
    if (!initial.empty()) anchor = initial.begin()->first;
    for (const RobotPairAlignment& p : alignment.pairs) {
      progress("robots " + std::to_string(p.robot_a) + "-" + std::to_string(p.robot_b) + ": " +
               std::to_string(p.inliers) + " of " + std::to_string(p.loop_closures) +
               " loop closures agree" + (p.in_tree ? " (in the spanning tree)" : ""));
    }
    progress("aligned " + std::to_string(alignment.aligned) + " of " +
             std::to_string(alignment.robots) + " robots");
  } else if (o.init == "chordal") {
    const EdgeFilter known_inliers = [](const PoseGraphEdge& e) { return !isLoopClosure(e); };
    auto chordal = chordalInitialization(clean, anchor, robust ? known_inliers : EdgeFilter());
    if (!chordal) return fail(chordal.error());
    initial = chordal.value();
  } else {
    initial = odometryInitialization(clean, anchor);
  }
  if (!o.unknown_frames) {
    for (const auto& [id, T] : clean.poses) initial.emplace(id, T);  // nodes the init missed
  }
  const double init_time = secondsSince(init_start);

  // Outliers, after the initialization they must not influence.
  PoseGraph graph = clean;
  const size_t injected = injectOutliers(graph, initial, o.outliers, o.seed);
  if (injected > 0) progress("injected " + std::to_string(injected) + " outlier loop closures");

  // Labels of the loop closures, when known.
  std::optional<std::vector<bool>> truly_inlier;
  if (!o.inliers_xml.empty()) {
    auto indices = readInlierIndices(o.inliers_xml);
    if (!indices) return fail(indices.error());
    const size_t last = *indices.value().rbegin();
    if (*indices.value().begin() == 0 || last > clean.edges.size())
      return fail(o.inliers_xml + ": inlier edge number " +
                  std::to_string(*indices.value().begin() == 0 ? 0 : last) +
                  " is not one of the inputs' edges (1 to " + std::to_string(clean.edges.size()) +
                  ")");
    truly_inlier = std::vector<bool>(graph.edges.size(), false);
    for (size_t k = 0; k < clean.edges.size(); ++k)
      (*truly_inlier)[k] = indices.value().count(k + 1) > 0;
  } else if (!o.inlier_edges.empty()) {
    auto labels = io::readG2o(o.inlier_edges);
    if (!labels) return fail(labels.error());
    std::set<std::pair<NodeId, NodeId>> true_edges;
    for (const PoseGraphEdge& e : labels.value().graph.edges)
      true_edges.insert(std::minmax(e.from, e.to));
    truly_inlier = std::vector<bool>(graph.edges.size(), false);
    std::set<std::pair<NodeId, NodeId>> matched;
    for (size_t k = 0; k < clean.edges.size(); ++k) {
      const auto key = std::minmax(clean.edges[k].from, clean.edges[k].to);
      (*truly_inlier)[k] = true_edges.count(key) > 0;
      if ((*truly_inlier)[k]) matched.insert(key);
    }
    // Labels of edges the inputs do not have label nothing: say so, and refuse a file of no use.
    if (matched.empty())
      return fail(o.inlier_edges + ": none of its " + std::to_string(true_edges.size()) +
                  " edges is an edge of the inputs");
    if (matched.size() < true_edges.size())
      std::cerr << "pgo: " << o.inlier_edges << ": " << true_edges.size() - matched.size()
                << " of its " << true_edges.size() << " edges are no edge of the inputs\n";
  } else if (injected > 0) {
    truly_inlier = std::vector<bool>(graph.edges.size(), false);
    for (size_t k = 0; k < clean.edges.size(); ++k) (*truly_inlier)[k] = true;
  }

  RobustPgoOptions options;
  options.robust = robust;
  options.solver.residual =
      o.residual == "chordal" ? ResidualType::kChordal : ResidualType::kGeodesic;
  options.solver.function_tolerance = o.tolerance;
  options.solver.num_threads = o.threads;
  options.solver.linearization_threads = o.threads;
  options.gnc_inner_iterations = o.gnc_inner_iterations;
  options.reduce_chains = !o.keep_chains;
  if (o.linear_solver == "cg") options.cholesky_mflops_per_pose_limit = 0.0;
  if (o.linear_solver == "cholesky") options.cholesky_mflops_per_pose_limit = 1e300;
  if (!o.quiet)
    options.progress = [](const std::string& line) { std::cerr << "pgo:   " << line << "\n"; };
  progress(std::string("optimizing ") + std::to_string(initial.size()) + " poses, " + o.residual +
           " residual" + (robust ? ", GNC over the loop closures" : ""));
  const RobustPgoResult result = optimizePoseGraph(graph, initial, anchor, options);
  if (!result.usable) return fail("pgo: the solver failed: " + result.message);
  progress("done in " + std::to_string(result.time_s) + " s, " + std::to_string(result.solves) +
           " solve(s), " + std::to_string(result.solver_time.iterations) + " iterations" +
           (robust ? ", GNC stopped: " + result.gnc.stop_reason : ""));

  // Evaluation.
  Json rejected = Json::array();
  size_t loop_closures = 0, predicted = 0, true_positive = 0, positives = 0;
  for (size_t k = 0; k < graph.edges.size(); ++k) {
    if (!isLoopClosure(graph.edges[k])) continue;
    ++loop_closures;
    const bool inlier = result.edge_inlier[k];
    if (!inlier)
      rejected.push_back(Json::array({graph.edges[k].from.value(), graph.edges[k].to.value()}));
    if (truly_inlier) {
      predicted += inlier ? 1 : 0;
      positives += (*truly_inlier)[k] ? 1 : 0;
      true_positive += (inlier && (*truly_inlier)[k]) ? 1 : 0;
    }
  }
  const auto sesync = sesyncCost(clean.edges, result.poses);
  std::optional<double> ate_m, ate_vs_clean_m;
  if (!o.groundtruth.empty()) {
    auto truth = readGroundTruth(o.groundtruth);
    if (!truth) return fail(truth.error());
    ate_m = ate(result.poses, truth.value());
    if (!ate_m) return fail(o.groundtruth + ": no common poses to align (need 3 or more)");
  }
  if (injected > 0) {
    RobustPgoOptions reference = options;
    reference.robust = false;
    ate_vs_clean_m = ate(result.poses, optimizePoseGraph(clean, initial, anchor, reference).poses);
  }
  if (!o.output.empty()) {
    PoseGraph out = clean;
    out.poses = result.poses;
    if (Status status = io::writeFile(o.output, io::writeG2o(out)); !status) {
      return fail(status.message());
    }
  }

  const auto ratio = [](size_t num, size_t den) {
    return den == 0 ? Json(nullptr) : Json(double(num) / double(den));
  };
  const auto optional = [](const std::optional<double>& v) { return v ? Json(*v) : Json(nullptr); };
  const size_t robots = o.unknown_frames ? alignment.robots : 1;
  const size_t robots_aligned = o.unknown_frames ? alignment.aligned : 1;
  Json j;
  j["poses"] = result.poses.size();
  j["edges"] = graph.edges.size();
  j["loop_closures"] = loop_closures;
  j["outliers_injected"] = injected;
  j["robots"] = robots;
  j["robots_aligned"] = robots_aligned;
  j["residual"] = o.residual;
  j["robust"] = o.robust;
  j["cost"] = result.final_cost;
  j["sesync_cost"] = sesync ? Json(sesync.value()) : Json(nullptr);
  j["iterations"] = result.solver_time.iterations;
  j["gnc_iterations"] = result.gnc.iterations;
  j["init_time_s"] = init_time;
  j["time_s"] = result.time_s;
  j["rejected"] = rejected;
  j["inlier_precision"] = truly_inlier ? ratio(true_positive, predicted) : Json(nullptr);
  j["inlier_recall"] = truly_inlier ? ratio(true_positive, positives) : Json(nullptr);
  j["ate_m"] = optional(ate_m);
  j["ate_vs_clean_m"] = optional(ate_vs_clean_m);
  if (o.json) {
    std::cout << j.dump() << "\n";
    return 0;
  }
  std::cout << "poses " << j["poses"] << ", edges " << j["edges"] << ", loop closures "
            << loop_closures << " (" << injected << " injected outliers)\n"
            << "robots " << robots_aligned << " of " << robots << " aligned\n"
            << "cost " << j["cost"]
            << "; SE-Sync cost over every input edge, rejected ones included: " << j["sesync_cost"]
            << "\n"
            << "iterations " << j["iterations"] << ", init " << init_time << " s, solve "
            << result.time_s << " s\n"
            << "rejected " << rejected.size() << " loop closures";
  if (truly_inlier) {
    std::cout << "; inlier precision " << j["inlier_precision"] << ", recall "
              << j["inlier_recall"];
  }
  std::cout << "\n";
  if (ate_m) std::cout << "ATE " << *ate_m << " m\n";
  if (ate_vs_clean_m)
    std::cout << "ATE against the outlier-free solution " << *ate_vs_clean_m << " m\n";
  if (!o.output.empty()) std::cout << "wrote " << o.output << "\n";
  return 0;
}

}  // namespace hydra_multi::apps
