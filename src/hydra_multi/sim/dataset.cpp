#include "hydra_multi/sim/dataset.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "hydra_multi/dsg/graph_delta.h"
#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/dsg/io/graph_file.h"
#include "hydra_multi/dsg/robot_stream.h"
#include "hydra_multi/sim/dataset_json.h"

namespace hydra_multi::sim {
namespace {

using json = nlohmann::ordered_json;
namespace fs = std::filesystem;

double pathLength(const std::vector<StampedPose>& truth) {
  double length = 0.0;
  for (size_t k = 1; k < truth.size(); ++k)
    length +=
        (truth[k].T_world_body.translation() - truth[k - 1].T_world_body.translation()).norm();
  return length;
}

std::string robotDir(RobotId robot) { return "robots/" + robot.str(); }

}  // namespace

Result<SimulatedDataset> planDataset(const SimulationConfig& config,
                                     const ProgressCallback& progress) {
  const auto say = [&](const std::string& line) {
    if (progress) progress(line);
  };
  SimulatedDataset dataset;
  dataset.config = config;
  if (config.sensors.size() != static_cast<size_t>(config.robots))
    return Error{"simulation: " + std::to_string(config.sensors.size()) + " sensor profiles for " +
                 std::to_string(config.robots) + " robots"};
  auto world = generateBuilding(config.building);
  if (!world) return Error{world.error()};
  say("building: " + std::to_string(world.value().floors.size()) + " floor(s), " +
      std::to_string(world.value().rooms.size()) + " rooms, " +
      std::to_string(world.value().objects.size()) + " objects");
  FreeSpace space = computeFreeSpace(world.value(), config.free_space);
  WorldMesh mesh = generateSurfaces(world.value(), config.surfaces);
  std::vector<TexturedPoint> textures = generateTextures(world.value(), config.textures);
  say("surfaces: " + std::to_string(mesh.vertices.size()) + " mesh vertices, " +
      std::to_string(textures.size()) + " textured points");
  dataset.sensed = std::make_unique<SensedWorld>(std::move(world).value(), std::move(space),
                                                 std::move(mesh), std::move(textures));
  const SensedWorld& sensed = *dataset.sensed;
  auto plans = planTeam(sensed.world, sensed.space, config);
  if (!plans) return Error{plans.error()};
  dataset.plans = plans.value();

  for (int r = 0; r < config.robots; ++r) {
    const RobotPlan& plan = dataset.plans[static_cast<size_t>(r)];
    auto tour = planBuildingTour(sensed.world, sensed.space, plan.start_floor, plan.start,
                                 plan.rooms, config.planner);
    if (!tour)
      return Error{"robot " + RobotId(static_cast<uint8_t>(r)).str() + ": " + tour.error()};
    RobotRun run;
    run.robot = RobotId(static_cast<uint8_t>(r));
    run.sensor = config.sensors[static_cast<size_t>(r)];
    const int64_t start_ns = static_cast<int64_t>(r * config.robot_start_interval_s * 1e9);
    run.truth = sampleTrajectory(tour.value(), start_ns, config.trajectory);
    for (const StampedPose& pose : run.truth) {
      run.floors.push_back(
          sensed.floorOf(pose.T_world_body.translation(), config.trajectory.body_height));
    }
    run.odometry_noise = config.odometry;
    run.odometry_noise.seed = config.odometry.seed * 101 + static_cast<uint64_t>(r);
    run.odometry = simulateOdometry(run.truth, run.odometry_noise);
    std::vector<int> rooms;
    for (size_t k = 0; k < run.truth.size(); ++k)
      rooms.push_back(sensed.roomOf(run.floors[k], run.truth[k].T_world_body.translation()));
    LoopClosureOptions closures = config.loop_closures;
    closures.seed = config.loop_closures.seed * 101 + static_cast<uint64_t>(r);
    run.loop_closures = simulateLoopClosures(sensed.world, run.truth, rooms, closures);
    say("robot " + run.robot.str() + " (" + run.sensor.kind +
        "): " + std::to_string(plan.rooms.size()) + " rooms, " +
        std::to_string(static_cast<int>(pathLength(run.truth))) + " m, " +
        std::to_string(run.truth.size()) + " keyframes");
    dataset.runs.push_back(std::move(run));
  }
  return dataset;
}

void mapDataset(SimulatedDataset& dataset, const ProgressCallback& progress) {
  const auto say = [&](const std::string& line) {
    if (progress) progress(line);
  };
  const SimulationConfig& config = dataset.config;
  const SensedWorld& sensed = *dataset.sensed;
  dataset.streams.clear();
  // The robots map independently: one task each.
  std::vector<std::future<std::vector<RobotUpdate>>> tasks;
  for (const RobotRun& run : dataset.runs) {
    MapperOptions options = config.mapper;
    options.detection.seed = config.mapper.detection.seed * 101 + run.robot.index();
    tasks.push_back(std::async(std::launch::async, [&sensed, &run, options] {
      return emulateRobotMap(sensed, run, options);
    }));
  }
  for (size_t r = 0; r < tasks.size(); ++r) {
    dataset.streams.push_back(tasks[r].get());
    say("robot " + dataset.runs[r].robot.str() + ": mapped, " +
        std::to_string(dataset.streams.back().size()) + " updates");
  }
}

Result<SimulatedDataset> simulateDataset(const SimulationConfig& config,
                                         const ProgressCallback& progress) {
  auto dataset = planDataset(config, progress);
  if (!dataset) return dataset;
  mapDataset(dataset.value(), progress);
  return dataset;
}

Result<std::vector<RobotRunSummary>> summarizeDataset(const SimulatedDataset& dataset) {
  std::vector<RobotRunSummary> summaries;
  for (size_t r = 0; r < dataset.runs.size(); ++r) {
    const RobotRun& run = dataset.runs[r];
    RobotRunSummary s;
    s.robot = run.robot;
    s.sensor = run.sensor.kind;
    s.keyframes = run.truth.size();
    s.path_length_m = pathLength(run.truth);
    if (!run.truth.empty()) {
      const Eigen::Vector3d truth_end =
          (run.truth.front().T_world_body.inverse() * run.truth.back().T_world_body).translation();
      s.final_drift_m = (run.odometry.back().translation() - truth_end).norm();
      s.final_drift_pct = s.path_length_m > 0 ? 100.0 * s.final_drift_m / s.path_length_m : 0.0;
    }
    for (const SimulatedLoopClosure& c : run.loop_closures) {
      ++s.loop_closures;
      if (!c.correct) ++s.wrong_loop_closures;
    }
    SceneGraph graph;
    for (const RobotUpdate& update : dataset.streams[r]) {
      if (Status status = validateRobotUpdate(update); !status) return Error{status.message()};
      if (Status status = applyToRobotGraph(graph, update); !status)
        return Error{"robot " + run.robot.str() + " update " + std::to_string(update.sequence) +
                     ": " + status.message()};
      s.bytes += io::encodeRobotUpdateBinary(update).size();
    }
    s.updates = dataset.streams[r].size();
    s.graph = summarize(graph);
    summaries.push_back(s);
  }
  return summaries;
}

namespace {

json vec(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

json poseJson(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.linear());
  return {{"position", vec(T.translation())},
          {"quaternion_xyzw", json::array({q.x(), q.y(), q.z(), q.w()})}};
}

Status writeText(const fs::path& path, const std::string& text) {
  return io::writeFile(path.string(), text);
}

std::string tumLines(const std::vector<StampedPose>& truth) {
  std::ostringstream out;
  out << "# true keyframe poses, world frame: t x y z qx qy qz qw\n"
      << std::setprecision(9) << std::fixed;
  for (const StampedPose& p : truth) {
    const Eigen::Quaterniond q(p.T_world_body.linear());
    const Eigen::Vector3d t = p.T_world_body.translation();
    out << p.time_ns / 1000000000 << "." << std::setw(9) << std::setfill('0')
        << p.time_ns % 1000000000 << std::setfill(' ') << " " << t.x() << " " << t.y() << " "
        << t.z() << " " << q.x() << " " << q.y() << " " << q.z() << " " << q.w() << "\n";
  }
  return out.str();
}

}  // namespace

Status writeDataset(const SimulatedDataset& dataset, const std::string& dir) {
  const fs::path root(dir);
  std::error_code ec;
  // Into an empty or new folder, or over an earlier dataset (whose robots/ and gt/ go first, so
  // that nothing stale stays); never into a folder of something else.
  if (fs::exists(root, ec) && !fs::is_empty(root, ec)) {
    if (!fs::exists(root / "dataset.json", ec))
      return Error{dir +
                   " holds files but no dataset.json: not overwriting it (choose a new or "
                   "empty folder)"};
    fs::remove_all(root / "robots", ec);
    fs::remove_all(root / "gt", ec);
  }
  fs::create_directories(root / "gt" / "trajectories", ec);
  if (ec) return Error{"cannot create " + (root / "gt").string() + ": " + ec.message()};
  const SimulationConfig& c = dataset.config;
  const SensedWorld& sensed = *dataset.sensed;

  json robots = json::array();
  for (size_t r = 0; r < dataset.runs.size(); ++r) {
    const RobotRun& run = dataset.runs[r];
    fs::create_directories(root / robotDir(run.robot), ec);
    if (ec)
      return Error{"cannot create " + (root / robotDir(run.robot)).string() + ": " + ec.message()};
    std::string bytes;
    for (const RobotUpdate& update : dataset.streams[r])
      bytes += io::encodeRobotUpdateBinary(update);
    const std::string stream = robotDir(run.robot) + "/updates.dsgb";
    if (Status s = writeText(root / stream, bytes); !s) return s;
    robots.push_back({{"robot", run.robot.str()},
                      {"index", run.robot.index()},
                      {"sensor", sensorJson(run.sensor)},
                      {"stream", stream},
                      {"updates", dataset.streams[r].size()},
                      {"bytes", bytes.size()}});
  }
  const json recipe = recipeJson(c);
  json header = {{"format", "hydra-multi-dataset"}, {"version", 1}};
  for (const auto& [key, value] : recipe.items())
    header[key] = key == "robots" ? robots : value;  // the robots with their streams
  header["ground_truth"] = "gt/ (for evaluation only; the station never reads it)";
  if (Status s = writeText(root / "dataset.json", header.dump(2) + "\n"); !s) return s;

  // Ground truth.
  json starts = json::array(), closures = json::array();
  for (const RobotRun& run : dataset.runs) {
    const std::string name = run.robot.str();
    if (Status s = writeText(root / "gt" / "trajectories" / (name + ".tum"), tumLines(run.truth));
        !s)
      return s;
    json start = poseJson(run.truth.front().T_world_body);
    start["robot"] = name;
    start["time_ns"] = run.truth.front().time_ns;
    starts.push_back(start);
    for (const SimulatedLoopClosure& lc : run.loop_closures) {
      const char* kind = lc.kind == SimulatedLoopClosure::Kind::kRevisit    ? "revisit"
                         : lc.kind == SimulatedLoopClosure::Kind::kAliasing ? "aliasing"
                                                                            : "gross_error";
      closures.push_back({{"robot", name},
                          {"from", NodeId(run.robot.prefix(), lc.from).str()},
                          {"to", NodeId(run.robot.prefix(), lc.to).str()},
                          {"correct", lc.correct},
                          {"kind", kind}});
    }
  }
  if (Status s = writeText(root / "gt" / "start_poses.json",
                           json({{"frame", "world"}, {"robots", starts}}).dump(2) + "\n");
      !s)
    return s;
  if (Status s = writeText(root / "gt" / "loop_closures.json",
                           json({{"loop_closures", closures}}).dump(1) + "\n");
      !s)
    return s;

  json objects = json::array();
  for (const ObjectInstance& o : sensed.world.objects) {
    const SemanticClass* cls = sensed.world.findClass(o.label);
    const Eigen::Matrix3d R = o.T_world_object.linear();
    objects.push_back({{"id", o.id},
                       {"label", o.label},
                       {"name", cls ? cls->name : ""},
                       {"room", o.room},
                       {"position", vec(o.T_world_object.translation())},
                       {"size", vec(o.size)},
                       {"yaw", std::atan2(R(1, 0), R(0, 0))}});
  }
  if (Status s = writeText(
          root / "gt" / "objects.json",
          json({{"object_threshold_m", c.object_threshold_m}, {"objects", objects}}).dump(1) +
              "\n");
      !s)
    return s;

  json gvd = json::array();
  const double height = c.mapper.places.height_above_floor;
  for (const Eigen::Vector3d& p : sensed.space.gvdPoints(height)) {
    gvd.push_back(p.x());
    gvd.push_back(p.y());
    gvd.push_back(p.z());
  }
  if (Status s =
          writeText(root / "gt" / "gvd.json",
                    json({{"height_above_floor_m", height}, {"points_xyz", gvd}}).dump() + "\n");
      !s)
    return s;

  json grids = json::array(), rooms = json::array();
  for (const FloorGrid& g : sensed.space.floors) {
    grids.push_back({{"floor", g.floor},
                     {"z", g.z},
                     {"origin", json::array({g.origin.x(), g.origin.y()})},
                     {"resolution", g.resolution},
                     {"width", g.width},
                     {"height", g.height}});
  }
  const auto voxels = sensed.space.roomVoxels(sensed.world.rooms.size());
  for (const Room& room : sensed.world.rooms) {
    json cells = json::array();
    for (const Eigen::Vector3i& v : voxels[static_cast<size_t>(room.id)]) {
      cells.push_back(v.x());
      cells.push_back(v.y());
    }
    rooms.push_back({{"id", room.id},
                     {"kind", roomKindName(room.kind)},
                     {"floor", room.floor},
                     {"layout", room.layout},
                     {"footprint", json::array({room.footprint.min.x(), room.footprint.min.y(),
                                                room.footprint.max.x(), room.footprint.max.y()})},
                     {"cells_xy", cells}});
  }
  return writeText(root / "gt" / "rooms.json",
                   json({{"floors", grids}, {"rooms", rooms}}).dump() + "\n");
}

}  // namespace hydra_multi::sim
