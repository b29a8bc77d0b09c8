#include "hydra_multi/web/view_state.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

namespace hydra_multi::web {
namespace {

using nlohmann::json;

int64_t centimetres(double metres) { return std::llround(metres * 100.0); }
double rounded(double value, double step) { return std::round(value / step) * step; }

std::string hexColor(const Color& c) {
  char text[8];
  std::snprintf(text, sizeof(text), "#%02x%02x%02x", c.r, c.g, c.b);
  return text;
}

json position(const Eigen::Vector3d& p) {
  return json::array({centimetres(p.x()), centimetres(p.y()), centimetres(p.z())});
}

json figures(const RoundTiming& timing) {
  const BackendRoundReport& r = timing.report;
  return {{"round", timing.round},
          {"after_update", timing.after_update},
          {"robots", r.robots},
          {"robots_aligned", r.robots_aligned},
          {"inter_robot_loop_closures", r.inter_robot_loop_closures},
          {"inter_robot_inliers", r.inter_robot_inliers},
          {"merges_proposed", r.merges_proposed},
          {"merges_accepted", r.merges_accepted},
          {"merges_undone", r.merges_undone},
          {"label_merges", r.label_merges},
          {"nodes", r.nodes},
          {"rooms", r.rooms},
          {"variables", r.variables},
          {"factors", r.factors},
          {"time_s", r.time_s},
          {"alignment_s", r.alignment_s},
          {"build_s", r.build_s},
          {"gnc_s", r.gnc_s},
          {"whole_graph_s", r.whole_graph_s},
          {"graph_s", r.graph_s},
          {"rooms_s", r.rooms_s}};
}

}  // namespace

const std::vector<std::string>& viewTables() {
  static const std::vector<std::string> tables = {"nodes", "edges", "loop_closures", "merges"};
  return tables;
}

std::string keyOfRow(const std::string& table, const json& row) {
  if (table == "nodes") return row.at(0).get<std::string>();
  return row.at(0).get<std::string>() + "|" + row.at(1).get<std::string>();
}

json nodeRow(const SceneGraph& graph, const Node& node) {
  json attributes = json::object();
  attributes["active"] = node.is_active;
  if (const SemanticAttributes* s = node.semantic()) {
    attributes["label"] = s->label;
    attributes["name"] = s->name;
    attributes["color"] = hexColor(s->color);
    if (s->bounding_box) {
      attributes["box"] = position(s->bounding_box->max - s->bounding_box->min);
    }
  }
  if (const AgentAttributes* a = node.find<AgentAttributes>()) {
    attributes["t"] = rounded(double(a->timestamp_ns) * 1e-9, 1e-3);
    attributes["k"] = a->keyframe_id;
    const Eigen::Quaterniond& q = a->orientation;
    attributes["q"] = json::array(
        {rounded(q.w(), 0.01), rounded(q.x(), 0.01), rounded(q.y(), 0.01), rounded(q.z(), 0.01)});
  } else if (const ObjectAttributes* o = node.find<ObjectAttributes>()) {
    attributes["vertices"] = o->mesh_vertices.size();
  } else if (const PlaceAttributes* p = node.find<PlaceAttributes>()) {
    attributes["distance"] = centimetres(p->distance);
  }
  const std::optional<RobotId> robot = node.robot();
  const std::optional<NodeId> parent = graph.parent(node.id);
  const Eigen::Vector3d& p = node.position;
  return json::array({node.id.str(), layerName(node.layer()), robot ? robot->str() : "",
                      centimetres(p.x()), centimetres(p.y()), centimetres(p.z()),
                      parent ? parent->str() : "", std::move(attributes)});
}

json meshExtents(const Mesh& mesh) {
  json extents = json::object();
  std::map<RobotId, std::array<uint64_t, 4>> ranges;  // v_start, v, f_start, f
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    auto [it, added] =
        ranges.try_emplace(mesh.vertices[i].robot, std::array<uint64_t, 4>{i, 0, 0, 0});
    ++it->second[1];
  }
  std::map<RobotId, bool> faced;
  for (size_t i = 0; i < mesh.faces.size(); ++i) {
    const uint32_t v = mesh.faces[i][0];
    if (v >= mesh.vertices.size()) continue;
    std::array<uint64_t, 4>& range = ranges[mesh.vertices[v].robot];
    if (!faced[mesh.vertices[v].robot]) range[2] = i;
    faced[mesh.vertices[v].robot] = true;
    ++range[3];
  }
  for (const auto& [robot, r] : ranges)
    extents[robot.str()] = json::array({r[0], r[1], r[2], r[3]});
  return extents;
}

