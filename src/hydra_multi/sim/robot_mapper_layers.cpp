#include <algorithm>
#include <cmath>
#include <set>

#include "hydra_multi/sim/robot_mapper_detail.h"
#include "hydra_multi/sim/visibility.h"

namespace hydra_multi::sim::detail {

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

bool RobotMapper::inView(const Eigen::Isometry3d& T_world_body, const Eigen::Vector3d& p) const {
  const Eigen::Vector3d b = T_world_body.inverse() * p;
  const double horizontal = std::hypot(b.x(), b.y());
  if (run_.sensor.mesh_horizontal_fov_deg < 360.0 &&
      std::abs(std::atan2(b.y(), b.x())) > 0.5 * run_.sensor.mesh_horizontal_fov_deg * M_PI / 180)
    return false;
  return std::abs(std::atan2(b.z(), horizontal)) <=
         0.5 * run_.sensor.mesh_vertical_fov_deg * M_PI / 180.0;
}

void RobotMapper::observeMesh(size_t k, int64_t t, const Eigen::Isometry3d& D) {
  const Eigen::Isometry3d& T = run_.truth[k].T_world_body;
  const int floor = run_.floors[k];
  const FloorGrid& grid = sensed_.space.floors.at(static_cast<size_t>(floor));
  const Eigen::Vector2d eye = T.translation().head<2>();
  std::normal_distribution<double> gauss(0.0, options_.mesh_noise_sigma);
  std::vector<uint32_t> seen_now;
  for (const auto& n : sensed_.mesh_index->withinRadius(T.translation(), run_.sensor.mesh_range)) {
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

void RobotMapper::addControlPoint(const Eigen::Vector3d& p, int64_t t, NodeId keyframe) {
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

void RobotMapper::addPlaces(size_t k, int64_t t, const Eigen::Isometry3d& D) {
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

void RobotMapper::attachToPlace(NodeId child, const Eigen::Vector3d& position) {
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

Node RobotMapper::objectNode(NodeId id, uint32_t label, const Eigen::Vector3d& centroid,
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

Eigen::Vector3d RobotMapper::placedWithItsVertices(int true_id,
                                                   const Eigen::Vector3d& true_centroid,
                                                   const Eigen::Isometry3d& D) const {
  const auto it = object_vertices_.find(true_id);
  if (it == object_vertices_.end() || it->second.empty()) return D * true_centroid;
  Eigen::Vector3d drift = Eigen::Vector3d::Zero();
  for (const uint64_t v : it->second) drift += vertex_drift_[v];
  return true_centroid + drift / double(it->second.size());
}

void RobotMapper::addObjects(size_t k, int64_t t, const Eigen::Isometry3d& D) {
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

void RobotMapper::runScheduledObjectEvents(int64_t t) {
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

void RobotMapper::refreshObjectVertices(int64_t t, const Eigen::Isometry3d& D) {
  for (const int true_id : grown_objects_) {
    const auto it = tracked_.find(true_id);
    if (it == tracked_.end() || !it->second.whole) continue;
    Tracked& o = it->second;
    o.centroid = placedWithItsVertices(true_id, o.true_centroid, D);
    putNode(objectNode(o.id, o.label, o.centroid, o.half, t, object_vertices_[true_id]));
  }
  grown_objects_.clear();
}

}  // namespace hydra_multi::sim::detail
