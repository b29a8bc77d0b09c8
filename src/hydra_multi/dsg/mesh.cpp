#include "hydra_multi/dsg/mesh.h"

#include <string>

namespace hydra_multi {

Status validateMesh(const Mesh& mesh) {
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (!mesh.vertices[i].position.allFinite()) {
      return Error{"mesh vertex " + std::to_string(i) + ": position is not finite"};
    }
  }
  for (size_t i = 0; i < mesh.faces.size(); ++i) {
    for (const uint32_t v : mesh.faces[i]) {
      if (v >= mesh.vertices.size()) {
        return Error{"mesh face " + std::to_string(i) + ": vertex " + std::to_string(v) +
                     " does not exist (" + std::to_string(mesh.vertices.size()) + " vertices)"};
      }
    }
  }
  return Status::Ok();
}

}  // namespace hydra_multi
