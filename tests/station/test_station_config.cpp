// The station configuration file: keys land in the options; unknown keys, wrong types, bad
// values and broken JSON are errors that name the problem and leave the options unchanged.

#include <gtest/gtest.h>

#include "hydra_multi/station/station_config.h"

namespace hydra_multi {
namespace {

TEST(StationConfig, KeysSetOptions) {
  StationOptions options;
  EXPECT_FALSE(options.backend.deformation.solver.reduce_chains);  // the station's defaults
  EXPECT_TRUE(options.backend.admit_fitting_merges);
  EXPECT_TRUE(options.backend.merge_while_solving);
  EXPECT_TRUE(options.backend.plan_merges_ahead);
  EXPECT_EQ(options.backend.deformation.solver.solver.linearization_threads, 2);
  EXPECT_EQ(options.backend.reconciliation.icp_threads, 2);
  EXPECT_DOUBLE_EQ(options.backend.reconciliation.icp_reuse_m, 0.01);
  EXPECT_DOUBLE_EQ(options.backend.reconciliation.icp_reuse_rad, 0.01);
  EXPECT_FALSE(options.backend.deformation.whole_graph_analysis_ahead);
  EXPECT_DOUBLE_EQ(options.backend.readmit_unsolved_share, 0.01);
  EXPECT_TRUE(options.backend.deformation.solver.keep_converged_gnc_solve);
  EXPECT_TRUE(options.backend.readmit_unsolved_with_merges);
  EXPECT_DOUBLE_EQ(options.backend.deformation.local_deferred_share, 0.6);
  EXPECT_DOUBLE_EQ(options.backend.alignment.realign_fit_share, 1.0);
  EXPECT_DOUBLE_EQ(options.backend.alignment.realign_fit_m, 2.0);
  EXPECT_TRUE(options.backend.alignment.realign_against_verdicts);
  EXPECT_DOUBLE_EQ(options.backend.alignment.realign_rejected_share, 0.5);
  EXPECT_EQ(options.keep_freed_mb, 3072u);
  const Status s = applyStationConfig(R"({
      "loop_closures": {"object_ambiguity_ratio": 0, "object_rival_distance": 2.5,
                        "anchor_objects": false},
      "alignment": {"min_inliers": 7, "sigma_translation_m": 0.25, "realign_threshold_m": 4,
                    "decline_refuted": false, "refuted_within_m": 2.5, "weigh_support": false,
                    "realign_fit_share": 0.5, "realign_fit_m": 3,
                    "realign_against_verdicts": false, "realign_rejected_share": 0.25},
      "deformation": {"two_stage": false, "final_iterations": 0, "mesh_variance": 0.001,
                      "gnc_mu_step": 2.0, "gnc_incremental_mu_step": 1, "link_max_dt_s": 0,
                      "odometry_rotation_variance": 0.01, "reduce_chains": true,
                      "chain_min_share": 0.5, "linearization_threads": 1,
                      "whole_graph_analysis_ahead": true, "readmit_unsolved_share": 0,
                      "keep_converged_gnc_solve": false, "readmit_unsolved_with_merges": false,
                      "local_deferred_share": 0.7},
      "reconciliation": {"enabled": false, "admit_fitting_merges": false,
                         "merge_while_solving": false, "plan_merges_ahead": false,
                         "place_max_distance": 0.6, "label_votes": true, "icp_threads": 3,
                         "icp_reuse_m": 0, "icp_reuse_rad": 0.002,
                         "label_confusion": 0.2, "label_min_odds": 2},
      "rooms": {"enabled": false, "min_room_places": 4, "threshold_rule": "most",
                    "max_door_radius": 0.6},
      "memory": {"keep_freed_mb": 0}})",
                                      "test.json", options);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_DOUBLE_EQ(options.detector.object_ambiguity_ratio, 0.0);
  EXPECT_DOUBLE_EQ(options.detector.object_rival_distance, 2.5);
  EXPECT_FALSE(options.detector.anchor_objects);
  EXPECT_EQ(options.backend.alignment.alignment.min_inliers, 7u);
  EXPECT_DOUBLE_EQ(options.backend.alignment.alignment.averaging.information(0, 0), 16.0);
  EXPECT_DOUBLE_EQ(options.backend.alignment.alignment.averaging.information(3, 3), 400.0);
  EXPECT_DOUBLE_EQ(options.backend.alignment.realign_threshold_m, 4.0);
  EXPECT_FALSE(options.backend.alignment.decline_refuted);
  EXPECT_DOUBLE_EQ(options.backend.alignment.refuted_within_m, 2.5);
  EXPECT_FALSE(options.backend.alignment.weigh_support);
  EXPECT_DOUBLE_EQ(options.backend.alignment.realign_fit_share, 0.5);
  EXPECT_DOUBLE_EQ(options.backend.alignment.realign_fit_m, 3.0);
  EXPECT_FALSE(options.backend.alignment.realign_against_verdicts);
  EXPECT_DOUBLE_EQ(options.backend.alignment.realign_rejected_share, 0.25);
  EXPECT_FALSE(options.backend.deformation.two_stage);
  EXPECT_EQ(options.backend.deformation.final_iterations, 0);
  EXPECT_DOUBLE_EQ(options.backend.deformation.mesh_variance, 0.001);
  EXPECT_DOUBLE_EQ(options.backend.deformation.solver.gnc.mu_step, 2.0);
  EXPECT_DOUBLE_EQ(options.backend.deformation.solver.incremental_mu_step, 1.0);
  EXPECT_DOUBLE_EQ(options.backend.deformation.link_max_dt_s, 0.0);
  EXPECT_DOUBLE_EQ(options.backend.deformation.odometry_rotation_variance, 0.01);
  EXPECT_TRUE(options.backend.deformation.solver.reduce_chains);
  EXPECT_DOUBLE_EQ(options.backend.deformation.solver.chain_min_share, 0.5);
  EXPECT_EQ(options.backend.deformation.solver.solver.linearization_threads, 1);
  EXPECT_TRUE(options.backend.deformation.whole_graph_analysis_ahead);
  EXPECT_DOUBLE_EQ(options.backend.readmit_unsolved_share, 0.0);
  EXPECT_FALSE(options.backend.deformation.solver.keep_converged_gnc_solve);
  EXPECT_FALSE(options.backend.readmit_unsolved_with_merges);
  EXPECT_DOUBLE_EQ(options.backend.deformation.local_deferred_share, 0.7);
  EXPECT_EQ(options.backend.reconciliation.icp_threads, 3);
  EXPECT_DOUBLE_EQ(options.backend.reconciliation.icp_reuse_m, 0.0);
  EXPECT_DOUBLE_EQ(options.backend.reconciliation.icp_reuse_rad, 0.002);
  EXPECT_FALSE(options.backend.reconcile);
  EXPECT_FALSE(options.backend.admit_fitting_merges);
  EXPECT_FALSE(options.backend.merge_while_solving);
  EXPECT_FALSE(options.backend.plan_merges_ahead);
  EXPECT_DOUBLE_EQ(options.backend.reconciliation.place_max_distance, 0.6);
  EXPECT_TRUE(options.backend.reconciliation.label_votes);
  EXPECT_DOUBLE_EQ(options.backend.reconciliation.label_confusion, 0.2);
  EXPECT_DOUBLE_EQ(options.backend.reconciliation.label_min_odds, 2.0);
  EXPECT_FALSE(options.backend.segment_rooms);
  EXPECT_EQ(options.backend.rooms.min_room_places, 4u);
  EXPECT_EQ(options.backend.rooms.rule, RoomSegmentationOptions::Rule::kMost);
  EXPECT_DOUBLE_EQ(options.backend.rooms.max_door_radius, 0.6);
  EXPECT_EQ(options.keep_freed_mb, 0u);
}

