#include "hydra_multi/sim/robot_mapper.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <stdexcept>
#include <tuple>

#include "hydra_multi/dsg/robot_stream.h"
#include "hydra_multi/sim/visibility.h"

namespace hydra_multi::sim {

uint32_t SensorProfile::providedLayers() const {
  uint32_t layers = kProvidesAgents | kProvidesPlaces | kProvidesMesh | kProvidesVisual;
  if (semantic) layers |= kProvidesObjects | kProvidesMeshLabels;
  return layers;
}

SensorProfile rgbdProfile() { return SensorProfile{}; }

SensorProfile lidarProfile() {
  SensorProfile lidar;
  lidar.kind = "lidar";
  lidar.semantic = false;
  lidar.mesh_range = 10.0;
  lidar.mesh_horizontal_fov_deg = 360.0;
  lidar.mesh_vertical_fov_deg = 30.0;
  return lidar;
}

SensedWorld::SensedWorld(World w, FreeSpace s, WorldMesh m, std::vector<TexturedPoint> t)
    : world(std::move(w)), space(std::move(s)), mesh(std::move(m)), textures(std::move(t)) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(mesh.vertices.size());
  for (const SurfaceVertex& v : mesh.vertices) points.push_back(v.position);
  mesh_index = std::make_unique<NearestNeighbors>(points);
  vertex_faces.resize(mesh.vertices.size());
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    for (const uint32_t v : mesh.faces[f]) vertex_faces[v].push_back(static_cast<uint32_t>(f));
  }
}

int SensedWorld::floorOf(const Eigen::Vector3d& body_position, double body_height) const {
  int floor = 0;
  for (const Floor& f : world.floors) {
    if (f.z <= body_position.z() - body_height + 0.5) floor = std::max(floor, f.index);
  }
  return floor;
}

int SensedWorld::roomOf(int floor, const Eigen::Vector3d& body_position) const {
  if (floor < 0 || static_cast<size_t>(floor) >= space.floors.size()) return -1;
  const FloorGrid& grid = space.floors[static_cast<size_t>(floor)];
  const Eigen::Vector2i c = grid.cellOf(body_position.head<2>());
  if (!grid.inside(c.x(), c.y())) return -1;
  return grid.room[grid.index(c.x(), c.y())];
}

namespace {

constexpr int64_t kUnseen = -1;

// The places of a whole run with the keyframe that first sees each (places.h, per floor).
struct TimedPlaces {
  struct Place {
    PlaceGraph::Place place;
    size_t first_keyframe = 0;
  };
  std::vector<Place> places;
  std::vector<PlaceGraph::Edge> edges;  // indices into places
};

TimedPlaces timedPlaces(const SensedWorld& sensed, const RobotRun& run,
                        const PlacesOptions& options) {
  TimedPlaces timed;
  std::set<int> floors(run.floors.begin(), run.floors.end());
  for (const int floor : floors) {
    const FloorGrid& grid = sensed.space.floors.at(static_cast<size_t>(floor));
    std::vector<size_t> keyframes;
    std::vector<Eigen::Vector2d> positions;
    for (size_t k = 0; k < run.truth.size(); ++k) {
      if (run.floors[k] != floor) continue;
      keyframes.push_back(k);
      positions.push_back(run.truth[k].T_world_body.translation().head<2>());
    }
    const PlaceGraph graph = extractPlaces(grid, positions, options);
    const size_t offset = timed.places.size();
    for (const PlaceGraph::Place& place : graph.places) {
      size_t first = run.truth.size();
      for (size_t i = 0; i < positions.size(); ++i) {
        if ((positions[i] - place.position.head<2>()).norm() <= options.sensor_range &&
            lineOfSight(grid, positions[i], place.position.head<2>())) {
          first = keyframes[i];
          break;
        }
      }
      timed.places.push_back({place, std::min(first, run.truth.size() - 1)});
    }
    for (PlaceGraph::Edge edge : graph.edges) {
      edge.a += offset;
      edge.b += offset;
      timed.edges.push_back(edge);
    }
  }
  return timed;
}

class RobotMapper {
 public:
  RobotMapper(const SensedWorld& sensed, const RobotRun& run, const MapperOptions& options)
      : sensed_(sensed),
        run_(run),
        options_(options),
        rng_(options.seed * 7919u + run.robot.index()),
        robot_vertex_(sensed.mesh.vertices.size(), kUnseen),
        face_emitted_(sensed.mesh.faces.size(), false) {
    const TimedPlaces timed = timedPlaces(sensed, run, options.places);
    places_ = timed.places;
    place_edges_by_place_.resize(places_.size());
    for (const PlaceGraph::Edge& e : timed.edges) {
      place_edges_by_place_[e.a].push_back(e);
      place_edges_by_place_[e.b].push_back(e);
    }
    places_at_.resize(run.truth.size());
    for (size_t i = 0; i < places_.size(); ++i) places_at_[places_[i].first_keyframe].push_back(i);
    place_node_.assign(places_.size(), std::nullopt);
    detections_at_.resize(run.truth.size());
    if (run.sensor.semantic) {
      for (const DetectedObject& d :
           detectObjects(sensed.world, sensed.space, run.floors, run.truth, run.sensor.camera,
                         options.detection)) {
        detections_at_[d.first_keyframe].push_back(d);
      }
    }
    closures_at_.resize(run.truth.size());
    for (const SimulatedLoopClosure& c : run.loop_closures) {
      if (c.to < run.truth.size()) closures_at_[c.to].push_back(c);
    }
  }

