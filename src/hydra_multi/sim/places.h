#pragma once
// The places a robot builds (Hydra's places layer, emulated from ground truth): nodes on the GVD of
// the free space the robot has seen (GVD cells within sensor range of one of its keyframes and in
// line of sight), thinned to at most one node per `spacing` square, each with its clearance as the
// free-space radius; edges join nodes closer than `max_edge_length` whose straight segment stays
// in free space, weighted by the smallest clearance along it.

#include <vector>

#include "hydra_multi/sim/free_space.h"

namespace hydra_multi::sim {

struct PlacesOptions {
  double spacing = 1.0;          ///< at most one place per square of this side (m)
  double max_edge_length = 2.0;  ///< (m)
  double sensor_range = 4.0;     ///< GVD cells this close to a keyframe are explored (m)
  double height_above_floor = 1.0;
};

struct PlaceGraph {
  struct Place {
    Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< world frame
    double distance = 0.0;                               ///< free-space radius (m)
    int room = -1;                                       ///< true room (ground truth only)
  };
  struct Edge {
    size_t a = 0, b = 0;
    double weight = 0.0;  ///< smallest clearance along the edge (m)
  };
  std::vector<Place> places;
  std::vector<Edge> edges;
};

/// Places of one floor seen from the keyframe positions (x-y in the world frame).
PlaceGraph extractPlaces(const FloorGrid& grid, const std::vector<Eigen::Vector2d>& keyframes,
                         const PlacesOptions& options = {});

}  // namespace hydra_multi::sim