TEST(StationConfig, ErrorsNameTheProblemAndChangeNothing) {
  const struct {
    const char* text;
    const char* says;
  } cases[] = {
      {"{", "not valid JSON"},
      {"[1, 2]", "expected a JSON object"},
      {R"({"backend": {}})", "unknown section \"backend\""},
      {R"({"rooms": 3})", "rooms: expected an object"},
      {R"({"loop_closures": {"object_ambiguity_ratio": -0.5}})",
       "loop_closures.object_ambiguity_ratio: expected a number >= 0"},
      {R"({"rooms": {"min_places": 3}})", "unknown key rooms.min_places"},
      {R"({"memory": {"keep_freed_mb": -1}})", "memory.keep_freed_mb: expected an integer >= 0"},
      {R"({"rooms": {"threshold_rule": "max"}})",
       "rooms.threshold_rule: expected \"median\" or \"most\""},
      {R"({"deformation": {"mesh_variance": -1}})",
       "deformation.mesh_variance: expected a number > 0"},
      {R"({"deformation": {"two_stage": 1}})", "deformation.two_stage: expected true or false"},
      {R"({"deformation": {"chain_min_share": 1.5}})",
       "deformation.chain_min_share: expected a number >= 0.0 and <= 1.0"},
      {R"({"deformation": {"readmit_unsolved_share": 1.5}})",
       "deformation.readmit_unsolved_share: expected a number >= 0.0 and <= 1.0"},
      {R"({"deformation": {"local_deferred_share": 1.5}})",
       "deformation.local_deferred_share: expected a number >= 0.0 and <= 1.0"},
      {R"({"deformation": {"gnc_incremental_mu_step": 0.5}})",
       "deformation.gnc_incremental_mu_step: expected a number >= 1"},
      {R"({"reconciliation": {"label_confusion": 0.5}})",
       "reconciliation.label_confusion: expected a number > 0 and < 0.5"},
      {R"({"reconciliation": {"label_min_shared_vertices": 1.5}})",
       "reconciliation.label_min_shared_vertices: expected a number > 0.0 and <= 1.0"},
      {R"({"alignment": {"min_inliers": 2.5}})", "alignment.min_inliers: expected an integer"},
      {R"({"alignment": {"realign_fit_share": 1.5}})",
       "alignment.realign_fit_share: expected a number >= 0.0 and <= 1.0"},
      {R"({"alignment": {"realign_rejected_share": -0.5}})",
       "alignment.realign_rejected_share: expected a number >= 0.0 and <= 1.0"},
      {R"({"alignment": {"realign_fit_m": 0}})", "alignment.realign_fit_m: expected a number > 0"},
      {R"({"rooms": {"min_threshold": 2.0, "max_threshold": 1.0}})", "min_threshold is above"},
      {R"({"reconciliation": {"enabled": false}, "rooms": {"thresholds": "12"}})",
       "rooms.thresholds"},
  };
  for (const auto& c : cases) {
    StationOptions options;
    const Status s = applyStationConfig(c.text, "bad.json", options);
    ASSERT_FALSE(s.ok()) << c.text;
    EXPECT_NE(s.message().find("bad.json: "), std::string::npos) << s.message();
    EXPECT_NE(s.message().find(c.says), std::string::npos) << s.message();
    EXPECT_TRUE(options.backend.reconcile) << c.text;  // unchanged, even by earlier keys
  }
  StationOptions options;
  EXPECT_FALSE(loadStationConfig("/nonexistent/config.json", options).ok());
}

// The shipped configuration of DESIGN.md's (Hydra's) room segmentation loads and sets it.
TEST(StationConfig, ShippedHydraRoomsConfiguration) {
  StationOptions options;
  const Status s = loadStationConfig(HYDRA_MULTI_SOURCE_DIR "/config/hydra-rooms.json", options);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(options.backend.rooms.min_room_places, 10u);
  EXPECT_EQ(options.backend.rooms.rule, RoomSegmentationOptions::Rule::kMedian);
  EXPECT_DOUBLE_EQ(options.backend.rooms.max_door_radius, 0.0);
  EXPECT_EQ(options.backend.rooms.thresholds, RoomSegmentationOptions{}.thresholds);
}

// The shipped configuration that turns the label votes on (reconciliation.h).
TEST(StationConfig, ShippedLabelVotesConfiguration) {
  StationOptions options;
  const Status s = loadStationConfig(HYDRA_MULTI_SOURCE_DIR "/config/label-votes.json", options);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_TRUE(options.backend.reconciliation.label_votes);
  EXPECT_DOUBLE_EQ(options.backend.reconciliation.label_confusion,
                   ReconciliationOptions{}.label_confusion);
}

}  // namespace
}  // namespace hydra_multi
