#pragma once
// Reading and writing scene-graph files, the format chosen by the file name:
//   .spark.json  Spark-DSG JSON             .json  our JSON (or Spark-DSG JSON, told by content)
//   .dsgb        our binary                 .ply   the mesh only (write only)
//   .sparkdsg    Spark-DSG's binary file (spark_graph.h)

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/dsg/robot_update.h"
#include "hydra_multi/dsg/scene_graph.h"

namespace hydra_multi::io {

enum class FileFormat { kJson, kSparkJson, kBinary, kPly, kSparkBinary };

/// The format a path names by its extension; nullopt for an unknown one.
std::optional<FileFormat> formatFromPath(const std::string& path);
const char* formatName(FileFormat format);

Result<std::string> readFile(const std::string& path);
Status writeFile(const std::string& path, const std::string& bytes);

/// Loads a graph; errors start with the path. With `unread_keys`, the keys of a JSON file the
/// reader did not read go there, with how often each occurs (KeyUse; describeUnread says them).
Result<SceneGraph> loadSceneGraph(const std::string& path,
                                  std::map<std::string, size_t>* unread_keys = nullptr);
/// "PATH: 3 keys not read: ..." for loadSceneGraph's unread keys; empty when there are none.
std::string describeUnread(const std::string& path,
                           const std::map<std::string, size_t>& unread_keys);
/// Saves a graph (for .ply, its mesh); creates no folders.
Status saveSceneGraph(const std::string& path, const SceneGraph& graph);

/// Loads every robot update of a .dsgb update stream, or of a robot-update .json file. A damaged
/// record of a stream (checksum, truncation, a payload that does not decode) is an error; with
/// `damaged`, it is described there instead ("PATH: record at byte N: why") and reading goes on
/// at the next intact record, so one bad record does not cost the rest of a recording.
Result<std::vector<RobotUpdate>> loadRobotUpdates(const std::string& path,
                                                  std::vector<std::string>* damaged = nullptr);

}  // namespace hydra_multi::io
