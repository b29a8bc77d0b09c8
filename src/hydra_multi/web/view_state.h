#pragma once
// What the viewer draws of one backend round (docs/VIEWER.md): the backend graph as tables of rows
// keyed by id (nodes, intra-layer edges, loop closures with GNC's verdict, merges), and the round's
// figures (the backend report, each robot's progress and link, the mesh's extent per robot).
// Positions are rounded to centimetres, so a round that moves a node by less changes no row; the
// delta between two views (diffViews) holds the rows that changed and the figures:
// applyViewDelta(a, diffViews(a, b)) == b. A snapshot is the delta from the empty view.

#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "hydra_multi/core/result.h"
#include "hydra_multi/station/station.h"

namespace hydra_multi::web {

/// What the input knows of a robot's link: the station's network, or `run`'s replay.
struct RobotLink {
  bool connected = false;
  double silent_s = 0.0;  ///< since the station last heard of it
  uint64_t bytes = 0;     ///< received from it
  bool done = false;      ///< it said BYE (the replay: its stream has ended)
};

struct ViewState {
  uint64_t seq = 0;  ///< the feed's number (viewer_feed.h); 0: not published
  size_t round = 0;
  bool final = false;
  nlohmann::json info = nlohmann::json::object();    ///< the round's figures
  nlohmann::json robots = nlohmann::json::object();  ///< per robot: alignment, progress, link
  nlohmann::json mesh = nlohmann::json::object();    ///< per robot: [v_start, v, f_start, f]
  /// Table name -> key -> row (a JSON array; its key is keyOfRow's).
  std::map<std::string, std::map<std::string, nlohmann::json>> tables;

  bool operator==(const ViewState& o) const {
    return seq == o.seq && round == o.round && final == o.final && info == o.info &&
           robots == o.robots && mesh == o.mesh && tables == o.tables;
  }
};

/// The tables a view has: "nodes", "edges", "loop_closures", "merges".
const std::vector<std::string>& viewTables();

/// A row's key: a node's id (row[0]); for the other tables "row[0]|row[1]".
std::string keyOfRow(const std::string& table, const nlohmann::json& row);

/// One node as a row: [id, layer, robot ("" when none), x, y, z (cm), parent id ("" when none),
/// attributes {label, name, color, active, and by layer t, k, q / box, vertices / distance}].
nlohmann::json nodeRow(const SceneGraph& graph, const Node& node);

/// The view of a backend round; `links` per robot where a network input knows them.
ViewState viewOfRound(const RoundOutput& round, const std::map<RobotId, RobotLink>& links = {});

/// The delta that turns `from` into `to`: {seq, round, final, info, robots, mesh, set: {table:
/// [rows]}, del: {table: [keys]}}; with `snapshot` (from the empty view) also "snapshot": true.
nlohmann::json diffViews(const ViewState& from, const ViewState& to);
nlohmann::json snapshotOfView(const ViewState& view);

/// Applies a delta (or, with "snapshot": true, replaces the view); checks its shape first and
/// leaves `state` untouched on an error, which names the field.
Status applyViewDelta(ViewState& state, const nlohmann::json& delta);

/// Each robot's range of the backend mesh: {robot: [vertex_start, vertices, face_start, faces]}
/// (the backend appends robot after robot; a face belongs to its first vertex's robot).
nlohmann::json meshExtents(const Mesh& mesh);

}  // namespace hydra_multi::web
