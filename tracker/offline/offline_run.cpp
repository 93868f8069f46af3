#include "tracker/offline/offline_run.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <optional>
#include <sstream>

#include "common/core/atomic_file.h"
#include "tracker/node/node_messages.h"

namespace hs {

EventSource euroc_source(EurocStream& stream) {
  return [&stream](DatasetEvent& e) { return stream.next(e); };
}

EventSource sim_source(sim::DatasetGenerator& gen, bool stereo) {
  // Merge IMU samples, ground truth and frames by time; IMU first at equal times, so the
  // sample at a frame's time is there when the frame arrives.
  struct State {
    size_t imu = 0, truth = 0, frame = 0;
  };
  auto st = std::make_shared<State>();
  return [&gen, st, stereo](DatasetEvent& e) {
    const auto& samples = gen.imu().samples;
    const auto& truth = gen.imu().truth;
    const auto& frames = gen.frame_times_ns();
    const int64_t inf = INT64_MAX;
    const int64_t t_imu = st->imu < samples.size() ? samples[st->imu].t_ns : inf;
    const int64_t t_gt = st->truth < truth.size() ? truth[st->truth].t_ns : inf;
    const int64_t t_frame = st->frame < frames.size() ? frames[st->frame] : inf;
    if (t_imu == inf && t_gt == inf && t_frame == inf) return false;
    if (t_imu <= t_gt && t_imu <= t_frame) {
      e = samples[st->imu++];
    } else if (t_gt <= t_frame) {
      e = truth[st->truth++];
    } else {
      const size_t i = st->frame++;
      sim::SimStereoFrame f = gen.frame(i);
      StereoFrame sf;
      sf.t_ns = f.t_ns;
      sf.seq = static_cast<int64_t>(i);
      sf.cam0 = f.cam0;
      if (stereo) sf.cam1 = f.cam1;
      e = std::move(sf);
    }
    return true;
  };
}

Trajectory OfflineRunResult::estimate() const {
  Trajectory t;
  for (const FrameRecord& f : frames) {
    if (!f.accepted || f.state == TrackState::kInitialising) continue;
    t.poses.push_back({f.t_ns, f.nav.T_w_b()});
  }
  return t;
}

Trajectory OfflineRunResult::keyframe_relative_estimate(
    const std::function<std::optional<Eigen::Isometry3d>(int64_t)>& T_w_kf) const {
  Trajectory t;
  for (const FrameRecord& f : frames) {
    if (!f.accepted || f.state == TrackState::kInitialising) continue;
    const std::optional<Eigen::Isometry3d> T_w_ref =
        f.ref_keyframe_id >= 0 ? T_w_kf(f.ref_keyframe_id) : std::nullopt;
    t.poses.push_back({f.t_ns, T_w_ref ? *T_w_ref * f.T_ref_b : f.nav.T_w_b()});
  }
  return t;
}

Trajectory OfflineRunResult::ground_truth_trajectory() const {
  Trajectory t;
  for (const NavState& s : ground_truth) {
    t.poses.push_back({s.t_ns, s.T_w_b()});
  }
  return t;
}

OfflineRunResult run_offline(const TrackerOptions& options, const EventSource& source,
                             const OfflineRunOptions& run_options) {
  Tracker tracker(options);
  if (run_options.back_end) tracker.set_mapper_present(static_cast<bool>(run_options.atlas));
  OfflineRunResult out;
  DatasetEvent e;
  std::optional<int64_t> first_t_ns;
  while (source(e)) {
    const int64_t t_ns = std::visit([](const auto& x) { return x.t_ns; }, e);
    if (!first_t_ns) first_t_ns = t_ns;
    if (t_ns < *first_t_ns + run_options.skip_ns && !std::holds_alternative<NavState>(e)) continue;
    if (const auto* imu = std::get_if<ImuSample>(&e)) {
      const ImuReject why = tracker.add_imu(*imu);
      if (why != ImuReject::kAccepted && run_options.verbose)
        std::fprintf(stderr, "IMU %lld: %s\n", static_cast<long long>(imu->t_ns), to_string(why));
    } else if (const auto* gt = std::get_if<NavState>(&e)) {
      out.ground_truth.push_back(*gt);
    } else {
      const FrameResult r = tracker.track(std::get<StereoFrame>(e));
      FrameRecord rec;
      rec.t_ns = r.t_ns;
      rec.accepted = r.accepted;
      rec.state = r.state;
      rec.method = r.method;
      rec.is_keyframe = r.is_keyframe;
      rec.tracked_points = r.tracked_points;
      rec.map_id = r.map_id;
      rec.quality = r.quality;
      rec.total_ms = r.total_ms;
      rec.stage_ms = r.stage_ms;
      rec.nav = r.nav;
      rec.message = r.message;
      if (const auto ref = tracker.map().latest_keyframe();
          ref && r.accepted && r.state != TrackState::kInitialising) {
        rec.ref_keyframe_id = ref->id;
        rec.T_ref_b = ref->state.T_w_b().inverse() * r.nav.T_w_b();
      }
      if (r.keyframe && run_options.back_end) {
        for (const MapCorrection& c :
             run_options.back_end(keyframe_msg(*r.keyframe, tracker.map(), r.map_id))) {
          const CorrectionResult applied = tracker.apply(c);
          rec.corrections += applied.applied;
          rec.correction_shift_m = std::max(rec.correction_shift_m, applied.shift_m);
          if (!applied.message.empty())
            rec.message += (rec.message.empty() ? "" : "; ") + applied.message;
        }
      }
      if (r.atlas_query && run_options.atlas) {
        const RelocAnswer answer = run_options.atlas(reloc_request_msg(*r.atlas_query, r.map_id));
        rec.message += (rec.message.empty() ? "" : "; ") + tracker.apply(answer);
      }
      if (run_options.verbose && !rec.message.empty())
        std::fprintf(stderr, "frame %lld [%s]: %s\n", static_cast<long long>(r.seq),
                     to_string(r.state), rec.message.c_str());
      out.frames.push_back(std::move(rec));
      if (run_options.progress && out.frames.size() % 100 == 0)
        std::fprintf(stderr, "  %zu frames, %lld keyframes, state %s\n", out.frames.size(),
                     static_cast<long long>(tracker.counters().keyframes), to_string(r.state));
    }
  }
  out.counters = tracker.counters();
  out.imu_counters = tracker.imu_counters();
  return out;
}

void write_timing_csv(const std::string& path, const OfflineRunResult& result) {
  // Stage columns in order of first appearance.
  std::vector<std::string> stages;
  std::map<std::string, size_t> index;
  for (const FrameRecord& f : result.frames)
    for (const auto& [name, ms] : f.stage_ms)
      if (index.emplace(name, stages.size()).second) stages.push_back(name);
  std::ostringstream out;
  out << "t_ns,state,method,keyframe,tracked,total_ms";
  for (const std::string& s : stages) out << "," << s << "_ms";
  out << "\n";
  for (const FrameRecord& f : result.frames) {
    out << f.t_ns << "," << to_string(f.state) << "," << to_string(f.method) << ","
        << (f.is_keyframe ? 1 : 0) << "," << f.tracked_points << "," << f.total_ms;
    std::vector<float> row(stages.size(), 0.0f);
    for (const auto& [name, ms] : f.stage_ms) row[index[name]] = ms;
    for (float ms : row) out << "," << ms;
    out << "\n";
  }
  write_file_atomically(path, out.str());
}

}  // namespace hs
