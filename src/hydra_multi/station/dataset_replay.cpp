#include "hydra_multi/station/dataset_replay.h"

#include <algorithm>

#include "hydra_multi/dsg/io/dataset_files.h"

namespace hydra_multi {

Result<DatasetStreams> loadDatasetStreams(const std::string& dir) {
  auto manifest = io::readDatasetManifest(dir);
  if (!manifest) return Error{manifest.error()};
  DatasetStreams streams;
  streams.dir = dir;
  for (const io::DatasetRobot& robot : manifest.value().robots) {
    auto records = io::loadRobotStream(robot.stream, robot.robot);
    if (!records) return Error{records.error()};
    streams.robots.push_back(robot.robot);
    streams.stream_paths.push_back(robot.stream);
    streams.bytes += records.value().bytes;
    const std::vector<std::string>& skipped = records.value().skipped;
    streams.skipped.insert(streams.skipped.end(), skipped.begin(), skipped.end());
    streams.skipped_per_robot[robot.robot] = skipped.size();
    const size_t intact = records.value().updates.size();
    if (intact == 0) {
      streams.warnings.push_back("robot " + robot.robot.str() + ": " + robot.stream +
                                 " holds no intact update of robot " + robot.robot.str());
    } else if (robot.updates_sent && intact < *robot.updates_sent) {
      streams.warnings.push_back("robot " + robot.robot.str() + ": " + robot.stream + " holds " +
                                 std::to_string(intact) + " intact updates, " +
                                 manifest.value().path + " says it sent " +
                                 std::to_string(*robot.updates_sent));
    }
    for (RobotUpdate& u : records.value().updates) streams.updates.push_back(std::move(u));
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
