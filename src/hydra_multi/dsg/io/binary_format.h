#pragma once
// The compact binary format (.dsgb), for scene graphs and for robot updates.
//
// A file is a sequence of records (binary_record.h); a graph file holds one, an update stream
// one per update. Inside a record's payload, integers are little-endian; counts and indices are
// varints; times and index runs are zigzag deltas; node positions and poses are float64, mesh
// positions float32 (as held in memory), so a round trip is exact. Decoding checks the checksum,
// every length against the bytes left, and every value (finite numbers, existing edge endpoints)
// before it returns anything.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/dsg/io/binary_record.h"
#include "hydra_multi/dsg/robot_update.h"
#include "hydra_multi/dsg/scene_graph.h"

namespace hydra_multi::io {

std::string encodeSceneGraphBinary(const SceneGraph& graph);
/// Decodes a buffer that holds exactly one scene-graph record.
Result<SceneGraph> decodeSceneGraphBinary(std::string_view bytes);

/// A delta between two graphs (dsg/graph_delta.h) as one record; decoding checks its layout and
/// numbers, applyDelta checks it against the graph it is applied to.
std::string encodeGraphDeltaBinary(const GraphDelta& delta);
Result<GraphDelta> decodeGraphDeltaBinary(std::string_view bytes);

std::string encodeRobotUpdateBinary(const RobotUpdate& update);
/// An update's encoded record split by what it carries (the paper's Fig. 9b categories); the
/// parts add up to encodeRobotUpdateBinary(update).size().
struct RobotUpdateBytes {
  size_t header = 0;       ///< record framing and checksum; robot, sequence, time, layers
  size_t nodes_edges = 0;  ///< scene-graph nodes and edges: added, changed and removed
  size_t mesh = 0;
  size_t pose_graph = 0;
  size_t deformation = 0;  ///< control points and their edges
  size_t descriptors = 0;  ///< loop-closure descriptors (bag of words, keypoints)
  size_t total() const {
    return header + nodes_edges + mesh + pose_graph + deformation + descriptors;
  }
};
RobotUpdateBytes robotUpdateBytes(const RobotUpdate& update);
/// A digest of an update's whole content (its encoding), to tell a duplicate from a conflict.
size_t robotUpdateDigest(const RobotUpdate& update);
/// Decodes a buffer that holds exactly one robot-update record.
Result<RobotUpdate> decodeRobotUpdateBinary(std::string_view bytes);

/// Decodes the payload of a robot-update record.
Result<RobotUpdate> decodeRobotUpdatePayload(const RecordView& record);
/// Decodes the payload of a scene-graph record.
Result<SceneGraph> decodeSceneGraphPayload(const RecordView& record);

}  // namespace hydra_multi::io
