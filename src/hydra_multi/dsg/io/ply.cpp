#include "hydra_multi/dsg/io/ply.h"

#include "hydra_multi/dsg/io/byte_codec.h"

namespace hydra_multi::io {

std::string meshToPly(const Mesh& mesh) {
  ByteWriter w;
  w.raw("ply\nformat binary_little_endian 1.0\ncomment written by hydra-multi\n");
  w.raw("element vertex " + std::to_string(mesh.vertices.size()) + "\n");
  w.raw("property float x\nproperty float y\nproperty float z\n");
  w.raw("property uchar red\nproperty uchar green\nproperty uchar blue\n");
  w.raw("property uint label\nproperty uchar robot\n");
  w.raw("element face " + std::to_string(mesh.faces.size()) + "\n");
  w.raw("property list uchar int vertex_indices\nend_header\n");
  for (const MeshVertex& v : mesh.vertices) {
    for (int i = 0; i < 3; ++i) w.f32(v.position[i]);
    w.u8(v.color.r);
    w.u8(v.color.g);
    w.u8(v.color.b);
    w.u32(v.label);
    w.u8(v.robot.index());
  }
  for (const MeshFace& face : mesh.faces) {
    w.u8(3);
    for (const uint32_t index : face) w.u32(index);
  }
  return w.release();
}

}  // namespace hydra_multi::io
