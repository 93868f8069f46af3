// Issue 5's hard cases on the simulator: the tracker must report LOST rather than publish
// garbage, recover within 1 s of good data returning, bridge IMU gaps, and drift <= 1% on the
// vehicle loop.
//
// "Honest" here: align the estimate on the last TRACKING frame before the bad segment (so drift
// before the segment does not count). From there to the end of the run, a frame reported
// TRACKING or RELOCALISED may carry the error of the latest LOST frame (drift the tracker
// admitted to, up to kMaxCarriedM / kMaxCarriedDeg; 0 if none) plus normal tracking drift
// since then: kHonestBaseM plus kHonestPathShare of the path flown, and kHonestRotationDeg.
// So a jump to a wrong pose, or claiming to track while drifting away, fails; dead-reckoning
// while LOST does not. A new map id declares a new epoch (consumers are told the pose may
// jump), so the alignment restarts on its first frame. Frames that carry no image content
// (blackout) must not be reported as tracked at all.
//
// Each scenario runs at its configured event times, cut a few seconds after the bad segment.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/features2d.hpp>

#include "tracker/offline/offline_run.h"

namespace hs {
namespace {

const std::string kSource = HS_SOURCE_DIR;

constexpr double kHonestBaseM = 0.05;
constexpr double kHonestPathShare = 0.05;  // 5x the 1% drift target
constexpr double kHonestRotationDeg = 3.0;
// A LOST stretch may leave the estimate this far off (a few seconds of IMU-only drift); a pose
// further off is not one to resume TRACKING from in the same map.
constexpr double kMaxCarriedM = 0.5;
constexpr double kMaxCarriedDeg = 5.0;
constexpr int64_t kRecoveryNs = 1'000'000'000;  // the target
constexpr double kVehicleDriftShare = 0.01;     // the target

sim::Scenario load(const std::string& name, double duration_s) {
  sim::Scenario s = sim::load_scenario(kSource + "/config/sim/" + name + ".yaml");
  s.duration_s = duration_s;
  return s;
}

// The tracker run over a scenario, with the generator kept for exact ground truth.
struct HardRun {
  explicit HardRun(const sim::Scenario& scenario) : gen(scenario) {
    TrackerOptions options;
    options.calib = scenario.camera.calib;
    run = run_offline(options, sim_source(gen));
  }
  int64_t abs_ns(int64_t t_rel_ns) const { return gen.scenario().start_time_ns + t_rel_ns; }
  double rel_s(int64_t t_ns) const { return ns_to_s(t_ns - gen.scenario().start_time_ns); }

