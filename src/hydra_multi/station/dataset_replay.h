#pragma once
// File replay of a dataset's robot streams (DESIGN.md "Data flow": robots -> updates -> station):
// dataset.json names the robots and their streams (dsg/io/dataset_files.h); the station reads
// nothing else of the dataset (never gt/). The updates of all robots are merged into one arrival
// order by robot time.

#include <map>
#include <string>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/dsg/robot_update.h"

namespace hydra_multi {

struct DatasetStreams {
  std::string dir;
  std::vector<RobotId> robots;            ///< dataset.json's, in its order
  std::vector<std::string> stream_paths;  ///< one per robot
  std::vector<RobotUpdate> updates;       ///< every robot's, by time (ties: robot, sequence)
  size_t bytes = 0;                       ///< of the stream files
  /// Records of the streams that were left out, each with its file, byte and why: damaged (a
  /// checksum, a truncated end, a payload that does not decode or holds NaNs) or from another
  /// robot than the stream's. The station sees the gap they leave, as it would on a network.
  std::vector<std::string> skipped;
  std::map<RobotId, size_t> skipped_per_robot;  ///< of `skipped`, per stream's robot
  /// A robot whose stream yields no update, or fewer than dataset.json says it sent.
  std::vector<std::string> warnings;
};

/// Reads DIR/dataset.json and every stream it names. A missing or malformed dataset.json (no
/// robots, a robot listed twice) or a stream that cannot be read is an error naming the file; a
/// damaged record is skipped and listed (a recording cut short, one flipped byte), the records
/// after it are read.
Result<DatasetStreams> loadDatasetStreams(const std::string& dir);

}  // namespace hydra_multi
