#pragma once
// Procedural buildings: on every floor a straight corridor with rooms on both sides, one door per
// room onto the corridor (two for a wide open space), and furniture by room kind. The far side
// may instead hold a few large open-plan rooms; on buildings of several floors the last room of
// the near side is a stairwell on every floor, with stairs between each floor and the next.
// Furniture is placed in a room frame (origin at the room's centre, x along the corridor, y away
// from the door) by rejection sampling without overlaps and clear of the door, so rooms that share
// a layout are identical in that frame: the perceptual aliasing of the paper's Simmons data.

#include <cstdint>

#include "hydra_multi/core/result.h"
#include "hydra_multi/sim/world.h"

namespace hydra_multi::sim {

struct BuildingOptions {
  int floors = 1;
  int rooms_per_side = 6;
  double room_width = 4.0;      ///< along the corridor (m)
  double room_depth = 5.0;      ///< away from the corridor (m)
  double corridor_width = 2.0;  ///< (m)
  double wall_thickness = 0.15;
  double floor_height = 3.0;  ///< floor to ceiling (m); floors are stacked with a 0.3 m slab
  RoomKind room_kind = RoomKind::kOffice;
  /// The far side (y > corridor) holds this many open-plan rooms instead of rooms_per_side rooms.
  int open_spaces = 0;
  /// Depth of the far side's rooms (m); 0: room_depth.
  double far_side_depth = 0.0;
  /// Every n-th room (n > 0) is a kitchen instead; 0: none.
  int kitchen_every = 0;
  /// This many further rooms per floor, at slots drawn from the seed, are kitchens (the common
  /// rooms of a dormitory floor, which sit where the plan puts them, not at a fixed period).
  int random_kitchens = 0;
  /// One furniture layout and wall texture for all rooms of room_kind (aliasing, like the
  /// identical student rooms of the paper's dormitory); kitchens and open spaces keep their own.
  bool identical_rooms = false;
  uint64_t seed = 1;

  /// Checks the numbers; the message names the first bad one.
  Status validate() const;
};

Result<World> generateBuilding(const BuildingOptions& options);

}  // namespace hydra_multi::sim
