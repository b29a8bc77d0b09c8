#pragma once
// The emulated robot's mapping process behind emulateRobotMap (robot_mapper.h), one per run: what
// it has observed and sent so far. Its keyframes, descriptors, loop closures and update stream are
// in robot_mapper.cpp; what it makes of the world's mesh, places and objects in
// robot_mapper_layers.cpp.

#include <map>
#include <optional>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include "hydra_multi/sim/robot_mapper.h"

namespace hydra_multi::sim::detail {

inline constexpr int64_t kUnseen = -1;

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
                        const PlacesOptions& options);

class RobotMapper {
 public:
  RobotMapper(const SensedWorld& sensed, const RobotRun& run, const MapperOptions& options);

  std::vector<RobotUpdate> run();

 private:
  NodeId agentId(size_t k) const { return NodeId(run_.robot.prefix(), k); }
  // World -> robot frame at keyframe k.
  Eigen::Isometry3d drift(size_t k) const;

  void step(size_t k);

  void addKeyframe(size_t k, int64_t t);

  bool inView(const Eigen::Isometry3d& T_world_body, const Eigen::Vector3d& p) const;

  void observeMesh(size_t k, int64_t t, const Eigen::Isometry3d& D);

  void addControlPoint(const Eigen::Vector3d& p, int64_t t, NodeId keyframe);

  void addPlaces(size_t k, int64_t t, const Eigen::Isometry3d& D);

  // Makes the nearest place within parent_place_radius the parent of a node.
  void attachToPlace(NodeId child, const Eigen::Vector3d& position);

  Node objectNode(NodeId id, uint32_t label, const Eigen::Vector3d& centroid,
                  const Eigen::Vector3d& half, int64_t t,
                  const std::vector<uint64_t>& vertices) const;

  // Where the robot puts a true object: Hydra computes an object from its mesh vertices, so the
  // object carries the drift its vertices were placed with (the mean over them), which may be of
  // an earlier pass than the keyframe that completed the detection. Without vertices yet, the
  // drift of now.
  Eigen::Vector3d placedWithItsVertices(int true_id, const Eigen::Vector3d& true_centroid,
                                        const Eigen::Isometry3d& D) const;

  void addObjects(size_t k, int64_t t, const Eigen::Isometry3d& D);

  void runScheduledObjectEvents(int64_t t);

  // Objects whose mesh grew (or that were merged) are sent again with all their vertices, placed
  // with them.
  void refreshObjectVertices(int64_t t, const Eigen::Isometry3d& D);

  void addDescriptor(size_t k);

  void putNode(const Node& node);
  void putEdge(NodeId a, NodeId b, EdgeAttributes info);
  void removeNode(NodeId id);

  void flush(int64_t t);

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

}  // namespace hydra_multi::sim::detail
