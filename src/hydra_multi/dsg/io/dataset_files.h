#pragma once
// A recorded team's files (written by `simulate`, sim/dataset.h): DIR/dataset.json names the
// robots and their update streams. The one reader of that list for the station's file replay and
// for the evaluation, and the one reader of a robot's stream file:
//   - dataset.json must be a hydra-multi dataset with at least one robot, each robot listed once,
//     each stream a relative path inside DIR;
//   - a stream's damaged records (checksum, truncation, a payload that does not decode or holds
//     NaNs) and updates of another robot are left out and named, the records after them read.

#include <optional>
#include <string>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/dsg/robot_update.h"

namespace hydra_multi::io {

struct DatasetRobot {
  RobotId robot;
  std::string stream;                  ///< the stream's path (DIR joined with dataset.json's)
  std::optional<size_t> updates_sent;  ///< dataset.json's count, when it gives one
};

struct DatasetManifest {
  std::string dir;
  std::string path;  ///< DIR/dataset.json
  std::vector<DatasetRobot> robots;
};

/// Reads DIR/dataset.json's team; errors name the file and what is wrong.
Result<DatasetManifest> readDatasetManifest(const std::string& dir);

/// One robot's stream file: its intact updates in file order, and every record left out, each as
/// "PATH: record at byte N: why" or "PATH: update K is from robot c, not a".
struct RobotStreamRecords {
  std::vector<RobotUpdate> updates;
  std::vector<std::string> skipped;
  size_t bytes = 0;  ///< of the file
};
/// An unreadable file is an error; damaged records are not.
Result<RobotStreamRecords> loadRobotStream(const std::string& path, RobotId robot);

}  // namespace hydra_multi::io
