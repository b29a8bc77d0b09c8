#include "hydra_multi/sim/robot_mapper.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <stdexcept>
#include <tuple>

#include "hydra_multi/dsg/robot_stream.h"
#include "hydra_multi/sim/robot_mapper_detail.h"
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

namespace detail {

RobotMapper::RobotMapper(const SensedWorld& sensed, const RobotRun& run,
                         const MapperOptions& options)
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
    for (const DetectedObject& d : detectObjects(sensed.world, sensed.space, run.floors, run.truth,
                                                 run.sensor.camera, options.detection)) {
      detections_at_[d.first_keyframe].push_back(d);
    }
  }
  closures_at_.resize(run.truth.size());
  for (const SimulatedLoopClosure& c : run.loop_closures) {
    if (c.to < run.truth.size()) closures_at_[c.to].push_back(c);
  }
}

std::vector<RobotUpdate> RobotMapper::run() {
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

Eigen::Isometry3d RobotMapper::drift(size_t k) const {
  return run_.odometry[k] * run_.truth[k].T_world_body.inverse();
}

void RobotMapper::step(size_t k) {
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

void RobotMapper::addKeyframe(size_t k, int64_t t) {
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

void RobotMapper::addDescriptor(size_t k) {
  const Eigen::Isometry3d& T = run_.truth[k].T_world_body;
  KeyframeDescriptor descriptor = describeKeyframe(sensed_.textures, sensed_.space, run_.floors[k],
                                                   T, agentId(k), run_.sensor.camera);
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

void RobotMapper::putNode(const Node& node) {
  pending_nodes_[node.id] = node;
  existing_.insert(node.id);
}

void RobotMapper::putEdge(NodeId a, NodeId b, EdgeAttributes info) {
  pending_.graph.edges.push_back({a, b, info});
}

void RobotMapper::removeNode(NodeId id) {
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

void RobotMapper::flush(int64_t t) {
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

}  // namespace detail

std::vector<RobotUpdate> emulateRobotMap(const SensedWorld& sensed, const RobotRun& run,
                                         const MapperOptions& options) {
  std::vector<RobotUpdate> updates = detail::RobotMapper(sensed, run, options).run();
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
