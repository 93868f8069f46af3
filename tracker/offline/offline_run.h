#pragma once
// Runs the tracker over a dataset in one process, deterministically and as fast as possible:
// the same library the hs-tracker process uses, fed from an EuRoC folder or straight from the
// simulator (no disk). Collects per-frame results for trajectories, timing and evaluation.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/dataset/euroc_stream.h"
#include "common/eval/evaluate.h"
#include "common/sim/dataset_gen.h"
#include "hsslam/keyframe_t.hpp"
#include "hsslam/reloc_request_t.hpp"
#include "tracker/tracker.h"

namespace hs {

// A back end in the same process (hs-run --with-mapper): it gets every keyframe as the
// KEYFRAME message the hs-tracker process would publish, and returns the corrections the
// tracker applies before the next frame (the deterministic stand-in for MAP_UPDATE).
using BackEnd = std::function<std::vector<MapCorrection>(const hsslam::keyframe_t&)>;
// The back end's atlas (hs-run --with-mapper): answers a lost tracker's RELOC_REQUEST at once,
// before the next frame (the deterministic stand-in for RELOC_ANSWER).
using AtlasBackEnd = std::function<RelocAnswer(const hsslam::reloc_request_t&)>;

// Yields events in sensor-time order; false at the end.
using EventSource = std::function<bool(DatasetEvent&)>;

EventSource euroc_source(EurocStream& stream);
// Frames of the simulator as cam0/cam1 (or cam0 only when `stereo` is false); ground truth at
// the IMU rate.
EventSource sim_source(sim::DatasetGenerator& generator, bool stereo = true);

struct FrameRecord {
  int64_t t_ns = 0;
  bool accepted = false;
  TrackState state = TrackState::kInitialising;
  TrackMethod method = TrackMethod::kNone;
  bool is_keyframe = false;
  int tracked_points = 0;
  int32_t map_id = 0;
  float quality = 0.0f;
  float total_ms = 0.0f;
  std::vector<std::pair<std::string, float>> stage_ms;
  NavState nav;
  std::string message;
  // The newest keyframe the tracker held when it estimated this frame (-1: none), and the frame's
  // pose relative to it then: with the back end's final keyframe poses, the frame's final pose.
  int64_t ref_keyframe_id = -1;
  Eigen::Isometry3d T_ref_b = Eigen::Isometry3d::Identity();
  int corrections = 0;              // back-end corrections applied after this frame
  double correction_shift_m = 0.0;  // the largest move of the pose they caused
};

struct OfflineRunResult {
  std::vector<FrameRecord> frames;
  std::vector<NavState> ground_truth;
  TrackerCounters counters;
  ImuBufferCounters imu_counters;

  // Body poses of the frames that have a state (not initialising, not rejected).
  Trajectory estimate() const;
  // The same frames placed on their reference keyframes' poses as `T_w_kf` gives them (e.g. a
  // back end's after loop closure); a frame whose keyframe it does not know keeps its own pose.
  Trajectory keyframe_relative_estimate(
      const std::function<std::optional<Eigen::Isometry3d>(int64_t)>& T_w_kf) const;
  Trajectory ground_truth_trajectory() const;
};

struct OfflineRunOptions {
  bool progress = false;  // a progress line on stderr every 100 frames
  bool verbose = false;   // every tracker message on stderr
  // IMU samples and frames of the first skip_ns of the dataset are not fed, so the tracker
  // starts mid-sequence (e.g. already moving); ground truth is kept.
  int64_t skip_ns = 0;
  BackEnd back_end;  // none: the tracker alone
  AtlasBackEnd atlas;
};

OfflineRunResult run_offline(const TrackerOptions& options, const EventSource& source,
                             const OfflineRunOptions& run_options = {});

// Per-frame timing CSV: t_ns, state, method, keyframe, tracked, total_ms, then each stage.
void write_timing_csv(const std::string& path, const OfflineRunResult& result);

}  // namespace hs
