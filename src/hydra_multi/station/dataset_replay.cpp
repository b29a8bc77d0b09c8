#include "hydra_multi/station/dataset_replay.h"

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "hydra_multi/dsg/io/graph_file.h"

namespace hydra_multi {

Result<DatasetStreams> loadDatasetStreams(const std::string& dir) {
  namespace fs = std::filesystem;
  const std::string header_path = (fs::path(dir) / "dataset.json").string();
  auto text = io::readFile(header_path);
  if (!text) return Error{text.error() + " (is " + dir + " a dataset written by simulate?)"};
  const nlohmann::json header = nlohmann::json::parse(text.value(), nullptr, false);
  if (header.is_discarded()) return Error{header_path + ": not valid JSON"};
  DatasetStreams streams;
  streams.dir = dir;
  try {
    for (const nlohmann::json& r : header.at("robots")) {
      const std::string name = r.at("robot").get<std::string>();
      const auto robot = RobotId::parse(name);
      if (!robot) return Error{header_path + ": unknown robot '" + name + "'"};
      streams.robots.push_back(*robot);
      streams.stream_paths.push_back((fs::path(dir) / r.at("stream").get<std::string>()).string());
    }
  } catch (const nlohmann::json::exception& e) {
    return Error{header_path + ": missing or malformed field (" + std::string(e.what()) + ")"};
  }
  for (size_t i = 0; i < streams.robots.size(); ++i) {
    auto updates = io::loadRobotUpdates(streams.stream_paths[i], &streams.skipped);
    if (!updates) return Error{updates.error()};
    std::error_code ec;
    streams.bytes += fs::file_size(streams.stream_paths[i], ec);
    for (RobotUpdate& u : updates.value()) {
      if (u.robot != streams.robots[i]) {
        streams.skipped.push_back(streams.stream_paths[i] + ": update " +
                                  std::to_string(u.sequence) + " is from robot " + u.robot.str() +
                                  ", not " + streams.robots[i].str());
        continue;
      }
      streams.updates.push_back(std::move(u));
    }
  }
  std::stable_sort(streams.updates.begin(), streams.updates.end(),
                   [](const RobotUpdate& a, const RobotUpdate& b) {
                     if (a.time_ns != b.time_ns) return a.time_ns < b.time_ns;
                     if (a.robot != b.robot) return a.robot < b.robot;
                     return a.sequence < b.sequence;
                   });
  return streams;
}

}  // namespace hydra_multi