  std::vector<RobotUpdate> run() {
    int64_t last_flush = run_.truth.empty() ? 0 : run_.truth.front().time_ns;
    for (size_t k = 0; k < run_.truth.size(); ++k) {
      step(k);
      const int64_t t = run_.truth[k].time_ns;
      if (k + 1 == run_.truth.size() ||
          t - last_flush >= static_cast<int64_t>(options_.update_period_s * 1e9)) {
        flush(t);
        last_flush = t;
      }
    }
    return std::move(updates_);
  }

 private:
  NodeId agentId(size_t k) const { return NodeId(run_.robot.prefix(), k); }
  // World -> robot frame at keyframe k.
  Eigen::Isometry3d drift(size_t k) const {
    return run_.odometry[k] * run_.truth[k].T_world_body.inverse();
  }

  void step(size_t k) {
    const int64_t t = run_.truth[k].time_ns;
    const Eigen::Isometry3d D = drift(k);
    addKeyframe(k, t);
    observeMesh(k, t, D);
    addPlaces(k, t, D);
    if (run_.sensor.semantic) {
      runScheduledObjectEvents(t);
      addObjects(k, t, D);
      refreshObjectVertices(t, D);
    }
    attachToPlace(agentId(k), run_.odometry[k].translation());
    addDescriptor(k);
    for (const SimulatedLoopClosure& c : closures_at_[k]) {
      PoseGraphEdge edge;
      edge.from = agentId(c.from);
      edge.to = agentId(c.to);
      edge.kind = PoseGraphEdge::Kind::kLoopClosure;
      edge.T_from_to = c.T_from_to;
      const double rot = options_.loop_closure_rotation_sigma_deg * M_PI / 180.0;
      edge.information =
          informationFromVariances(std::pow(options_.loop_closure_translation_sigma, 2), rot * rot);
      pending_.pose_graph.push_back(edge);
    }
  }

  void addKeyframe(size_t k, int64_t t) {
    const Eigen::Isometry3d& T = run_.odometry[k];
    Node node = makeNode(agentId(k), Layer::kAgents, T.translation());
    node.last_update_time_ns = t;
    AgentAttributes& agent = std::get<AgentAttributes>(node.attributes);
    agent.orientation = Eigen::Quaterniond(T.linear()).normalized();
    agent.timestamp_ns = t;
    agent.keyframe_id = k;
    putNode(node);
    if (k == 0) return;
    putEdge(agentId(k - 1), agentId(k), {});
    PoseGraphEdge odometry;
    odometry.from = agentId(k - 1);
    odometry.to = agentId(k);
    odometry.T_from_to = run_.odometry[k - 1].inverse() * T;
    // The odometry noise of a step of length s has variance sigma^2 * s (trajectory.h).
    const double s = std::max(0.05, (run_.truth[k].T_world_body.translation() -
                                     run_.truth[k - 1].T_world_body.translation())
                                        .norm());
    const OdometryNoise& n = run_.odometry_noise;
    const double yaw = std::max(n.yaw_sigma, n.roll_pitch_sigma);
    odometry.information =
        informationFromVariances(n.translation_sigma * n.translation_sigma * s, yaw * yaw * s);
    pending_.pose_graph.push_back(odometry);
  }

