#include "hydra_multi/backend/optimized_map.h"

#include <algorithm>
#include <limits>

#include "hydra_multi/core/nearest_neighbors.h"

namespace hydra_multi {

SceneGraph unplacedMap(const SceneGraph& frontend,
                       const std::vector<RobotDeformationInput>& robots) {
  SceneGraph graph;
  size_t vertices = 0, faces = 0;
  for (const RobotDeformationInput& robot : robots) {
    if (robot.mesh == nullptr) continue;
    vertices += robot.mesh->vertices.size();
    faces += robot.mesh->faces.size();
  }
  graph.mesh().vertices.reserve(vertices);
  graph.mesh().faces.reserve(faces);
  for (const RobotDeformationInput& robot : robots) {
    const uint64_t vertex_offset = graph.mesh().vertices.size();
    if (robot.mesh != nullptr) {
      graph.mesh().vertices.insert(graph.mesh().vertices.end(), robot.mesh->vertices.begin(),
                                   robot.mesh->vertices.end());
      for (MeshFace f : robot.mesh->faces) {
        for (uint32_t& i : f) i += static_cast<uint32_t>(vertex_offset);
        graph.mesh().faces.push_back(f);
      }
    }
    const bool posed = !frontend.nodesOfRobot(robot.robot, Layer::kAgents).empty();
    for (const Node* robot_node : frontend.robotNodes(robot.robot)) {
      const Node& node = *robot_node;
      if (node.layer() == Layer::kAgents || node.layer() == Layer::kPlaces) {
        if (posed) graph.addOrUpdateNode(node);
      } else if (node.find<ObjectAttributes>() != nullptr) {
        Node object = node;
        for (uint64_t& v : object.find<ObjectAttributes>()->mesh_vertices) v += vertex_offset;
        graph.addOrUpdateNode(std::move(object));
      }  // rooms and buildings are the backend's own
    }
  }
  for (const auto& [key, info] : frontend.edges()) {
    if (graph.hasNode(key.first()) && graph.hasNode(key.second()))
      graph.addOrUpdateEdge(key.first(), key.second(), info);
  }
  return graph;
}

void placeMap(SceneGraph& map, const SceneGraph& frontend,
              const std::vector<RobotDeformationInput>& robots, const DeformationGraph& deformation,
              const std::map<NodeId, Eigen::Isometry3d>& poses,
              const DeformationGraphOptions& options, size_t mesh_neighbours,
              std::map<RobotId, Eigen::Isometry3d>* first_keyframes,
              std::map<RobotId, MeshBinding>* bindings, std::map<NodeId, Placement>* placements) {
  if (first_keyframes != nullptr) first_keyframes->clear();
  if (bindings != nullptr) {
    // Robots no longer aligned leave.
    for (auto it = bindings->begin(); it != bindings->end();) {
      const bool aligned = std::any_of(robots.begin(), robots.end(),
                                       [&](const auto& r) { return r.robot == it->first; });
      it = aligned ? std::next(it) : bindings->erase(it);
    }
  }
  uint64_t vertex_offset = 0;
  for (const RobotDeformationInput& robot : robots) {
    const Eigen::Isometry3d& T = robot.T_global_robot;
    // Control points before and after, for the mesh and for objects without vertices.
    std::vector<Eigen::Isometry3d> cp_initial, cp_optimized;
    std::vector<Eigen::Vector3d> cp_local;
    std::vector<int64_t> cp_times;
    if (robot.control_points != nullptr) {
      for (const ControlPoint& cp : *robot.control_points) {
        const NodeId id = controlPointId(robot.robot, cp.id);
        const auto a = deformation.initial.find(id);
        const auto b = poses.find(id);
        if (a == deformation.initial.end() || b == poses.end()) continue;
        cp_initial.push_back(a->second);
        cp_optimized.push_back(b->second);
        cp_local.push_back(cp.position);
        cp_times.push_back(cp.time_ns);
      }
    }
    // The mesh: aligned, then deformed (bound in the robot's frame, kept when `bindings`); its
    // vertices' positions before (`aligned`) and after (`moved`).
    std::vector<Eigen::Vector3f> aligned, moved;
    if (robot.mesh != nullptr) {
      aligned.reserve(robot.mesh->vertices.size());
      for (const MeshVertex& v : robot.mesh->vertices)
        aligned.push_back((T * v.position.cast<double>()).cast<float>());
      MeshBinding fresh;
      MeshBinding& binding = bindings != nullptr ? (*bindings)[robot.robot] : fresh;
      bindMesh(binding, robot.mesh->vertices, cp_local, cp_times, options.link_max_dt_s,
               mesh_neighbours);
      moved = blendMesh(binding, aligned, cp_initial, cp_optimized);
      for (size_t i = 0; i < moved.size(); ++i)
        map.mesh().vertices[vertex_offset + i].position = moved[i];
      vertex_offset += robot.mesh->vertices.size();
    }
    std::vector<Eigen::Vector3d> cp_centres;
    for (const Eigen::Isometry3d& c : cp_initial) cp_centres.push_back(c.translation());
    const TimedNeighbors near_cp(cp_centres, cp_times, windowNs(options.link_max_dt_s));
    int64_t first_time = std::numeric_limits<int64_t>::max();
    for (const Node* robot_node : frontend.robotNodes(robot.robot)) {
      const NodeId id = robot_node->id;
      Node* placed = map.findMutableNode(id);
      Placement* record = nullptr;
      if (placements != nullptr) {
        const auto it = placements->find(id);
        if (it != placements->end()) record = &it->second;
      }
      if (placed == nullptr && record == nullptr) continue;  // rooms, buildings, nodes not solved
      const Node& node = *robot_node;
      if (node.layer() == Layer::kAgents || node.layer() == Layer::kPlaces) {
        const auto pose = poses.find(id);
        if (pose == poses.end()) {
          if (placed != nullptr) map.removeNode(id);
          continue;
        }
        const Eigen::Vector3d position = pose->second.translation();
        if (record != nullptr) {
          const SemanticAttributes* semantic = node.semantic();  // none for keyframes
          *record = {position, semantic ? semantic->bounding_box : std::nullopt};
        }
        if (placed == nullptr) continue;
        placed->position = position;
        if (AgentAttributes* agent = placed->find<AgentAttributes>()) {
          agent->orientation = Eigen::Quaterniond(pose->second.linear()).normalized();
          if (agent->timestamp_ns < first_time) {
            first_time = agent->timestamp_ns;
            if (first_keyframes != nullptr) (*first_keyframes)[robot.robot] = pose->second;
          }
        }
      } else if (const ObjectAttributes* object = node.find<ObjectAttributes>()) {
        // Moved as its mesh vertices moved, or as its nearest control point moved.
        const Eigen::Vector3d aligned_position = T * node.position;
        Eigen::Vector3d shift = Eigen::Vector3d::Zero();
        size_t counted = 0;
        for (const uint64_t v : object->mesh_vertices) {
          if (v >= moved.size()) continue;
          shift += (moved[v] - aligned[v]).cast<double>();
          ++counted;
        }
        if (counted > 0) {
          shift /= double(counted);
        } else if (!cp_centres.empty()) {
          const size_t c =
              near_cp.nearest(aligned_position, node.last_update_time_ns).front().index;
          shift = cp_optimized[c] * (cp_initial[c].inverse() * aligned_position) - aligned_position;
        }
        Placement placement{aligned_position + shift, object->semantic.bounding_box};
        if (placement.box) {
          const Eigen::Vector3d half = 0.5 * (placement.box->max - placement.box->min);
          placement.box = BoundingBox{placement.position - half, placement.position + half};
        }
        if (record != nullptr) *record = placement;
        if (placed != nullptr) {
          placed->position = placement.position;
          placed->semantic()->bounding_box = placement.box;
        }
      }
    }
  }
}

}  // namespace hydra_multi
