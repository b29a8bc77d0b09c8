#pragma once
// Room segmentation over the places layer (Hydra, Hughes et al. 2023; DESIGN.md "Room
// segmentation"): rooms are the parts of free space that stay connected when the narrow passages
// (doors) are cut.
//   1. For each of `thresholds` values t evenly over [min_threshold, max_threshold], keep the
//      places with free-space radius > t and the place edges with weight > t; the connected
//      components with at least min_room_places places are candidate room seeds.
//   2. Take the threshold whose number of seeds is the median over all thresholds (the smallest
//      such threshold); or, with Rule::kMost, the one with the most seeds. The median suits
//      rooms of many places (office-3: 11 rooms of 12); where rooms are small (a student room of
//      the dorm presets holds 8 places) they stand apart only over a few thresholds and the median
//      makes one room of the floor; there min_room_places 5 with kMost separates them (README,
//      `trials`), while on office-3 it splits large rooms (29 of 12).
//   3. Grow the seeds to every other place they reach over the places graph, each place going
//      to the seed nearest along the graph (Dijkstra from all seeds at once, Euclidean lengths).
// Rooms get a room node at the mean of their places, and every room the building node as parent.

#include <vector>

#include "hydra_multi/dsg/scene_graph.h"

namespace hydra_multi {

struct RoomSegmentationOptions {
  int thresholds = 12;  ///< Hydra: 12 values over 0.43-1.2 m
  double min_threshold = 0.43;
  double max_threshold = 1.2;
  size_t min_room_places = 10;
  /// Which threshold: the one whose seed count is the median over all (kMedian), or the one with
  /// the most seeds (kMost); the smallest such threshold either way.
  enum class Rule { kMedian, kMost } rule = Rule::kMedian;
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