  bool inView(const Eigen::Isometry3d& T_world_body, const Eigen::Vector3d& p) const {
    const Eigen::Vector3d b = T_world_body.inverse() * p;
    const double horizontal = std::hypot(b.x(), b.y());
    if (run_.sensor.mesh_horizontal_fov_deg < 360.0 &&
        std::abs(std::atan2(b.y(), b.x())) > 0.5 * run_.sensor.mesh_horizontal_fov_deg * M_PI / 180)
      return false;
    return std::abs(std::atan2(b.z(), horizontal)) <=
           0.5 * run_.sensor.mesh_vertical_fov_deg * M_PI / 180.0;
  }

  void observeMesh(size_t k, int64_t t, const Eigen::Isometry3d& D) {
    const Eigen::Isometry3d& T = run_.truth[k].T_world_body;
    const int floor = run_.floors[k];
    const FloorGrid& grid = sensed_.space.floors.at(static_cast<size_t>(floor));
    const Eigen::Vector2d eye = T.translation().head<2>();
    std::normal_distribution<double> gauss(0.0, options_.mesh_noise_sigma);
    std::vector<uint32_t> seen_now;
    for (const auto& n :
         sensed_.mesh_index->withinRadius(T.translation(), run_.sensor.mesh_range)) {
      if (robot_vertex_[n.index] != kUnseen) continue;
      const SurfaceVertex& v = sensed_.mesh.vertices[n.index];
      if (v.floor != floor || !inView(T, v.position)) continue;
      // Surface points sit on walls: step a little back towards the eye for the sight line.
      Eigen::Vector2d target = v.position.head<2>();
      const Eigen::Vector2d to = target - eye;
      if (to.norm() > 1e-6) target -= 0.6 * grid.resolution * to / to.norm();
      if (!lineOfSight(grid, eye, target)) continue;
      seen_now.push_back(static_cast<uint32_t>(n.index));
    }
    const Color grey{128, 128, 128};
    for (const uint32_t w : seen_now) {
      const SurfaceVertex& v = sensed_.mesh.vertices[w];
      MeshVertex vertex;
      const Eigen::Vector3d noise(gauss(rng_), gauss(rng_), gauss(rng_));
      vertex.position = (D * v.position + noise).cast<float>();
      const SemanticClass* c = sensed_.world.findClass(v.label);
      vertex.color = run_.sensor.semantic && c != nullptr ? c->color : grey;
      vertex.label = run_.sensor.semantic ? v.label : MeshVertex::kUnlabeled;
      vertex.robot = run_.robot;
      vertex.time_ns = t;
      robot_vertex_[w] = static_cast<int64_t>(num_vertices_++);
      vertex_drift_.push_back(D * v.position - v.position);
      pending_.graph.mesh.vertices.push_back(vertex);
      if (v.object >= 0) {
        object_vertices_[v.object].push_back(static_cast<uint64_t>(robot_vertex_[w]));
        grown_objects_.insert(v.object);
      }
      addControlPoint(vertex.position.cast<double>(), t, agentId(k));
    }
    for (const uint32_t w : seen_now) {
      for (const uint32_t f : sensed_.vertex_faces[w]) {
        if (face_emitted_[f]) continue;
        const auto& face = sensed_.mesh.faces[f];
        if (robot_vertex_[face[0]] == kUnseen || robot_vertex_[face[1]] == kUnseen ||
            robot_vertex_[face[2]] == kUnseen)
          continue;
        face_emitted_[f] = true;
        pending_.graph.mesh.faces.push_back({static_cast<uint32_t>(robot_vertex_[face[0]]),
                                             static_cast<uint32_t>(robot_vertex_[face[1]]),
                                             static_cast<uint32_t>(robot_vertex_[face[2]])});
      }
    }
  }

