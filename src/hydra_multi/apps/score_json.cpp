#include "hydra_multi/apps/score_json.h"

namespace hydra_multi::apps {
namespace {

nlohmann::ordered_json orNull(const std::optional<double>& v) {
  return v ? nlohmann::ordered_json(*v) : nlohmann::ordered_json(nullptr);
}

}  // namespace

nlohmann::ordered_json scoreJson(const SceneGraphScore& s) {
  return {{"ate_rmse_m", orNull(s.ate_rmse_m)},
          {"objects_found_pct", orNull(s.objects_found_pct)},
          {"objects_correct_pct", orNull(s.objects_correct_pct)},
          {"object_threshold_m", s.object_threshold_m},
          {"places_position_error_m", orNull(s.places_position_error_m)},
          {"rooms_precision", orNull(s.rooms_precision)},
          {"rooms_recall", orNull(s.rooms_recall)},
          {"num_objects", s.num_objects},
          {"num_places", s.num_places},
          {"num_rooms", s.num_rooms},
          {"objects_correct", s.objects_correct},
          {"objects_duplicates", s.objects_duplicates},
          {"objects_wrong_label", s.objects_wrong_label},
          {"objects_misplaced", s.objects_misplaced}};
}

}  // namespace hydra_multi::apps