  sim::DatasetGenerator gen;
  OfflineRunResult run;
};

bool is_tracked(TrackState s) {
  return s == TrackState::kTracking || s == TrackState::kRelocalised;
}

// Ground-truth path length between two times (200 Hz ground truth).
double path_m(const HardRun& h, int64_t t0_ns, int64_t t1_ns) {
  double sum = 0.0;
  const NavState* prev = nullptr;
  for (const NavState& s : h.run.ground_truth) {
    if (s.t_ns < t0_ns || s.t_ns > t1_ns) continue;
    if (prev) sum += (s.p_w_b - prev->p_w_b).norm();
    prev = &s;
  }
  return sum;
}

// Index of the last TRACKING frame before t_ns, or -1.
int anchor_before(const OfflineRunResult& run, int64_t t_ns) {
  int anchor = -1;
  for (size_t i = 0; i < run.frames.size() && run.frames[i].t_ns < t_ns; ++i)
    if (run.frames[i].accepted && run.frames[i].state == TrackState::kTracking)
      anchor = static_cast<int>(i);
  return anchor;
}

struct PoseError {
  double position_m = 0.0;
  double rotation_deg = 0.0;
  double velocity_mps = 0.0;  // for diagnosis only
};

// Error of frame f with the estimate aligned on frame `anchor`.
PoseError error_at(const HardRun& h, const FrameRecord& anchor, const FrameRecord& f) {
  const Eigen::Isometry3d T_gt_est = h.gen.T_w_b(anchor.t_ns) * anchor.nav.T_w_b().inverse();
  const Eigen::Isometry3d T_w_b_est = T_gt_est * f.nav.T_w_b();
  const Eigen::Isometry3d T_w_b_gt = h.gen.T_w_b(f.t_ns);
  PoseError e;
  e.position_m = (T_w_b_est.translation() - T_w_b_gt.translation()).norm();
  e.rotation_deg =
      Eigen::AngleAxisd(T_w_b_gt.linear().transpose() * T_w_b_est.linear()).angle() * 180.0 / M_PI;
  e.velocity_mps = (T_gt_est.linear() * f.nav.v_w - h.gen.body_at(f.t_ns).v_w).norm();
  return e;
}

// FAST corners in the cam0 image at frame time t_ns (rendered again).
size_t fast_corners(HardRun& h, int64_t t_ns) {
  const auto& times = h.gen.frame_times_ns();
  const size_t i = static_cast<size_t>(std::find(times.begin(), times.end(), t_ns) - times.begin());
  std::vector<cv::KeyPoint> corners;
  cv::FAST(h.gen.frame(i).cam0, corners, 20);
  return corners.size();
}

// State changes (with the tracker's messages) from t0_ns to t1_ns, for failure reports.
std::string transitions(const HardRun& h, int64_t t0_ns, int64_t t1_ns) {
  std::ostringstream o;
  const FrameRecord* prev = nullptr;
  for (const FrameRecord& f : h.run.frames) {
    if (f.t_ns >= t0_ns && f.t_ns <= t1_ns && (!prev || prev->state != f.state))
      o << "  " << h.rel_s(f.t_ns) << " s " << to_string(f.state) << ": " << f.message << "\n";
    prev = &f;
  }
  return o.str();
}

// Checks honesty (see the top of the file) from the last TRACKING frame before seg_start_ns to
// the end of the run; prints the figures.
void expect_honest(const HardRun& h, int64_t seg_start_ns, const std::string& what) {
  const int anchor_index = anchor_before(h.run, seg_start_ns);
  ASSERT_GE(anchor_index, 0) << what << ": no TRACKING frame before the bad segment";
  const FrameRecord* anchor = &h.run.frames[static_cast<size_t>(anchor_index)];
  const FrameRecord* since = anchor;  // the allowance for normal drift counts from here
  PoseError admitted;                 // error of the latest LOST frame
  double worst_ratio = 0.0, worst_admitted_m = 0.0;
  int64_t worst_t_ns = anchor->t_ns;
  std::string worst;
  int dishonest = 0, lost = 0, new_maps = 0;
  for (size_t i = static_cast<size_t>(anchor_index) + 1; i < h.run.frames.size(); ++i) {
    const FrameRecord& f = h.run.frames[i];
    if (!f.accepted || f.state == TrackState::kInitialising) continue;
    if (f.map_id != anchor->map_id) {
      // A new map id declares a new epoch (the pose may jump): align on it afresh.
      anchor = since = &f;
      admitted = {};
      ++new_maps;
      continue;
    }
    const PoseError e = error_at(h, *anchor, f);
    if (f.state == TrackState::kLost) {
      ++lost;
      since = &f;
      admitted.position_m = std::min(e.position_m, kMaxCarriedM);
      admitted.rotation_deg = std::min(e.rotation_deg, kMaxCarriedDeg);
      worst_admitted_m = std::max(worst_admitted_m, e.position_m);
      continue;
    }
    const double bound_m =
        admitted.position_m + kHonestBaseM + kHonestPathShare * path_m(h, since->t_ns, f.t_ns);
    const double bound_deg = admitted.rotation_deg + kHonestRotationDeg;
    const double ratio = std::max(e.position_m / bound_m, e.rotation_deg / bound_deg);
    dishonest += ratio > 1.0;
    if (ratio > worst_ratio) {
      worst_ratio = ratio;
      worst_t_ns = f.t_ns;
      std::ostringstream o;
      o << "at " << h.rel_s(f.t_ns) << " s (" << to_string(f.state) << "): " << e.position_m
        << " m (bound " << bound_m << " m), " << e.rotation_deg << " deg (bound " << bound_deg
        << " deg), velocity error " << e.velocity_mps << " m/s";
      worst = o.str();
    }
  }
  std::printf(
      "[%s] anchor %.2f s, %d LOST frames (largest error while LOST %.3f m), %d new map ids, "
      "%d dishonest tracked frames, worst %.2fx bound %s\n",
      what.c_str(), h.rel_s(h.run.frames[static_cast<size_t>(anchor_index)].t_ns), lost,
      worst_admitted_m, new_maps, dishonest, worst_ratio, worst.c_str());
  EXPECT_EQ(dishonest, 0) << what << ": tracked frames far from ground truth; worst " << worst
                          << "\n"
                          << transitions(h, h.run.frames[static_cast<size_t>(anchor_index)].t_ns,
                                         worst_t_ns);
}

// The first TRACKING frame at or after seg_end_ns must come within kRecoveryNs, and tracking
// must then hold until hold_until_ns.
void expect_recovery(const HardRun& h, int64_t seg_start_ns, int64_t seg_end_ns,
                     int64_t hold_until_ns, const std::string& what) {
  const auto& frames = h.run.frames;
  const auto first = std::find_if(frames.begin(), frames.end(), [&](const FrameRecord& f) {
    return f.t_ns >= seg_end_ns && f.state == TrackState::kTracking;
  });
  const std::string story =
      transitions(h, seg_start_ns - kRecoveryNs, seg_end_ns + 3 * kRecoveryNs);
  ASSERT_NE(first, frames.end()) << what << ": never TRACKING again after the segment\n" << story;
  const double recovery_s = ns_to_s(first->t_ns - seg_end_ns);
  const int lost_after =
      static_cast<int>(std::count_if(first, frames.end(), [&](const FrameRecord& f) {
        return f.t_ns < hold_until_ns && f.state == TrackState::kLost;
      }));
  std::printf("[%s] TRACKING %.3f s after the segment end, %d LOST frames after that\n",
              what.c_str(), recovery_s, lost_after);
  EXPECT_LE(first->t_ns - seg_end_ns, kRecoveryNs)
      << what << ": recovery took " << recovery_s << " s\n"
      << story;
  EXPECT_EQ(lost_after, 0) << what << ": LOST again after recovering\n" << story;
}

TEST(TrackerHardCases, BlackoutIsReportedLostAndRecoveredWithinOneSecond) {
  const sim::Scenario s = load("blackout", 20.0);  // 2 s of black frames from 15 s
  ASSERT_EQ(s.events.blackouts.size(), 1u);
  const HardRun h(s);
  const int64_t start = h.abs_ns(s.events.blackouts[0].start_ns);
  const int64_t end = h.abs_ns(s.events.blackouts[0].end_ns);
  int black = 0, claimed = 0;
  for (const FrameRecord& f : h.run.frames) {
    if (f.t_ns < start || f.t_ns > end) continue;
    ++black;
    if (is_tracked(f.state)) {
      ++claimed;
      ADD_FAILURE() << "black frame at " << h.rel_s(f.t_ns) << " s reported " << to_string(f.state)
                    << ": " << f.message;
    }
  }
  EXPECT_GT(black, 30);
  std::printf("[blackout] %d black frames, %d reported as tracked\n", black, claimed);
  expect_honest(h, start, "blackout");
  // The first frame after the window is the first good one.
  expect_recovery(h, start, end, INT64_MAX, "blackout");
}

// A 4.5 s blackout, longer than the IMU may bridge (continue_map_within_s, 3 s): the
// dead-reckoned pose is no prior to track from. The first frame with images is placed by
// relocalisation (PnP on the reference keyframe's points) or starts a new map id; it is not
// tracked frame to frame from the prediction (with the mapper, and its corrections, that once
// kept 15 inliers 13 cm off the truth: LoopDetection.AfterALongBlackout...).
TEST(TrackerHardCases, AfterALongBlackoutTheFrameIsRelocalisedOrStartsANewMap) {
  sim::Scenario s = load("blackout", 32.0);
  ASSERT_EQ(s.events.blackouts.size(), 1u);
  s.events.blackouts[0] = {24'500'000'000, 29'000'000'000};
  const HardRun h(s);
  const int64_t start = h.abs_ns(s.events.blackouts[0].start_ns);
  const int64_t end = h.abs_ns(s.events.blackouts[0].end_ns);
  const int anchor_index = anchor_before(h.run, start);
  ASSERT_GE(anchor_index, 0);
  const FrameRecord& anchor = h.run.frames[static_cast<size_t>(anchor_index)];
  const auto first =
      std::find_if(h.run.frames.begin(), h.run.frames.end(),
                   [&](const FrameRecord& f) { return f.t_ns > end && is_tracked(f.state); });
  ASSERT_NE(first, h.run.frames.end()) << transitions(h, start, end + 3 * kRecoveryNs);
  const bool new_map = first->map_id != anchor.map_id;
  const bool relocalised = first->method == TrackMethod::kRelocalisedReference ||
                           first->method == TrackMethod::kRelocalisedGlobal;
  const PoseError e = error_at(h, anchor, *first);
  std::printf(
      "[long blackout] first tracked frame %.2f s after it: %s, %s, %.3f m from the truth "
      "relative to before it\n",
      ns_to_s(first->t_ns - end), to_string(first->method), new_map ? "new map id" : "same map id",
      e.position_m);
  EXPECT_TRUE(new_map || relocalised) << first->message;
  if (!new_map) {
    EXPECT_LT(e.position_m, 0.03) << first->message;
  }
  expect_recovery(h, start, end, INT64_MAX, "long blackout");
}

TEST(TrackerHardCases, IlluminationStepsAreTrackedHonestly) {
  const sim::Scenario s = load("illumination_step", 26.0);  // steps at 12 s and 24 s
  ASSERT_EQ(s.events.gain_steps.size(), 2u);
  const HardRun h(s);
  // Each step is a bad "segment" of no length: good (if different) images follow at once.
  const int64_t step0 = h.abs_ns(s.events.gain_steps[0].t_ns);
  const int64_t step1 = h.abs_ns(s.events.gain_steps[1].t_ns);
  expect_recovery(h, step0, step0, step1, "gain step to 1.4");
  expect_recovery(h, step1, step1, INT64_MAX, "gain step to 0.6");
  expect_honest(h, step0, "illumination");
}

TEST(TrackerHardCases, FastRotationIsHonestAndRecoveredWithinOneSecond) {
  const sim::Scenario s = load("fast_rotation", 14.0);
  const HardRun h(s);
  // The burst: frames whose body rate exceeds twice the normal looking-around rate.
  const double burst_rad_s = 120.0 * M_PI / 180.0;
  int64_t start = -1, end = -1;
  double peak = 0.0;
  for (const FrameRecord& f : h.run.frames) {
    const double rate = h.gen.body_at(f.t_ns).omega_b.norm();
    peak = std::max(peak, rate);
    if (rate < burst_rad_s) continue;
    if (start < 0) start = f.t_ns;
    end = f.t_ns;
  }
  ASSERT_GE(start, 0) << "no fast rotation in the scenario";
  std::printf("[fast_rotation] burst %.2f-%.2f s, peak %.0f deg/s\n", h.rel_s(start), h.rel_s(end),
              peak * 180.0 / M_PI);
  expect_honest(h, start, "fast_rotation");
  expect_recovery(h, start, end, INT64_MAX, "fast_rotation");
}

TEST(TrackerHardCases, TexturelessWallIsHonestAndRecoveredWithinOneSecond) {
  const sim::Scenario s = load("textureless", 25.0);
  ASSERT_EQ(s.events.textureless.size(), 1u);
  HardRun h(s);  // non-const: frames are rendered again below
  const int64_t start = h.abs_ns(s.events.textureless[0].start_ns);
  expect_honest(h, start, "textureless");
  // The scenario's window is nominal: good data is back when the camera sees at least as many
  // corners as in the last frame the tracker tracked before the wall.
  const int anchor = anchor_before(h.run, start);
  ASSERT_GE(anchor, 0);
  const size_t reference = fast_corners(h, h.run.frames[static_cast<size_t>(anchor)].t_ns);
  int64_t good = -1;
  for (const int64_t t_ns : h.gen.frame_times_ns())
    if (t_ns >= h.abs_ns(s.events.textureless[0].end_ns) && fast_corners(h, t_ns) >= reference) {
      good = t_ns;
      break;
    }
  ASSERT_GE(good, 0) << "the texture never comes back";
  std::printf("[textureless] %zu FAST corners at the last tracked frame; as many from %.2f s\n",
              reference, h.rel_s(good));
  expect_recovery(h, start, good, INT64_MAX, "textureless");
}

TEST(TrackerHardCases, ImuGapIsBridgedWithoutLosingTrack) {
  const sim::Scenario s = load("imu_gap", 18.0);  // 0.5 s without IMU from 15 s
  ASSERT_EQ(s.events.imu_gaps.size(), 1u);
  const HardRun h(s);
  const int64_t start = h.abs_ns(s.events.imu_gaps[0].start_ns);
  const int64_t end = h.abs_ns(s.events.imu_gaps[0].end_ns);
  EXPECT_GT(h.run.counters.imu_gaps, 0) << "the tracker never saw the gap";
  // Every frame from the gap to a second after it has a pose and is tracked.
  int across = 0;
  for (const FrameRecord& f : h.run.frames) {
    if (f.t_ns < start || f.t_ns > end + kRecoveryNs) continue;
    ++across;
    EXPECT_TRUE(f.accepted) << "frame at " << h.rel_s(f.t_ns) << " s dropped: " << f.message;
    EXPECT_NE(f.state, TrackState::kLost) << "at " << h.rel_s(f.t_ns) << " s: " << f.message;
  }
  EXPECT_GE(across, 30);
  std::printf("[imu_gap] %d frames across the gap, %lld gap intervals seen by the tracker\n",
              across, static_cast<long long>(h.run.counters.imu_gaps));
  expect_honest(h, start, "imu_gap");
}

TEST(TrackerHardCases, StaticBodyStaysStillAndTracked) {
  const HardRun h(load("static", 6.0));
  const FrameRecord* first = nullptr;
  double worst_m = 0.0;
  for (const FrameRecord& f : h.run.frames) {
    if (f.state == TrackState::kInitialising) continue;
    EXPECT_EQ(f.state, TrackState::kTracking) << "at " << h.rel_s(f.t_ns) << " s: " << f.message;
    if (!first) first = &f;
    worst_m = std::max(worst_m, (f.nav.p_w_b - first->nav.p_w_b).norm());
  }
  ASSERT_NE(first, nullptr) << "never initialised";
  std::printf("[static] largest move from the first pose %.4f m\n", worst_m);
  EXPECT_LT(worst_m, 0.005);
}

// The full 102 s loop takes minutes (hs-run reports it); 20 s is about 65 m of road.
TEST(TrackerHardCases, VehicleDriftsAtMostOnePercentAndTracksEveryFrame) {
  // The whole scenario: two laps of the 185 m street loop.
  const sim::Scenario s = sim::load_scenario(kSource + "/config/sim/vehicle_loop.yaml");
  const HardRun h(s);
  const auto& frames = h.run.frames;
  const auto first = std::find_if(frames.begin(), frames.end(), [](const FrameRecord& f) {
    return f.state != TrackState::kInitialising;
  });
  ASSERT_NE(first, frames.end()) << "never initialised";
  EXPECT_LE(first - frames.begin(), 21);  // one second of IMU history for gravity
  for (auto f = first; f != frames.end(); ++f)
    EXPECT_TRUE(f->accepted && is_tracked(f->state))
        << "at " << h.rel_s(f->t_ns) << " s " << to_string(f->state) << ": " << f->message;
  // The world frame is gravity aligned at the first frame: align there, compare at the end.
  const PoseError e = error_at(h, *first, frames.back());
  const double path = path_m(h, first->t_ns, frames.back().t_ns);
  ASSERT_GT(path, 300.0);
  std::printf("[vehicle_loop] final drift %.3f m over %.1f m = %.2f%%, rotation %.2f deg\n",
              e.position_m, path, 100.0 * e.position_m / path, e.rotation_deg);
  EXPECT_LE(e.position_m, kVehicleDriftShare * path);
}

}  // namespace
}  // namespace hs