ViewState viewOfRound(const RoundOutput& round, const std::map<RobotId, RobotLink>& links) {
  ViewState view;
  view.round = round.timing.round;
  view.info = figures(round.timing);
  std::set<RobotId> robots;
  for (const auto& [robot, progress] : round.progress) robots.insert(robot);
  for (const auto& [robot, link] : links) robots.insert(robot);
  for (const RobotId robot : robots) {
    json r = {{"aligned", round.aligned.count(robot) != 0}};
    if (const auto p = round.progress.find(robot); p != round.progress.end()) {
      r["applied"] = p->second.applied;
      r["next_sequence"] = p->second.next_sequence;
      r["robot_time_s"] = rounded(double(p->second.robot_time_ns) * 1e-9, 1e-3);
    }
    if (const auto l = links.find(robot); l != links.end()) {
      r["connected"] = l->second.connected;
      r["silent_s"] = rounded(l->second.silent_s, 0.1);
      r["bytes"] = l->second.bytes;
      r["done"] = l->second.done;
    }
    view.robots[robot.str()] = std::move(r);
  }
  view.mesh = meshExtents(round.graph.mesh());

  auto& nodes = view.tables["nodes"];
  for (const auto& [id, node] : round.graph.nodes())
    nodes.emplace(id.str(), nodeRow(round.graph, node));
  auto& edges = view.tables["edges"];
  for (const auto& [key, info] : round.graph.edges()) {
    const Node& a = round.graph.getNode(key.first());
    const Node& b = round.graph.getNode(key.second());
    if (a.layer() != b.layer()) continue;  // parents are in the node rows
    json row = json::array({a.id.str(), b.id.str()});
    edges.emplace(keyOfRow("edges", row), std::move(row));
  }
  auto& closures = view.tables["loop_closures"];
  for (const LoopClosureVerdict& v : round.loop_closures) {
    json row = json::array({v.from.str(), v.to.str(), v.inter_robot ? 1 : 0, v.kept ? 1 : 0});
    closures.emplace(keyOfRow("loop_closures", row), std::move(row));
  }
  auto& merges = view.tables["merges"];
  for (const AcceptedMerge& m : round.merges) {
    json row = json::array({m.target.str(), m.source.str(), layerName(m.layer)});
    for (const json& c : position(m.target_optimized)) row.push_back(c);
    for (const json& c : position(m.source_optimized)) row.push_back(c);
    merges.emplace(keyOfRow("merges", row), std::move(row));
  }
  return view;
}

json diffViews(const ViewState& from, const ViewState& to) {
  json delta = {{"seq", to.seq},         {"round", to.round},    {"final", to.final},
                {"info", to.info},       {"robots", to.robots},  {"mesh", to.mesh},
                {"set", json::object()}, {"del", json::object()}};
  static const std::map<std::string, json> kEmpty;
  for (const std::string& table : viewTables()) {
    const auto f = from.tables.find(table);
    const auto t = to.tables.find(table);
    const auto& before = f == from.tables.end() ? kEmpty : f->second;
    const auto& after = t == to.tables.end() ? kEmpty : t->second;
    json set = json::array(), del = json::array();
    for (const auto& [key, row] : after) {
      const auto old = before.find(key);
      if (old == before.end() || old->second != row) set.push_back(row);
    }
    for (const auto& [key, row] : before) {
      if (after.count(key) == 0) del.push_back(key);
    }
    if (!set.empty()) delta["set"][table] = std::move(set);
    if (!del.empty()) delta["del"][table] = std::move(del);
  }
  return delta;
}

json snapshotOfView(const ViewState& view) {
  json s = diffViews(ViewState{}, view);
  s["snapshot"] = true;
  return s;
}

Status applyViewDelta(ViewState& state, const json& delta) {
  const auto fail = [](const std::string& what) { return Error{"viewer delta: " + what}; };
  if (!delta.is_object()) return fail("not a JSON object");
  for (const char* field : {"seq", "round"}) {
    if (!delta.contains(field) || !delta[field].is_number_unsigned())
      return fail(std::string("'") + field + "' is not a non-negative integer");
  }
  for (const char* field : {"info", "robots", "mesh", "set", "del"}) {
    if (!delta.contains(field) || !delta[field].is_object())
      return fail(std::string("'") + field + "' is not an object");
  }
  const bool snapshot = delta.value("snapshot", false);
  ViewState next = snapshot ? ViewState{} : state;
  try {
    for (const auto& [table, rows] : delta["set"].items()) {
      if (!rows.is_array()) return fail("set." + table + " is not an array");
      const auto& known = viewTables();
      if (std::find(known.begin(), known.end(), table) == known.end())
        return fail("unknown table '" + table + "'");
      auto& t = next.tables[table];
      for (const json& row : rows) {
        if (!row.is_array() || row.size() < 2 || !row[0].is_string() || !row[1].is_string())
          return fail("a row of set." + table + " is not an array that starts with two strings");
        t[keyOfRow(table, row)] = row;
      }
    }
    for (const auto& [table, keys] : delta["del"].items()) {
      if (!keys.is_array()) return fail("del." + table + " is not an array");
      auto& t = next.tables[table];
      for (const json& key : keys) {
        if (!key.is_string()) return fail("a key of del." + table + " is not a string");
        if (t.erase(key.get<std::string>()) == 0)
          return fail("del." + table + " names " + key.get<std::string>() +
                      ", which it does not hold");
      }
    }
  } catch (const json::exception& e) {
    return fail(e.what());
  }
  next.seq = delta["seq"].get<uint64_t>();
  next.round = delta["round"].get<size_t>();
  next.final = delta.value("final", false);
  next.info = delta["info"];
  next.robots = delta["robots"];
  next.mesh = delta["mesh"];
  for (auto it = next.tables.begin(); it != next.tables.end();) {
    it = it->second.empty() ? next.tables.erase(it) : std::next(it);
  }
  state = std::move(next);
  return Status::Ok();
}

}  // namespace hydra_multi::web
