#include "hydra_multi/dsg/io/graph_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/dsg/io/json_fields.h"
#include "hydra_multi/dsg/io/json_format.h"
#include "hydra_multi/dsg/io/ply.h"
#include "hydra_multi/dsg/io/spark_graph.h"
#include "hydra_multi/dsg/io/spark_json.h"

namespace hydra_multi::io {
namespace {

bool endsWith(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

std::optional<FileFormat> formatFromPath(const std::string& path) {
  if (endsWith(path, ".spark.json")) return FileFormat::kSparkJson;
  if (endsWith(path, ".json")) return FileFormat::kJson;
  if (endsWith(path, ".dsgb")) return FileFormat::kBinary;
  if (endsWith(path, ".ply")) return FileFormat::kPly;
  if (endsWith(path, ".sparkdsg")) return FileFormat::kSparkBinary;
  return std::nullopt;
}

const char* formatName(FileFormat format) {
  switch (format) {
    case FileFormat::kJson:
      return "JSON";
    case FileFormat::kSparkJson:
      return "Spark-DSG JSON";
    case FileFormat::kBinary:
      return "binary";
    case FileFormat::kPly:
      return "PLY";
    case FileFormat::kSparkBinary:
      return "Spark-DSG binary";
  }
  return "unknown";
}

Result<std::string> readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{path + ": cannot open (" + std::strerror(errno) + ")"};
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) return Error{path + ": read failed"};
  return buffer.str();
}

Status writeFile(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return Error{path + ": cannot open for writing (" + std::strerror(errno) + ")"};
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) return Error{path + ": write failed"};
  return Status::Ok();
}

std::string describeUnread(const std::string& path,
                           const std::map<std::string, size_t>& unread_keys) {
  return unread_keys.empty() ? "" : path + ": " + KeyUse::describe(unread_keys);
}

Result<SceneGraph> loadSceneGraph(const std::string& path,
                                  std::map<std::string, size_t>* unread_keys) {
  const auto format = formatFromPath(path);
  if (!format) return Error{path + ": unknown extension (.json, .spark.json, .dsgb or .sparkdsg)"};
  if (*format == FileFormat::kPly) {
    return Error{path + ": a PLY file holds only a mesh and cannot be read as a scene graph"};
  }
  auto bytes = readFile(path);
  if (!bytes) return Error{bytes.error()};
  Result<SceneGraph> graph = Error{""};
  if (*format == FileFormat::kBinary) {
    graph = decodeSceneGraphBinary(bytes.value());
  } else if (*format == FileFormat::kSparkBinary) {
    graph = sceneGraphFromSparkFile(bytes.value());
  } else {
    auto root = parseJson(bytes.value(), formatName(*format));
    if (!root) return Error{path + ": " + root.error()};
    const bool ours = *format == FileFormat::kJson && isOurSceneGraphJson(root.value());
    KeyUse use;
    graph =
        ours ? sceneGraphFromJsonValue(root.value()) : sceneGraphFromSparkJsonValue(root.value());
    if (unread_keys) *unread_keys = use.unread(root.value());
  }
  if (!graph) return Error{path + ": " + graph.error()};
  return graph;
}

Status saveSceneGraph(const std::string& path, const SceneGraph& graph) {
  const auto format = formatFromPath(path);
  if (!format)
    return Error{path + ": unknown extension (.json, .spark.json, .dsgb, .sparkdsg or .ply)"};
  switch (*format) {
    case FileFormat::kJson:
      return writeFile(path, sceneGraphToJson(graph));
    case FileFormat::kSparkJson:
      return writeFile(path, sceneGraphToSparkJson(graph));
    case FileFormat::kBinary:
      return writeFile(path, encodeSceneGraphBinary(graph));
    case FileFormat::kPly:
      return writeFile(path, meshToPly(graph.mesh()));
    case FileFormat::kSparkBinary:
      return writeFile(path, sceneGraphToSparkFile(graph));
  }
  return Error{path + ": unknown format"};
}

Result<std::vector<RobotUpdate>> loadRobotUpdates(const std::string& path,
                                                  std::vector<std::string>* damaged) {
  auto bytes = readFile(path);
  if (!bytes) return Error{bytes.error()};
  const auto format = formatFromPath(path);
  if (format == FileFormat::kJson) {
    auto update = robotUpdateFromJson(bytes.value());
    if (!update) return Error{path + ": " + update.error()};
    return std::vector<RobotUpdate>{std::move(update).value()};
  }
  if (format != FileFormat::kBinary) return Error{path + ": robot updates are .dsgb or .json"};
  std::vector<RobotUpdate> updates;
  RecordReader reader(bytes.value());
  while (true) {
    auto record = reader.next();
    if (!record) {
      if (!damaged) return Error{path + ": " + record.error()};
      damaged->push_back(path + ": " + record.error());
      if (!reader.resynchronize()) break;
      continue;
    }
    if (!record.value()) break;
    auto update = decodeRobotUpdatePayload(*record.value());
    if (!update) {
      if (!damaged) return Error{path + ": " + update.error()};
      damaged->push_back(path + ": " + update.error());
      continue;
    }
    updates.push_back(std::move(update).value());
  }
  return updates;
}

}  // namespace hydra_multi::io
