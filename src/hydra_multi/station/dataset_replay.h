#pragma once
// File replay of a dataset's robot streams (DESIGN.md "Data flow": robots -> updates -> station):
// dataset.json names the robots and their streams; the station reads nothing else of the dataset
// (never gt/). The updates of all robots are merged into one arrival order by robot time.

#include <string>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/dsg/robot_update.h"

namespace hydra_multi {

struct DatasetStreams {
  std::string dir;
  std::vector<RobotId> robots;
  std::vector<std::string> stream_paths;  ///< one per robot
  std::vector<RobotUpdate> updates;       ///< every robot's, by time (ties: robot, sequence)
  size_t bytes = 0;                       ///< of the stream files
};

/// Reads DIR/dataset.json and every stream it names; errors name the file and the problem.
Result<DatasetStreams> loadDatasetStreams(const std::string& dir);

}  // namespace hydra_multi
