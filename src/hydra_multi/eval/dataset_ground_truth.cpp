#include "hydra_multi/eval/dataset_ground_truth.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "hydra_multi/dsg/graph_delta.h"
#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/dsg/io/dataset_files.h"
#include "hydra_multi/dsg/io/graph_file.h"
#include "hydra_multi/dsg/robot_stream.h"
#include "hydra_multi/eval/trajectory_error.h"

namespace hydra_multi {
namespace {

using nlohmann::json;

Result<json> readJson(const std::string& path) {
  auto text = io::readFile(path);
  if (!text) return Error{text.error()};
  json j = json::parse(text.value(), nullptr, false);
  if (j.is_discarded()) return Error{path + ": not valid JSON"};
  return j;
}

Eigen::Vector3d vec3(const json& j) {
  return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}

Eigen::Isometry3d poseOf(const json& j) {
  const json& q = j.at("quaternion_xyzw");
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(q.at(3).get<double>(), q.at(0).get<double>(),
                                  q.at(1).get<double>(), q.at(2).get<double>())
                   .normalized()
                   .toRotationMatrix();
  T.translation() = vec3(j.at("position"));
  return T;
}

Result<RobotId> robotOf(const json& j, const std::string& where) {
  const auto robot = RobotId::parse(j.get<std::string>());
  if (!robot) return Error{where + ": unknown robot '" + j.get<std::string>() + "'"};
  return *robot;
}

// Full TUM poses (trajectory_error.h reads positions only).
Result<DatasetGroundTruth::Trajectory> readTumPoses(const std::string& path) {
  auto text = io::readFile(path);
  if (!text) return Error{text.error()};
  DatasetGroundTruth::Trajectory trajectory;
  std::istringstream in(text.value());
  std::string line;
  size_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::string stamp;
    double v[7];
    fields >> stamp;
    for (double& x : v) fields >> x;
    const size_t dot = stamp.find('.');
    if (!fields || dot == std::string::npos)
      return Error{path + ":" + std::to_string(number) + ": expected t x y z qx qy qz qw"};
    // "seconds.fraction", digits only: exact nanoseconds, as the simulator writes them.
    int64_t seconds = 0, nanoseconds = 0;
    std::string fraction = stamp.substr(dot + 1);
    const bool digits = dot > 0 && fraction.size() <= 9 &&
                        stamp.find_first_not_of("0123456789.") == std::string::npos &&
                        fraction.find('.') == std::string::npos;
    fraction.resize(9, '0');
    const auto whole = std::from_chars(stamp.data(), stamp.data() + dot, seconds);
    const auto part = std::from_chars(fraction.data(), fraction.data() + 9, nanoseconds);
    if (!digits || whole.ec != std::errc() || part.ec != std::errc() ||
        seconds > std::numeric_limits<int64_t>::max() / 1000000000 - 1)
      return Error{path + ":" + std::to_string(number) + ": stamp '" + stamp +
                   "' is not seconds.nanoseconds"};
    trajectory.stamps_ns.push_back(seconds * 1000000000 + nanoseconds);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() << v[0], v[1], v[2];
    T.linear() = Eigen::Quaterniond(v[6], v[3], v[4], v[5]).normalized().toRotationMatrix();
    trajectory.poses.push_back(T);
  }
  return trajectory;
}

}  // namespace

Eigen::Vector2i GroundTruthGrid::cellOf(const Eigen::Vector2d& p) const {
  const Eigen::Vector2d c = (p - origin) / resolution;
  return {static_cast<int>(std::floor(c.x())), static_cast<int>(std::floor(c.y()))};
}

const Eigen::Isometry3d* DatasetGroundTruth::poseAt(RobotId robot, int64_t stamp_ns) const {
  const auto it = trajectories.find(robot);
  if (it == trajectories.end()) return nullptr;
  const auto& stamps = it->second.stamps_ns;
  const auto pos = std::lower_bound(stamps.begin(), stamps.end(), stamp_ns - 1000000);
  if (pos == stamps.end() || std::llabs(*pos - stamp_ns) > 1000000) return nullptr;
  return &it->second.poses[static_cast<size_t>(pos - stamps.begin())];
}

const GroundTruthGrid* DatasetGroundTruth::gridFor(double z) const {
  const GroundTruthGrid* best = nullptr;
  for (const GroundTruthGrid& g : grids) {
    if (g.z <= z - 0.5 && (best == nullptr || g.z > best->z)) best = &g;
  }
  if (best == nullptr && !grids.empty()) best = &grids.front();
  return best;
}