  void addControlPoint(const Eigen::Vector3d& p, int64_t t, NodeId keyframe) {
    const Eigen::Vector3i key = (p / options_.control_point_spacing).array().floor().cast<int>();
    const auto tuple = std::make_tuple(key.x(), key.y(), key.z());
    if (control_points_.count(tuple)) return;
    const uint64_t id = control_points_.size();
    control_points_[tuple] = id;
    pending_.deformation.points.push_back({id, p, t, keyframe});
    for (int dz = -1; dz <= 1; ++dz) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const auto it =
              control_points_.find(std::make_tuple(key.x() + dx, key.y() + dy, key.z() + dz));
          if (it != control_points_.end() && it->second != id)
            pending_.deformation.edges.push_back({it->second, id});
        }
      }
    }
  }

  void addPlaces(size_t k, int64_t t, const Eigen::Isometry3d& D) {
    for (const size_t i : places_at_[k]) {
      const PlaceGraph::Place& truth = places_[i].place;
      const NodeId id('p', i);
      Node node = makeNode(id, Layer::kPlaces, D * truth.position);
      node.last_update_time_ns = t;
      std::get<PlaceAttributes>(node.attributes).distance = truth.distance;
      putNode(node);
      place_node_[i] = node.position;
      for (const PlaceGraph::Edge& e : place_edges_by_place_[i]) {
        const size_t other = e.a == i ? e.b : e.a;
        if (place_node_[other]) putEdge(NodeId('p', other), id, {e.weight, true});
      }
    }
  }

  // Makes the nearest place within parent_place_radius the parent of a node.
  void attachToPlace(NodeId child, const Eigen::Vector3d& position) {
    double best = options_.parent_place_radius;
    std::optional<size_t> parent;
    for (size_t i = 0; i < place_node_.size(); ++i) {
      if (!place_node_[i]) continue;
      const double d = (*place_node_[i] - position).norm();
      if (d < best) {
        best = d;
        parent = i;
      }
    }
    if (parent) putEdge(NodeId('p', *parent), child, {});
  }

  Node objectNode(NodeId id, uint32_t label, const Eigen::Vector3d& centroid,
                  const Eigen::Vector3d& half, int64_t t,
                  const std::vector<uint64_t>& vertices) const {
    Node node = makeNode(id, Layer::kObjects, centroid);
    node.last_update_time_ns = t;
    ObjectAttributes& object = std::get<ObjectAttributes>(node.attributes);
    object.semantic.label = label;
    if (const SemanticClass* c = sensed_.world.findClass(label)) {
      object.semantic.name = c->name;
      object.semantic.color = c->color;
    }
    object.semantic.bounding_box = BoundingBox{centroid - half, centroid + half};
    object.mesh_vertices = vertices;
    return node;
  }

  // Where the robot puts a true object: Hydra computes an object from its mesh vertices, so the
  // object carries the drift its vertices were placed with (the mean over them), which may be of
  // an earlier pass than the keyframe that completed the detection. Without vertices yet, the
  // drift of now.
  Eigen::Vector3d placedWithItsVertices(int true_id, const Eigen::Vector3d& true_centroid,
                                        const Eigen::Isometry3d& D) const {
    const auto it = object_vertices_.find(true_id);
    if (it == object_vertices_.end() || it->second.empty()) return D * true_centroid;
    Eigen::Vector3d drift = Eigen::Vector3d::Zero();
    for (const uint64_t v : it->second) drift += vertex_drift_[v];
    return true_centroid + drift / double(it->second.size());
  }

  void addObjects(size_t k, int64_t t, const Eigen::Isometry3d& D) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (const DetectedObject& d : detections_at_[k]) {
      const Eigen::Vector3d centroid = placedWithItsVertices(d.true_id, d.centroid, D);
      const Eigen::Vector3d half = 0.5 * (d.box.max - d.box.min);
      const NodeId id('O', next_object_++);
      Tracked tracked{id, d.label, centroid, half, d.centroid};
      const bool split = unit(rng_) < options_.split_probability &&
                         2.0 * half.head<2>().maxCoeff() >= options_.split_min_extent;
      const bool spurious = unit(rng_) < options_.spurious_probability;
      if (split) {
        // Two halves along the longer horizontal axis; merged later into the whole.
        int axis = 0;
        half.head<2>().maxCoeff(&axis);
        Eigen::Vector3d half_half = half, offset = Eigen::Vector3d::Zero();
        half_half[axis] *= 0.5;
        offset[axis] = half_half[axis];
        const NodeId second('O', next_object_++);
        putNode(
            objectNode(id, d.label, centroid - offset, half_half, t, object_vertices_[d.true_id]));
        putNode(objectNode(second, d.label, centroid + offset, half_half, t, {}));
        attachToPlace(id, centroid - offset);
        attachToPlace(second, centroid + offset);
        events_.push_back({t + static_cast<int64_t>(options_.split_merge_delay_s * 1e9),
                           Event::kMerge, id, second, d.true_id});
      } else {
        putNode(objectNode(id, d.label, centroid, half, t, object_vertices_[d.true_id]));
        attachToPlace(id, centroid);
      }
      tracked.whole = !split;
      tracked_[d.true_id] = tracked;
      if (spurious) {
        // A false detection beside it, of a look-alike class, deleted later.
        const double angle = 2.0 * M_PI * unit(rng_);
        const Eigen::Vector3d beside =
            centroid +
            (0.6 + 0.6 * unit(rng_)) * Eigen::Vector3d(std::cos(angle), std::sin(angle), 0);
        const NodeId ghost('O', next_object_++);
        putNode(objectNode(ghost, confusableLabel(d.label), beside, 0.5 * half, t, {}));
        attachToPlace(ghost, beside);
        events_.push_back({t + static_cast<int64_t>(options_.spurious_lifetime_s * 1e9),
                           Event::kDelete, ghost, ghost, -1});
      }
    }
  }

  void runScheduledObjectEvents(int64_t t) {
    for (auto it = events_.begin(); it != events_.end();) {
      if (it->due > t) {
        ++it;
        continue;
      }
      removeNode(it->second);
      if (it->kind == Event::kMerge) {
        Tracked& tracked = tracked_.at(it->true_id);
        tracked.whole = true;
        grown_objects_.insert(it->true_id);  // re-sent whole by refreshObjectVertices
      }
      it = events_.erase(it);
    }
  }

  // Objects whose mesh grew (or that were merged) are sent again with all their vertices, placed
  // with them.
  void refreshObjectVertices(int64_t t, const Eigen::Isometry3d& D) {
    for (const int true_id : grown_objects_) {
      const auto it = tracked_.find(true_id);
      if (it == tracked_.end() || !it->second.whole) continue;
      Tracked& o = it->second;
      o.centroid = placedWithItsVertices(true_id, o.true_centroid, D);
      putNode(objectNode(o.id, o.label, o.centroid, o.half, t, object_vertices_[true_id]));
    }
    grown_objects_.clear();
  }

  void addDescriptor(size_t k) {
    const Eigen::Isometry3d& T = run_.truth[k].T_world_body;
    KeyframeDescriptor descriptor = describeKeyframe(
        sensed_.textures, sensed_.space, run_.floors[k], T, agentId(k), run_.sensor.camera);
    std::normal_distribution<double> gauss(0.0, 1.0);
    for (Keypoint& keypoint : descriptor.keypoints) {
      const double depth = keypoint.position.cast<double>().norm();
      const double sigma =
          options_.keypoint_sigma_base + options_.keypoint_sigma_per_m2 * depth * depth;
      const Eigen::Vector3d noise(gauss(rng_), gauss(rng_), gauss(rng_));
      keypoint.position += (sigma * noise).cast<float>();
    }
    pending_.descriptors.push_back(std::move(descriptor));
  }

  void putNode(const Node& node) {
    pending_nodes_[node.id] = node;
    existing_.insert(node.id);
  }
  void putEdge(NodeId a, NodeId b, EdgeAttributes info) {
    pending_.graph.edges.push_back({a, b, info});
  }
  void removeNode(NodeId id) {
    existing_.erase(id);
    const bool only_pending = pending_nodes_.count(id) && !sent_.count(id);
    pending_nodes_.erase(id);
    // Edges of the node go with it: drop the pending ones; the station drops the sent ones.
    auto& edges = pending_.graph.edges;
    edges.erase(std::remove_if(edges.begin(), edges.end(),
                               [&](const Edge& e) { return e.source == id || e.target == id; }),
                edges.end());
    if (!only_pending) pending_.graph.removed_nodes.push_back(id);
  }

  void flush(int64_t t) {
    RobotUpdate& u = pending_;
    u.robot = run_.robot;
    u.sequence = updates_.size();
    u.time_ns = t;
    u.is_snapshot = updates_.empty();
    u.provided_layers = run_.sensor.providedLayers();
    u.graph.mesh.vertex_start = sent_vertices_;
    u.graph.mesh.face_start = sent_faces_;
    sent_vertices_ += u.graph.mesh.vertices.size();
    sent_faces_ += u.graph.mesh.faces.size();
    for (auto& [id, node] : pending_nodes_) {
      u.graph.nodes.push_back(std::move(node));
      sent_.insert(id);
    }
    pending_nodes_.clear();
    updates_.push_back(std::move(u));
    pending_ = RobotUpdate();
  }

  struct Tracked {
    NodeId id;
    uint32_t label = 0;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    Eigen::Vector3d half = Eigen::Vector3d::Zero();
    Eigen::Vector3d true_centroid = Eigen::Vector3d::Zero();  ///< world frame, with detection noise
    bool whole = true;
  };
  struct Event {
    int64_t due = 0;
    enum Kind { kMerge, kDelete } kind = kDelete;
    NodeId keep, second;  // kMerge: `second` merges into `keep`; kDelete: `second` goes
    int true_id = -1;
  };

  const SensedWorld& sensed_;
  const RobotRun& run_;
  const MapperOptions& options_;
  std::mt19937_64 rng_;
  std::vector<int64_t> robot_vertex_;  // world vertex -> robot vertex index
  std::vector<bool> face_emitted_;
  size_t num_vertices_ = 0;
  std::vector<Eigen::Vector3d>
      vertex_drift_;  ///< per robot vertex: where drift put it, minus truth
  uint64_t sent_vertices_ = 0, sent_faces_ = 0;
  std::map<std::tuple<int, int, int>, uint64_t> control_points_;
  std::vector<TimedPlaces::Place> places_;
  std::vector<std::vector<PlaceGraph::Edge>> place_edges_by_place_;
  std::vector<std::vector<size_t>> places_at_;
  std::vector<std::optional<Eigen::Vector3d>> place_node_;  // robot-frame position once sent
  std::vector<std::vector<DetectedObject>> detections_at_;
  std::vector<std::vector<SimulatedLoopClosure>> closures_at_;
  std::map<int, std::vector<uint64_t>> object_vertices_;  // true object -> robot vertices
  std::set<int> grown_objects_;
  std::map<int, Tracked> tracked_;
  std::vector<Event> events_;
  uint64_t next_object_ = 0;
  std::map<NodeId, Node> pending_nodes_;
  std::set<NodeId> existing_, sent_;
  RobotUpdate pending_;
  std::vector<RobotUpdate> updates_;
};

}  // namespace

std::vector<RobotUpdate> emulateRobotMap(const SensedWorld& sensed, const RobotRun& run,
                                         const MapperOptions& options) {
  std::vector<RobotUpdate> updates = RobotMapper(sensed, run, options).run();
  for (RobotUpdate& u : updates) {
    if (!options.send_keypoints) {
      for (KeyframeDescriptor& d : u.descriptors) d.keypoints.clear();
    }
    if (!options.send_own_loop_closures) {
      u.pose_graph.erase(std::remove_if(u.pose_graph.begin(), u.pose_graph.end(),
                                        [](const PoseGraphEdge& e) {
                                          return e.kind == PoseGraphEdge::Kind::kLoopClosure;
                                        }),
                         u.pose_graph.end());
    }
  }
  if (options.snapshot_every == 0) return updates;
  // Every snapshot_every-th update goes as the snapshot of the map so far.
  RobotStreamState sent;
  for (RobotUpdate& u : updates) {
    if (Status s = sent.add(u); !s)
      throw std::logic_error("robot " + run.robot.str() + "'s own stream: " + s.message());
    if (u.sequence > 0 && u.sequence % options.snapshot_every == 0) u = sent.snapshot();
  }
  return updates;
}

}  // namespace hydra_multi::sim
