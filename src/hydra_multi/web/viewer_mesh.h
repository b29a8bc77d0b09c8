#pragma once
// The mesh as the viewer page reads it (docs/VIEWER.md "Mesh"), little-endian: u32 header length,
// the header (JSON: {seq, vertices, faces, robots: {robot: [v_start, v, f_start, f]}}) padded with
// spaces to a multiple of 4 bytes, then f32 positions (3 per vertex), u8 colours (3 per vertex,
// zero-padded to 4 bytes), u32 labels (one per vertex, 2^32-1 for none), u32 faces (3 per face).

#include <cstdint>
#include <string>

#include "hydra_multi/core/result.h"
#include "hydra_multi/dsg/mesh.h"

namespace hydra_multi::web {

std::string encodeViewerMesh(const Mesh& mesh, uint64_t seq);

/// The inverse (for tests and `view`'s checks): an error names what is short or out of range.
Result<Mesh> decodeViewerMesh(const std::string& bytes, uint64_t* seq = nullptr);

}  // namespace hydra_multi::web
