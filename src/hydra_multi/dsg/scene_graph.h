#pragma once
// SceneGraph: the layered 3D scene graph of DESIGN.md (agents, objects, places, rooms, buildings
// and a mesh), with undirected weighted edges. Inside a layer edges join siblings; across layers
// the node of the higher level is the parent, and a node has at most one parent (a new parent edge
// replaces the old one, as Spark-DSG's single-parent rule does).
//
// Misuse by the caller (an edge to a node that does not exist, a node that changes layer) throws
// std::invalid_argument: it is a bug. Input from robots and files is checked before it reaches the
// graph (applyDelta, the decoders), so bad input never gets here.

#include <map>
#include <optional>
#include <set>
#include <unordered_map>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/dsg/edge.h"
#include "hydra_multi/dsg/mesh.h"
#include "hydra_multi/dsg/node.h"

namespace hydra_multi {

/// A node's position and box, as a merge fuses them (mergeNodes): positions averaged, boxes united
/// (a missing box takes the other's).
struct Placement {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  std::optional<BoundingBox> box;
};
Placement fusedPlacement(const Placement& target, const Placement& source);

/// What mergeNodes() did, so that undoMerge() can take it back.
struct MergeRecord {
  Node target_before;                   ///< the target as it was before the merge
  Node source;                          ///< the node that was merged away
  std::vector<Edge> source_edges;       ///< every edge the source had
  std::vector<NodeId> moved_to_target;  ///< neighbours whose edge to the target the merge created
};

class SceneGraph {
 public:
  SceneGraph() = default;
  SceneGraph(const SceneGraph& other);
  SceneGraph(SceneGraph&&) = default;
  SceneGraph& operator=(const SceneGraph& other);
  SceneGraph& operator=(SceneGraph&&) = default;

  // --- nodes ---
  /// Adds the node, or replaces the node with the same id; returns true when it was added.
  /// Throws std::invalid_argument when a node with this id exists in another layer.
  bool addOrUpdateNode(Node node);
  /// Removes the node and its edges; false when there is no such node.
  bool removeNode(NodeId id);
  bool hasNode(NodeId id) const { return index_.count(id) != 0; }
  const Node* findNode(NodeId id) const;
  /// The node; throws std::out_of_range when absent.
  const Node& getNode(NodeId id) const;
  /// Mutable access to a node's attributes; the caller must not change its id or its layer.
  Node* findMutableNode(NodeId id);

  // --- edges ---
  /// Adds the edge a-b or updates its attributes; returns true when it was added. Throws
  /// std::invalid_argument for a missing endpoint, a self-loop, or layers that may not be joined.
  bool addOrUpdateEdge(NodeId a, NodeId b, EdgeAttributes info = {});
  bool removeEdge(NodeId a, NodeId b);
  bool hasEdge(NodeId a, NodeId b) const { return edges_.count(EdgeKey(a, b)) != 0; }
  const EdgeAttributes* findEdge(NodeId a, NodeId b) const;

  // --- queries ---
  /// Neighbours in the same layer (siblings).
  std::vector<NodeId> neighbours(NodeId id) const;
  /// Every node joined to this one, in any layer.
  std::vector<NodeId> adjacent(NodeId id) const;
  std::optional<NodeId> parent(NodeId id) const;
  std::vector<NodeId> children(NodeId id) const;
  std::vector<NodeId> nodesInLayer(Layer layer) const;
  /// Nodes of a robot: its agent poses, and station nodes whose source it is.
  std::vector<NodeId> nodesOfRobot(RobotId robot) const;
  /// The same nodes, in the same order (valid while they stay in the graph).
  std::vector<const Node*> robotNodes(RobotId robot) const;
  /// Those of them in one layer.
  std::vector<NodeId> nodesOfRobot(RobotId robot, Layer layer) const;
  /// Robots that own a node or a mesh vertex, in order.
  std::vector<RobotId> robots() const;
  size_t numNodes() const { return nodes_.size(); }
  size_t numNodes(Layer layer) const;
  /// How many nodesOfRobot(robot, layer) gives, without the copy.
  size_t numNodes(RobotId robot, Layer layer) const;
  size_t numEdges() const { return edges_.size(); }
  const std::map<NodeId, Node>& nodes() const { return nodes_; }
  const std::map<EdgeKey, EdgeAttributes>& edges() const { return edges_; }

  Mesh& mesh() { return mesh_; }
  const Mesh& mesh() const { return mesh_; }

  // --- merging ---
  /// Merges node `source` into node `target` (same layer, not agents): the edges of the source move
  /// to the target (the target keeps its own parent if it has one), the attributes are fused
  /// (positions averaged, boxes and mesh vertices united, the target's label and name kept), and
  /// the source is removed. `record` (may be null): where what the merge did is written, for
  /// undoMerge(). Throws std::invalid_argument on misuse.
  void mergeNodes(NodeId target, NodeId source, MergeRecord* record = nullptr);
  /// Takes a merge back: the target gets its attributes from before the merge, loses the edges the
  /// merge gave it, and the source comes back with the edges whose other end still exists. Fails
  /// (and changes nothing) when the target is gone or the source id is in use again.
  Status undoMerge(const MergeRecord& record);

  bool operator==(const SceneGraph& other) const;
  bool operator!=(const SceneGraph& other) const { return !(*this == other); }

 private:
  std::map<NodeId, Node> nodes_;
  // Every node of nodes_ by id, hashed: lookups without a walk down the tree (std::map keeps a
  // node's address until it is erased; a copy re-points the index at its own nodes).
  std::unordered_map<NodeId, Node*> index_;
  std::map<EdgeKey, EdgeAttributes> edges_;
  std::unordered_map<NodeId, std::set<NodeId>> adjacency_;
  // Node ids by robot and by layer (a node's id and layer never change): nodesOfRobot and
  // nodesInLayer without a pass over every node. A robot's nodes in one array sorted by id, copied
  // out at once (a node added or removed moves the larger ones of its robot); a copy re-points
  // them at its own nodes.
  std::map<RobotId, std::vector<std::pair<NodeId, Node*>>> by_robot_;
  std::map<std::pair<RobotId, Layer>, std::set<NodeId>> by_robot_layer_;
  std::map<Layer, std::set<NodeId>> by_layer_;
  Mesh mesh_;
};

}  // namespace hydra_multi
