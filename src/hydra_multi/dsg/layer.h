#pragma once
// The layers of a 3D scene graph. The numeric level is Hydra's layer id (agents and objects share
// level 2); across levels the higher one is the parent.

#include <array>
#include <cstdint>
#include <optional>
#include <string>

namespace hydra_multi {

enum class Layer : uint8_t { kAgents = 0, kObjects = 1, kPlaces = 2, kRooms = 3, kBuildings = 4 };

inline constexpr std::array<Layer, 5> kAllLayers = {Layer::kAgents, Layer::kObjects, Layer::kPlaces,
                                                    Layer::kRooms, Layer::kBuildings};

/// Hydra's layer id: agents 2, objects 2, places 3, rooms 4, buildings 5.
int layerLevel(Layer layer);
/// "agents", "objects", "places", "rooms", "buildings".
const char* layerName(Layer layer);
std::optional<Layer> layerFromName(const std::string& name);
/// The id category character of nodes of this layer ('O', 'p', 'R', 'B'); agents use their
/// robot's prefix letter instead, so this returns 'a' for them.
char layerCategory(Layer layer);

/// Whether an edge may join nodes of these layers: the same layer (an intra-layer edge) or two
/// different levels (the higher is the parent). Agents and objects share a level and are not
/// joined.
bool isValidEdge(Layer a, Layer b);

}  // namespace hydra_multi
