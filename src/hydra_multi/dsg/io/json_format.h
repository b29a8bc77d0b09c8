#pragma once
// Our readable JSON format (.json) for scene graphs and robot updates. Node ids are written in
// their readable form ("O(3)", "a12", "O(3)@b"); quaternions as {"w","x","y","z"}; poses as their
// 3x4 matrix rows. Doubles are written with the shortest digits that read back exactly, floats
// with the shortest that read back to the same float, so a round trip is exact.
//
//   {"format": "hydra-multi scene graph", "version": 1, "nodes": [...], "edges": [...],
//    "mesh": {"vertices": [...], "faces": [[i, j, k], ...]}}

#include <nlohmann/json.hpp>
#include <string>

#include "hydra_multi/core/result.h"
#include "hydra_multi/dsg/robot_update.h"
#include "hydra_multi/dsg/scene_graph.h"

namespace hydra_multi::io {

inline constexpr int kJsonVersion = 1;
inline constexpr const char* kSceneGraphFormatName = "hydra-multi scene graph";
inline constexpr const char* kRobotUpdateFormatName = "hydra-multi robot update";

/// one_line: the whole document on one line; otherwise one node, edge or vertex per line.
std::string sceneGraphToJson(const SceneGraph& graph, bool one_line = false);
Result<SceneGraph> sceneGraphFromJson(const std::string& text);
/// The same, from a parsed document (see parseJson).
Result<SceneGraph> sceneGraphFromJsonValue(const nlohmann::ordered_json& root);

std::string robotUpdateToJson(const RobotUpdate& update, bool one_line = false);
Result<RobotUpdate> robotUpdateFromJson(const std::string& text);

/// Parses JSON text; the error names the byte where parsing failed.
Result<nlohmann::ordered_json> parseJson(const std::string& text, const char* what);
/// True when a parsed document names our scene-graph format (rather than Spark-DSG's).
bool isOurSceneGraphJson(const nlohmann::ordered_json& root);

}  // namespace hydra_multi::io