Eigen::Isometry3d DatasetGroundTruth::worldFromGlobal(std::optional<RobotId> robot) const {
  if (!robot && robots.empty()) return Eigen::Isometry3d::Identity();
  const auto it = start_poses.find(robot ? *robot : robots.front());
  return it == start_poses.end() ? Eigen::Isometry3d::Identity() : it->second;
}

Result<DatasetGroundTruth> readDatasetGroundTruth(const std::string& dir) {
  namespace fs = std::filesystem;
  DatasetGroundTruth gt;
  gt.dir = dir;
  const std::string header_path = (fs::path(dir) / "dataset.json").string();
  std::string where;
  try {
    where = header_path;
    auto header = readJson(header_path);
    if (!header) return Error{header.error() + " (is " + dir + " a dataset written by simulate?)"};
    const json& h = header.value();
    if (h.value("format", "") != "hydra-multi-dataset")
      return Error{header_path + ": not a hydra-multi dataset (format field)"};
    gt.object_threshold_m = h.at("object_threshold_m").get<double>();
    auto manifest = io::readDatasetManifest(dir);
    if (!manifest) return Error{manifest.error()};
    for (const io::DatasetRobot& r : manifest.value().robots) {
      gt.robots.push_back(r.robot);
      gt.streams[r.robot] = r.stream;
    }
    const fs::path g = fs::path(dir) / "gt";
    where = (g / "start_poses.json").string();
    auto starts = readJson(where);
    if (!starts) return Error{starts.error()};
    for (const json& s : starts.value().at("robots")) {
      auto robot = robotOf(s.at("robot"), where);
      if (!robot) return Error{robot.error()};
      gt.start_poses[robot.value()] = poseOf(s);
    }
    for (const RobotId robot : gt.robots) {
      auto trajectory = readTumPoses((g / "trajectories" / (robot.str() + ".tum")).string());
      if (!trajectory) return Error{trajectory.error()};
      gt.trajectories[robot] = std::move(trajectory).value();
    }
    where = (g / "objects.json").string();
    auto objects = readJson(where);
    if (!objects) return Error{objects.error()};
    for (const json& o : objects.value().at("objects"))
      gt.objects.push_back({o.at("label").get<uint32_t>(), vec3(o.at("position"))});
    where = (g / "gvd.json").string();
    auto gvd = readJson(where);
    if (!gvd) return Error{gvd.error()};
    const json& xyz = gvd.value().at("points_xyz");
    if (xyz.size() % 3 != 0) return Error{where + ": points_xyz is not a list of triples"};
    for (size_t i = 0; i < xyz.size(); i += 3)
      gt.gvd.emplace_back(xyz[i].get<double>(), xyz[i + 1].get<double>(), xyz[i + 2].get<double>());
    where = (g / "rooms.json").string();
    auto rooms = readJson(where);
    if (!rooms) return Error{rooms.error()};
    for (const json& f : rooms.value().at("floors")) {
      GroundTruthGrid grid;
      grid.floor = f.at("floor").get<int>();
      grid.z = f.at("z").get<double>();
      grid.origin << f.at("origin").at(0).get<double>(), f.at("origin").at(1).get<double>();
      grid.resolution = f.at("resolution").get<double>();
      grid.width = f.at("width").get<int>();
      grid.height = f.at("height").get<int>();
      gt.grids.push_back(grid);
    }
    for (const json& r : rooms.value().at("rooms")) {
      gt.room_ids.push_back(r.at("id").get<int>());
      gt.room_kinds.push_back(r.at("kind").get<std::string>());
      const int floor = r.at("floor").get<int>();
      const json& cells = r.at("cells_xy");
      std::vector<Eigen::Vector3i> keys;
      for (size_t i = 0; i + 1 < cells.size(); i += 2)
        keys.emplace_back(cells[i].get<int>(), cells[i + 1].get<int>(), floor);
      gt.room_cells.push_back(std::move(keys));
    }
  } catch (const json::exception& e) {
    return Error{where + ": missing or malformed field (" + std::string(e.what()) + ")"};
  } catch (const std::exception& e) {
    return Error{where + ": " + e.what()};
  }
  return gt;
}

Result<RobotReplay> replayRobotGraph(const DatasetGroundTruth& dataset, RobotId robot) {
  const auto it = dataset.streams.find(robot);
  if (it == dataset.streams.end())
    return Error{"robot " + robot.str() + " is not in the dataset " + dataset.dir};
  auto records = io::loadRobotStream(it->second, robot);
  if (!records) return Error{records.error()};
  RobotStreamReplay replay(robot, io::robotUpdateDigest);
  for (const RobotUpdate& update : records.value().updates) replay.add(update);
  RobotReplay result{std::move(replay.graph()), replay.order().counts(), records.value().skipped,
                     describeStream(robot, &replay.order(), records.value().skipped.size())};
  return result;
}

}  // namespace hydra_multi
