// Mapper corrections applied by the tracker (issue 6, "Tracker coupling"): the local map and the
// current state move with the corrected keyframes; a large move changes the map id; corrections
// for another map or for keyframes the tracker no longer has are ignored and counted.
#include <gtest/gtest.h>

#include <algorithm>

#include "tests/tracker/sim_tracker_fixture.h"

namespace hs {
namespace {

using TrackerCorrection = test::SimTrackerTest;

// Every window keyframe and every point of the tracker's map moved by T (world frame).
MapCorrection rigid_correction(const Tracker& tracker, const Eigen::Isometry3d& T, int32_t map_id) {
  MapCorrection c;
  c.map_id = map_id;
  for (const auto& kf : tracker.map().window()) {
    NavState s = kf->state;
    s.p_w_b = T * s.p_w_b;
    s.q_w_b = Eigen::Quaterniond(T.linear() * s.q_w_b.toRotationMatrix());
    s.v_w = T.linear() * s.v_w;
    c.keyframes.push_back({kf->id, s});
  }
  for (const auto& [id, p] : tracker.map().points()) c.points.push_back({id, T * p.p_w});
  return c;
}

Eigen::Isometry3d shift(double x_m) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation().x() = x_m;
  return T;
}

// An atlas answer the tracker did not ask for (none pending: it is tracking) changes nothing.
TEST_F(TrackerCorrection, AnAtlasAnswerNotAskedForIsIgnored) {
  track_range(0, 40);
  ASSERT_EQ(tracker_->state(), TrackState::kTracking);
  RelocAnswer a;
  a.seq = 0;
  a.found = true;
  a.map_id = 7;
  a.T_w_b = shift(1.0);
  EXPECT_NE(tracker_->apply(a).find("ignored: not the pending request"), std::string::npos);
  EXPECT_EQ(tracker_->counters().atlas_answers_ignored, 1);
  const FrameResult r = track_range(40, 41);
  EXPECT_EQ(r.state, TrackState::kTracking);
  EXPECT_EQ(r.map_id, 0) << r.message;
  EXPECT_EQ(tracker_->counters().atlas_relocalisations, 0);
}

TEST_F(TrackerCorrection, IgnoredWhileInitialising) {
  track_range(0, 5);  // less than the 1 s of IMU the start needs
  ASSERT_EQ(tracker_->state(), TrackState::kInitialising);
  const CorrectionResult r = tracker_->apply(MapCorrection{});
  EXPECT_FALSE(r.applied);
  EXPECT_NE(r.message.find("initialising"), std::string::npos) << r.message;
  EXPECT_EQ(tracker_->counters().corrections_ignored, 1);
}

TEST_F(TrackerCorrection, SmallRigidShiftMovesThePoseWithTheMap) {
  // At rest (the flight holds still for 2 s): consecutive poses agree to well under 1 mm.
  const FrameResult before = track_range(0, 30);
  ASSERT_EQ(before.state, TrackState::kTracking);
  const CorrectionResult r = tracker_->apply(rigid_correction(*tracker_, shift(0.01), 0));
  ASSERT_TRUE(r.applied) << r.message;
  EXPECT_NEAR(r.shift_m, 0.01, 1e-9);
  EXPECT_TRUE(r.message.empty()) << r.message;
  const FrameResult after = track_range(30, 31);
  EXPECT_EQ(after.state, TrackState::kTracking);
  EXPECT_EQ(after.map_id, before.map_id);  // under the silent limit (2 cm)
  EXPECT_NEAR((after.nav.p_w_b - before.nav.p_w_b - Eigen::Vector3d(0.01, 0, 0)).norm(), 0.0, 1e-3);
  EXPECT_EQ(tracker_->counters().corrections_applied, 1);
}

// How stale a correction is: from its newest keyframe to the frame it is applied after.
TEST_F(TrackerCorrection, LagFromTheNewestCorrectedKeyframe) {
  const FrameResult at = track_range(0, 30);
  ASSERT_EQ(at.state, TrackState::kTracking);
  const MapCorrection c = rigid_correction(*tracker_, shift(0.001), 0);
  int64_t newest_ns = 0;
  for (const KeyframeCorrection& k : c.keyframes) newest_ns = std::max(newest_ns, k.state.t_ns);
  const FrameResult later = track_range(30, 34);
  ASSERT_TRUE(tracker_->apply(c).applied);
  EXPECT_EQ(tracker_->counters().last_correction_lag_ms, (later.t_ns - newest_ns) / 1'000'000);
  EXPECT_GE(tracker_->counters().last_correction_lag_ms, (later.t_ns - at.t_ns) / 1'000'000);
  ASSERT_TRUE(tracker_->apply(rigid_correction(*tracker_, shift(0.0), 0)).applied);
  EXPECT_LE(tracker_->counters().last_correction_lag_ms,
            tracker_->counters().max_correction_lag_ms);
  EXPECT_EQ(tracker_->counters().max_correction_lag_ms, (later.t_ns - newest_ns) / 1'000'000);
}

TEST_F(TrackerCorrection, LargeMoveIsStatedWithANewMapId) {
  const FrameResult before = track_range(0, 30);
  ASSERT_EQ(before.state, TrackState::kTracking);
  const CorrectionResult r = tracker_->apply(rigid_correction(*tracker_, shift(0.05), 0));
  ASSERT_TRUE(r.applied);
  EXPECT_NE(r.message.find("map id now 1"), std::string::npos) << r.message;
  const FrameResult after = track_range(30, 31);
  EXPECT_EQ(after.map_id, before.map_id + 1);
  EXPECT_NEAR((after.nav.p_w_b - before.nav.p_w_b - Eigen::Vector3d(0.05, 0, 0)).norm(), 0.0, 1e-3);
  EXPECT_EQ(tracker_->counters().correction_jumps, 1);
  // Corrections for the old map id are stale now.
  EXPECT_FALSE(tracker_->apply(rigid_correction(*tracker_, shift(0.0), 0)).applied);
}

TEST_F(TrackerCorrection, StaleOrForeignCorrectionsAreIgnoredAndPointsRemoved) {
  ASSERT_EQ(track_range(0, 30).state, TrackState::kTracking);
  MapCorrection other_map = rigid_correction(*tracker_, shift(0.01), 3);
  CorrectionResult r = tracker_->apply(other_map);
  EXPECT_FALSE(r.applied);
  EXPECT_NE(r.message.find("map id 3"), std::string::npos) << r.message;

  MapCorrection unknown = rigid_correction(*tracker_, shift(0.01), 0);
  for (KeyframeCorrection& k : unknown.keyframes) k.id += 1000;
  r = tracker_->apply(unknown);
  EXPECT_FALSE(r.applied);
  EXPECT_NE(r.message.find("no keyframe the tracker still has"), std::string::npos);
  EXPECT_EQ(tracker_->counters().corrections_ignored, 2);

  ASSERT_FALSE(tracker_->map().points().empty());
  const int64_t removed = tracker_->map().points().begin()->first;
  MapCorrection removal = rigid_correction(*tracker_, shift(0.0), 0);
  removal.removed_points = {removed};
  ASSERT_TRUE(tracker_->apply(removal).applied);
  EXPECT_EQ(tracker_->map().points().count(removed), 0u);
  EXPECT_EQ(track_range(30, 31).state, TrackState::kTracking);
}

TEST_F(TrackerCorrection, MapperGravityIsAdoptedWhenPlausible) {
  ASSERT_EQ(track_range(0, 30).state, TrackState::kTracking);
  EXPECT_EQ(tracker_->gravity_w(), default_gravity_w());
  MapCorrection c = rigid_correction(*tracker_, shift(0.0), 0);
  c.g_w = Eigen::AngleAxisd(0.4 * M_PI / 180.0, Eigen::Vector3d::UnitX()) * default_gravity_w();
  ASSERT_TRUE(tracker_->apply(c).applied);
  EXPECT_EQ(tracker_->gravity_w(), c.g_w);

  // 10 deg off the world's -z, or 20% too strong: a broken mapper, not an accelerometer bias.
  MapCorrection tilted = rigid_correction(*tracker_, shift(0.0), 0);
  tilted.g_w =
      Eigen::AngleAxisd(10.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()) * default_gravity_w();
  CorrectionResult r = tracker_->apply(tilted);
  EXPECT_FALSE(r.applied);
  EXPECT_NE(r.message.find("gravity is 10"), std::string::npos) << r.message;
  MapCorrection strong = rigid_correction(*tracker_, shift(0.0), 0);
  strong.g_w = 1.2 * default_gravity_w();
  EXPECT_FALSE(tracker_->apply(strong).applied);
  EXPECT_EQ(tracker_->gravity_w(), c.g_w);
  // Zero: the mapper does not estimate gravity; the tracker keeps what it has.
  ASSERT_TRUE(tracker_->apply(rigid_correction(*tracker_, shift(0.0), 0)).applied);
  EXPECT_EQ(tracker_->gravity_w(), c.g_w);
  EXPECT_EQ(track_range(30, 31).state, TrackState::kTracking);
}

}  // namespace
}  // namespace hs
