#pragma once
// Room segmentation over the places layer (Hydra, Hughes et al. 2023; DESIGN.md "Room
// segmentation"): rooms are the parts of free space that stay connected when the narrow passages
// (doors) are cut.
//   1. For each of `thresholds` values t evenly over [min_threshold, max_threshold], keep the
//      places with free-space radius > t and the place edges with weight > t; the connected
//      components with at least min_room_places places are candidate room seeds.
//   2. Take the threshold with the most seeds (Rule::kMost, the smallest such threshold), or
//      DESIGN.md's: the one whose number of seeds is the median over all thresholds (kMedian).
//   3. Grow the seeds to every other place they reach over the places graph, each place going
//      to the seed nearest along the graph (Dijkstra from all seeds at once, Euclidean lengths).
//   4. Join grown rooms that a place edge of clearance above max_door_radius connects: the
//      opening between them is wider than a door.
// Rooms get a room node at the mean of their places, and every room the building node as parent.
//
// The defaults depart from DESIGN.md's (the median threshold, seeds of 10 places, no joining):
// docs/DECISIONS.md "Rooms from the most seeds, joined across openings wider than a door".
// config/hydra-rooms.json restores DESIGN.md's rule.

#include <vector>

#include "hydra_multi/dsg/scene_graph.h"

namespace hydra_multi {

struct RoomSegmentationOptions {
  int thresholds = 12;  ///< Hydra: 12 values over 0.43-1.2 m
  double min_threshold = 0.43;
  double max_threshold = 1.2;
  size_t min_room_places = 5;  ///< DESIGN.md, Hydra: 10
  /// Which threshold: the one whose seed count is the median over all (kMedian, DESIGN.md's), or
  /// the one with the most seeds (kMost); the smallest such threshold either way.
  enum class Rule { kMedian, kMost } rule = Rule::kMost;
  /// Two grown rooms joined by a place edge whose clearance (weight) is above this are one room:
  /// the opening between them is wider than a door (2 x this). 0: rooms are never joined
  /// (DESIGN.md's). An unweighted edge joins nothing.
  double max_door_radius = 0.55;
};

struct RoomSegmentation {
  double threshold = 0.0;                  ///< the one chosen
  std::vector<std::vector<NodeId>> rooms;  ///< places of each room, sorted
  std::vector<size_t> seeds_per_threshold;
};

RoomSegmentation segmentRooms(const SceneGraph& graph, const RoomSegmentationOptions& options = {});

/// Replaces the graph's rooms and buildings: a room node R(i) per room, parent of its places, and
/// one building node B(0), parent of the rooms.
void applyRooms(SceneGraph& graph, const RoomSegmentation& segmentation);

}  // namespace hydra_multi
