#pragma once
// The compact binary format (.dsgb), for scene graphs and for robot updates.
//
// A file is a sequence of records; a graph file holds one, an update stream one per update:
//
//   "HMDG" | kind u8 (1 graph, 2 robot update) | version u16 | payload size varint | payload |
//   CRC-32 u32 of everything from kind to the end of the payload
//
// Integers are little-endian; counts and indices are varints; times and index runs are zigzag
// deltas; node positions and poses are float64, mesh positions float32 (as held in memory), so a
// round trip is exact. Decoding checks the checksum, every length against the bytes left, and every
// value (finite numbers, existing edge endpoints) before it returns anything.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/dsg/robot_update.h"
#include "hydra_multi/dsg/scene_graph.h"

namespace hydra_multi::io {

inline constexpr uint16_t kBinaryVersion = 1;

enum class RecordKind : uint8_t { kSceneGraph = 1, kRobotUpdate = 2 };

std::string encodeSceneGraphBinary(const SceneGraph& graph);
Result<SceneGraph> decodeSceneGraphBinary(std::string_view bytes);

std::string encodeRobotUpdateBinary(const RobotUpdate& update);
/// Decodes a buffer that holds exactly one robot-update record.
Result<RobotUpdate> decodeRobotUpdateBinary(std::string_view bytes);

/// One record of a file: its kind, its place and its payload.
struct RecordView {
  RecordKind kind;
  size_t offset = 0;  ///< where the record starts in the file
  std::string_view payload;
};

/// Reads the records of a file one at a time, so a stream of updates is never loaded whole into
/// decoded form. next() returns nullopt at the end; a broken record is an error naming its offset.
class RecordReader {
 public:
  explicit RecordReader(std::string_view bytes) : bytes_(bytes) {}
  /// The next record, nullopt at the end of the file, or an error.
  Result<std::optional<RecordView>> next();

 private:
  std::string_view bytes_;
  size_t pos_ = 0;
};

/// Decodes the payload of a robot-update record.
Result<RobotUpdate> decodeRobotUpdatePayload(const RecordView& record);
/// Decodes the payload of a scene-graph record.
Result<SceneGraph> decodeSceneGraphPayload(const RecordView& record);

}  // namespace hydra_multi::io
