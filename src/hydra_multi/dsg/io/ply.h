#pragma once
// Mesh export to PLY (binary little-endian), which common mesh viewers open (MeshLab, CloudCompare,
// Blender, Open3D). Vertices carry x y z (float), red green blue (uchar) and two extra properties
// that viewers ignore: label (uint, 4294967295 for none) and robot (uchar). Faces are triangles
// as a uchar-counted list of int vertex indices.

#include <string>

#include "hydra_multi/dsg/mesh.h"

namespace hydra_multi::io {

std::string meshToPly(const Mesh& mesh);

}  // namespace hydra_multi::io
