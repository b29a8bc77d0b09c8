#pragma once
// Scene-graph metrics of the paper (Section IV), on plain inputs so they are checked by hand:
//   objects  % correct: estimated objects with a true object of the same label within the
//            threshold; % found: true objects with an estimated object of the same label within it;
//            the wrong ones split into wrong label and misplaced, the correct ones counted once
//            per true object (the rest are duplicates: counted correct by the paper's metric)
//   places   the mean distance from each place to the nearest true free-space (GVD) voxel
//   rooms    precision: for each estimated room, the largest share of its voxels that one true
//            room holds, averaged over estimated rooms; recall: the same with the roles swapped
//            (Hydra's room metric).

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

namespace hydra_multi {

struct LabelledPoint {
  uint32_t label = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
};

/// What one estimated object is, against the truth.
struct ObjectVerdict {
  enum class Kind { kCorrect, kDuplicate, kWrongLabel, kMisplaced };
  Kind kind = Kind::kMisplaced;
  /// Correct or duplicate: the nearest true object of its label; wrong label: the nearest true
  /// object; misplaced: -1.
  int true_index = -1;
  double distance_m = 0.0;  ///< to that true object (0 when misplaced)
};
const char* toString(ObjectVerdict::Kind kind);

struct ObjectMetrics {
  std::optional<double> found_pct;    ///< none when there are no true objects
  std::optional<double> correct_pct;  ///< none when there are no estimated objects
  // What each estimated object is; correct + wrong_label + misplaced = estimated objects.
  size_t correct = 0;      ///< a true object of its label within the threshold
  size_t duplicates = 0;   ///< correct ones whose nearest true object another one also matched
  size_t wrong_label = 0;  ///< not correct, but a true object of another label within it
  size_t misplaced = 0;    ///< no true object of any label within the threshold
  std::vector<ObjectVerdict> verdicts;  ///< one per estimated object, in their order
};
ObjectMetrics objectMetrics(const std::vector<LabelledPoint>& estimated,
                            const std::vector<LabelledPoint>& truth, double threshold_m);

/// Mean distance of the places to their nearest GVD voxel centre; none without places or voxels.
std::optional<double> placesPositionError(const std::vector<Eigen::Vector3d>& places,
                                          const std::vector<Eigen::Vector3d>& gvd_voxels);

/// The integer key of the voxel of side `voxel_size` that holds p.
Eigen::Vector3i voxelKey(const Eigen::Vector3d& p, double voxel_size);

struct RoomMetrics {
  std::optional<double> precision;  ///< none without estimated rooms
  std::optional<double> recall;     ///< none without true rooms
};
/// Rooms as sets of voxel keys (duplicates within a room are ignored).
RoomMetrics roomMetrics(const std::vector<std::vector<Eigen::Vector3i>>& estimated,
                        const std::vector<std::vector<Eigen::Vector3i>>& truth);

}  // namespace hydra_multi
