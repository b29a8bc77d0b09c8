#pragma once
// A digest of what the station's frontend holds of the robots (the crash test compares a restarted
// station with an uninterrupted one by it): FNV-1a, 64 bits, over the frontend's scene graph in its
// binary encoding (dsg/io/binary_format.h, nodes and edges in id order) and, per robot in id order,
// its pose graph, control points, control-point edges and mesh, every number by its bytes.
// Invariant: it depends only on the updates applied per robot, in each robot's sequence order, not
// on how the robots' updates interleaved; the loop-closure detector's state is not in it.

#include <cstdint>
#include <string>

#include "hydra_multi/frontend/scene_graph_processor.h"

namespace hydra_multi {

uint64_t frontendDigest(const SceneGraphProcessor& processor);

/// The digest as 16 hexadecimal digits.
std::string digestHex(uint64_t digest);

}  // namespace hydra_multi
