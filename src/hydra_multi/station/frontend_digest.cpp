#include "hydra_multi/station/frontend_digest.h"

#include <cstdio>
#include <type_traits>

#include "hydra_multi/dsg/io/binary_format.h"

namespace hydra_multi {
namespace {

class Fnv1a {
 public:
  void bytes(const void* data, size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t k = 0; k < size; ++k) {
      hash_ ^= p[k];
      hash_ *= 0x100000001b3ull;
    }
  }
  template <typename T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes(&v, sizeof(T));
  }
  template <typename Derived>
  void matrix(const Eigen::MatrixBase<Derived>& m) {
    for (Eigen::Index r = 0; r < m.rows(); ++r)
      for (Eigen::Index c = 0; c < m.cols(); ++c) value(m(r, c));
  }
  uint64_t result() const { return hash_; }

 private:
  uint64_t hash_ = 0xcbf29ce484222325ull;
};

}  // namespace

uint64_t frontendDigest(const SceneGraphProcessor& processor) {
  Fnv1a h;
  const std::string graph = io::encodeSceneGraphBinary(processor.graph());
  h.value(graph.size());
  h.bytes(graph.data(), graph.size());
  for (const RobotId robot : processor.robots()) {
    const RobotFrontendState* state = processor.robot(robot);
    if (state == nullptr) continue;
    h.value(robot.index());
    h.value(state->pose_graph.size());
    for (const PoseGraphEdge& e : state->pose_graph) {
      h.value(e.from.value());
      h.value(e.to.value());
      h.value(e.kind);
      h.matrix(e.T_from_to.matrix());
      h.matrix(e.information);
    }
    h.value(state->control_points.size());
    for (const ControlPoint& p : state->control_points) {
      h.value(p.id);
      h.matrix(p.position);
      h.value(p.time_ns);
      h.value(p.keyframe.value());
    }
    h.value(state->control_point_edges.size());
    for (const ControlPointEdge& e : state->control_point_edges) {
      h.value(e.from);
      h.value(e.to);
    }
    h.value(state->mesh.vertices.size());
    for (const MeshVertex& v : state->mesh.vertices) {
      h.matrix(v.position);
      h.value(v.color.r);
      h.value(v.color.g);
      h.value(v.color.b);
      h.value(v.label);
      h.value(v.robot.index());
      h.value(v.time_ns);
    }
    h.value(state->mesh.faces.size());
    for (const MeshFace& f : state->mesh.faces) h.value(f);
  }
  return h.result();
}

std::string digestHex(uint64_t digest) {
  char text[17];
  std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(digest));
  return text;
}

}  // namespace hydra_multi
