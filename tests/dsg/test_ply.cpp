#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "hydra_multi/dsg/io/ply.h"
#include "support/random_graphs.h"

namespace hydra_multi::io {
namespace {

// The PLY header declares what follows, and the binary body holds exactly those vertices and faces
// (read back here independently of the writer).
TEST(Ply, HeaderAndBodyAgree) {
  std::mt19937 rng(51);
  const Mesh mesh = testing::makeRandomGraph(rng, {0, 0, 0, 0, 50, 70}).mesh();
  const std::string ply = meshToPly(mesh);
  const size_t end = ply.find("end_header\n");
  ASSERT_NE(end, std::string::npos);
  const std::string header = ply.substr(0, end);
  EXPECT_EQ(header.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);
  EXPECT_NE(header.find("element vertex 50\n"), std::string::npos);
  EXPECT_NE(header.find("element face 70\n"), std::string::npos);
  EXPECT_NE(header.find("property list uchar int vertex_indices"), std::string::npos);

  const size_t vertex_bytes = 3 * 4 + 3 + 4 + 1;
  const size_t face_bytes = 1 + 3 * 4;
  const char* body = ply.data() + end + std::strlen("end_header\n");
  ASSERT_EQ(ply.size() - (end + 11), 50 * vertex_bytes + 70 * face_bytes);
  for (size_t i = 0; i < 50; ++i) {
    float xyz[3];
    std::memcpy(xyz, body + i * vertex_bytes, sizeof xyz);
    EXPECT_EQ(Eigen::Vector3f(xyz[0], xyz[1], xyz[2]), mesh.vertices[i].position);
    EXPECT_EQ(static_cast<uint8_t>(body[i * vertex_bytes + 12]), mesh.vertices[i].color.r);
  }
  const char* faces = body + 50 * vertex_bytes;
  for (size_t f = 0; f < 70; ++f) {
    EXPECT_EQ(faces[f * face_bytes], 3);
    int32_t index[3];
    std::memcpy(index, faces + f * face_bytes + 1, sizeof index);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(static_cast<uint32_t>(index[k]), mesh.faces[f][k]);
  }
}

}  // namespace
}  // namespace hydra_multi::io
