#include "hydra_multi/dsg/io/dataset_files.h"

#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>

#include "hydra_multi/dsg/io/graph_file.h"

namespace hydra_multi::io {

Result<DatasetManifest> readDatasetManifest(const std::string& dir) {
  namespace fs = std::filesystem;
  DatasetManifest manifest;
  manifest.dir = dir;
  manifest.path = (fs::path(dir) / "dataset.json").string();
  const std::string& path = manifest.path;
  auto text = readFile(path);
  if (!text) return Error{text.error() + " (is " + dir + " a dataset written by simulate?)"};
  const nlohmann::json header = nlohmann::json::parse(text.value(), nullptr, false);
  if (header.is_discarded()) return Error{path + ": not valid JSON"};
  if (!header.is_object() || header.value("format", "") != "hydra-multi-dataset")
    return Error{path +
                 ": not a hydra-multi dataset (its \"format\" is not \"hydra-multi-dataset\")"};
  if (!header.contains("robots") || !header["robots"].is_array())
    return Error{path + ": no \"robots\" list"};
  const nlohmann::json& robots = header["robots"];
  if (robots.empty()) return Error{path + ": the \"robots\" list is empty: no robot to replay"};
  std::set<RobotId> seen;
  for (size_t i = 0; i < robots.size(); ++i) {
    const nlohmann::json& r = robots[i];
    const std::string where = path + ": robots[" + std::to_string(i) + "]";
    if (!r.is_object() || !r.contains("robot") || !r["robot"].is_string())
      return Error{where + ": no \"robot\" name"};
    if (!r.contains("stream") || !r["stream"].is_string())
      return Error{where + ": no \"stream\" path"};
    const std::string name = r["robot"].get<std::string>();
    const auto robot = RobotId::parse(name);
    if (!robot) return Error{where + ": unknown robot '" + name + "'"};
    if (!seen.insert(*robot).second) return Error{where + ": robot " + name + " is listed twice"};
    const fs::path stream(r["stream"].get<std::string>());
    bool leaves = stream.empty() || stream.is_absolute();
    for (const fs::path& part : stream) leaves = leaves || part == "..";
    if (leaves)
      return Error{where + ": stream '" + stream.string() +
                   "' is not a relative path inside the dataset's folder"};
    DatasetRobot entry;
    entry.robot = *robot;
    entry.stream = (fs::path(dir) / stream).string();
    if (r.contains("updates")) {
      if (!r["updates"].is_number_unsigned()) return Error{where + ": \"updates\" is not a count"};
      entry.updates_sent = r["updates"].get<size_t>();
    }
    manifest.robots.push_back(std::move(entry));
  }
  return manifest;
}

Result<RobotStreamRecords> loadRobotStream(const std::string& path, RobotId robot) {
  RobotStreamRecords records;
  auto updates = loadRobotUpdates(path, &records.skipped);
  if (!updates) return Error{updates.error()};
  std::error_code ec;
  records.bytes = std::filesystem::file_size(path, ec);
  for (RobotUpdate& u : updates.value()) {
    if (u.robot != robot) {
      records.skipped.push_back(path + ": update " + std::to_string(u.sequence) +
                                " is from robot " + u.robot.str() + ", not " + robot.str());
      continue;
    }
    records.updates.push_back(std::move(u));
  }
  return records;
}

}  // namespace hydra_multi::io
