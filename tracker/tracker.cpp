#include "tracker/tracker.h"

#include <algorithm>
#include <cstring>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <stdexcept>
#include <unordered_set>

#include "common/imu/imu_residual.h"
#include "common/imu/static_init.h"
#include "common/imu/vi_alignment.h"
#include "tracker/direct_patch.h"
#include "tracker/stage_timer.h"

namespace hs {

const char* to_string(TrackState state) {
  switch (state) {
    case TrackState::kInitialising:
      return "INITIALISING";
    case TrackState::kTracking:
      return "TRACKING";
    case TrackState::kLost:
      return "LOST";
    case TrackState::kRelocalised:
      return "RELOCALISED";
  }
  return "?";
}

const char* to_string(TrackMethod method) {
  switch (method) {
    case TrackMethod::kNone:
      return "none";
    case TrackMethod::kDirect:
      return "direct";
    case TrackMethod::kDescriptors:
      return "descriptors";
    case TrackMethod::kRelocalisedReference:
      return "relocalised (reference keyframe)";
    case TrackMethod::kRelocalisedGlobal:
      return "relocalised (global)";
  }
  return "?";
}

namespace {

Eigen::Matrix<double, 15, 1> initial_sigmas(bool static_start) {
  // Pose: the gauge (origin, yaw) and the gravity direction from the accelerometer, so tight.
  // Velocity: zero at rest, unknown in motion. Biases: gyro from the static mean.
  Eigen::Matrix<double, 15, 1> s;
  s << Eigen::Vector3d::Constant(1e-3), Eigen::Vector3d::Constant(1e-3),
      Eigen::Vector3d::Constant(static_start ? 0.01 : 1.0),
      Eigen::Vector3d::Constant(static_start ? 0.005 : 0.05), Eigen::Vector3d::Constant(0.2);
  return s;
}

Matrix15d information_from_sigmas(const Eigen::Matrix<double, 15, 1>& sigma) {
  return sigma.cwiseInverse().cwiseAbs2().asDiagonal();
}

// Without the IMU: the last state moved on at its velocity, attitude held.
NavState constant_velocity(const NavState& last, int64_t t_ns) {
  NavState s = last;
  s.t_ns = t_ns;
  s.p_w_b += last.v_w * ns_to_s(t_ns - last.t_ns);
  return s;
}

// Whether the scene moved between two images: median optical flow of strong corners over
// half a pixel (a static camera shows only noise).
bool image_moved(const cv::Mat& previous, const cv::Mat& current) {
  std::vector<cv::Point2f> p0, p1;
  cv::goodFeaturesToTrack(previous, p0, 60, 0.01, 20.0);
  if (p0.size() < 10) return false;
  std::vector<uint8_t> ok;
  std::vector<float> err;
  cv::calcOpticalFlowPyrLK(previous, current, p0, p1, ok, err);
  std::vector<float> moved;
  for (size_t i = 0; i < p0.size(); ++i)
    if (ok[i]) moved.push_back(static_cast<float>(cv::norm(p1[i] - p0[i])));
  if (moved.size() < 10) return true;  // most corners lost: it moved
  std::nth_element(moved.begin(), moved.begin() + moved.size() / 2, moved.end());
  return moved[moved.size() / 2] > 0.5f;
}

}  // namespace

Tracker::Tracker(const TrackerOptions& options)
    : options_(options),
      imu_(options_.imu_buffer),
      map_(options_.local_map),
      optimizer_(options_.calib, options_.pose_opt),
      aligner_(options_.direct.sparse),
      builder_(options_),
      relocaliser_(options_, optimizer_),
      mono_init_(options_.calib.cam0.intrinsics, options_.mono.init) {
  if (options_.threads > 0) cv::setNumThreads(options_.threads);
}

Eigen::Isometry3d Tracker::T_w_c0(const NavState& nav) const {
  return nav.T_w_b() * options_.calib.cam0.T_b_c;
}

std::string Tracker::validate(const StereoFrame& frame) {
  const PinholeRadtan& cam = options_.calib.cam0.intrinsics;
  if (frame.cam0.empty() || frame.cam0.type() != CV_8UC1 || frame.cam0.cols != cam.width ||
      frame.cam0.rows != cam.height) {
    ++counters_.rejected_bad_image;
    return "cam0 image is " + std::to_string(frame.cam0.cols) + "x" +
           std::to_string(frame.cam0.rows) + (frame.cam0.type() == CV_8UC1 ? "" : " not mono8") +
           ", expected " + std::to_string(cam.width) + "x" + std::to_string(cam.height) +
           " mono8: frame dropped";
  }
  if (last_ && frame.t_ns <= last_->t_ns) {
    ++counters_.rejected_out_of_order;
    return std::string(frame.t_ns == last_->t_ns ? "duplicate" : "out-of-order") +
           " frame timestamp " + std::to_string(frame.t_ns) + " (previous " +
           std::to_string(last_->t_ns) + "): frame dropped";
  }
  // Once tracking, a frame the IMU does not reach is still tracked, on vision alone (track()).
  if (imu_.empty() || (state_ == TrackState::kInitialising &&
                       imu_behind_ns(frame.t_ns) > options_.max_camera_imu_offset_ns)) {
    ++counters_.rejected_clock_offset;
    return imu_.empty()
               ? "no IMU data yet: frame dropped"
               : "initialising: IMU is " + std::to_string(imu_behind_ns(frame.t_ns) / 1000000) +
                     " ms behind the camera (limit " +
                     std::to_string(options_.max_camera_imu_offset_ns / 1000000) +
                     " ms): frame dropped";
  }
  return "";
}

FrameResult Tracker::track(const StereoFrame& frame) {
  FrameResult r = track_frame(frame);
  // Keyframes of a moving start are in a world not yet aligned with gravity: a back end must
  // not see them (alignment rotates the map, and later keyframes carry the rotated points).
  if (r.state == TrackState::kInitialising) r.keyframe.reset();
  return r;
}

FrameResult Tracker::track_frame(const StereoFrame& frame_in) {
  FrameResult r;
  r.t_ns = frame_in.t_ns;
  r.seq = frame_in.seq;
  r.state = state_;
  r.map_id = map_id_;
  if (std::string err = validate(frame_in); !err.empty()) {
    r.message = std::move(err);
    return r;
  }
  StereoFrame frame = frame_in;
  if (options_.stereo) {
    const bool bad_right = !frame.cam1.empty() &&
                           (frame.cam1.size() != frame.cam0.size() || frame.cam1.type() != CV_8UC1);
    if (frame.cam1.empty() || bad_right) {
      ++counters_.missing_right_image;
      r.message = bad_right ? "cam1 image has the wrong size or type: tracked with cam0 only"
                            : "cam1 image missing: tracked with cam0 only";
      frame.cam1 = cv::Mat();
    }
  } else {
    frame.cam1 = cv::Mat();
  }
  r.accepted = true;
  ++counters_.frames;
  StageTimer timer(r);
  ImagePyramid pyr = build_pyramid(frame.cam0, options_.pyramid_levels);
  timer.stage("pyramid");

  if (state_ == TrackState::kInitialising) {
    initialise(frame, pyr, r);
    timer.stage("initialise");
    return r;
  }

  const ImuPreintegration pim = preintegrate_since_last(frame.t_ns);
  // An IMU gap longer than interpolation can bridge, or an IMU behind the camera (the window
  // ends extrapolated): this frame is tracked on vision alone from a constant-velocity guess.
  const bool use_imu = imu_usable(pim) && !bootstrap_;
  if (!imu_usable(pim)) {
    ++counters_.frames_without_imu;
    r.message = "IMU gap of " + std::to_string(pim.status().largest_gap_ns / 1000000) + " ms" +
                (imu_behind_ns(frame.t_ns) > 0
                     ? " (IMU " + std::to_string(imu_behind_ns(frame.t_ns) / 1000000) +
                           " ms behind the camera)"
                     : "") +
                ": tracked on vision alone";
  }
  NavState predicted = use_imu ? predict(last_->nav, pim, optimizer_.gravity())
                               : constant_velocity(last_->nav, frame.t_ns);
  predicted.t_ns = frame.t_ns;
  timer.stage("imu_predict");

  std::optional<OrbFeatures> features;
  std::string why;
  // After a loss the IMU cannot bridge, its prediction is no prior to track from: frame-to-frame
  // matching near it found 15 inliers 13 cm off the truth (4.5 s blackout), where
  // relocalisation, with its stricter inlier count and its PnP, or the atlas, places the frame.
  if (state_ == TrackState::kLost && lost_beyond_imu_bridge(frame.t_ns)) {
    why = "lost for " + std::to_string(ns_to_s(frame.t_ns - last_tracked_t_ns_)).substr(0, 4) +
          " s, longer than the IMU bridges: no frame-to-frame tracking";
  } else if (track_from_prediction(frame, pyr, predicted, pim, use_imu, features, why, r, timer)) {
    return r;
  }

  // Failure check fired (Algorithm 1): relocalise with the reference keyframe (Eq. 7), then
  // globally (Eq. 8).
  scale_window_.clear();  // its frames must chain
  if (bootstrap_ && bootstrap_->up_to_scale) {
    // A mono map of unknown scale cannot be carried by the IMU: start again.
    r.message = why;
    restart_mono(r);
    r.state = state_;
    return r;
  }
  if (bootstrap_) {
    bootstrap_.reset();
    why += "; vision-IMU alignment abandoned (gravity stays from the mean acceleration)";
  }
  if (!features) features = builder_.orb().extract(frame.cam0);
  RelocResult reloc;
  if (auto ref = map_.latest_keyframe()) {
    reloc = relocaliser_.against_keyframe(*ref, *features, predicted, map_);
    r.method = TrackMethod::kRelocalisedReference;
  }
  if (!reloc.ok) {
    reloc = relocaliser_.global(pyr.levels.back(), *features, predicted, map_);
    r.method = TrackMethod::kRelocalisedGlobal;
  }
  timer.stage("relocalise");
  if (reloc.ok) {
    if (const std::string veto = check_against_prediction(reloc.nav, predicted, frame.t_ns);
        !veto.empty()) {
      ++counters_.relocalisations_rejected;
      reloc.ok = false;
      reloc.message = veto;
    }
  }
  if (reloc.ok) {
    ++counters_.relocalisations;
    NavState nav = reloc.nav;
    nav.v_w = predicted.v_w;
    const double jump = (nav.p_w_b - predicted.p_w_b).norm();
    r.message = why + "; " + reloc.message;
    // A relocalisation that moves the estimate far from the IMU prediction is a stated jump.
    if (jump > 0.1) {
      map_id_ = new_map_id();
      r.message +=
          "; pose jumped " + std::to_string(jump) + " m: map id now " + std::to_string(map_id_);
    }
    state_ = TrackState::kRelocalised;
    lost_since_ns_ = -1;
    r.map_id = map_id_;
    accept(frame, std::move(pyr), nav, std::move(reloc.tracked), nullptr, &*features, r, timer);
    timer.stage("keyframe");
    return r;
  }

  // Lost: the IMU carries the state; after a while a new local map starts in place, or where
  // the mapper's atlas places the frame.
  ++counters_.lost_frames;
  if (lost_since_ns_ < 0) {
    lost_since_ns_ = frame.t_ns;
    atlas_request_.reset();
    atlas_fix_.reset();
    atlas_asked_since_ns_ = -1;
  }
  state_ = TrackState::kLost;
  r.method = TrackMethod::kNone;
  r.message = why + "; relocalisation failed: " + reloc.message;
  if (atlas_fix_ && frame.stereo()) {
    const Eigen::Isometry3d& C = atlas_fix_->correction;
    NavState nav = predicted;
    nav.set_T_w_b(C * predicted.T_w_b());
    nav.v_w = C.linear() * predicted.v_w;
    r.message += "; " + atlas_fix_->message;
    start_map_in_place(frame, pyr, nav, r, atlas_fix_->map_id);
    timer.stage("reinitialise");
    if (state_ != TrackState::kLost) {
      ++counters_.atlas_relocalisations;
      atlas_fix_.reset();
      return r;
    }
  }
  if (frame.t_ns - lost_since_ns_ >= options_.reinit_after_lost_ns && frame.stereo()) {
    const bool waiting = ask_atlas(frame, pyr, *features, predicted, r);
    if (!waiting) start_map_in_place(frame, pyr, predicted, r);
    timer.stage("reinitialise");
    if (state_ != TrackState::kLost) return r;
  } else if (frame.t_ns - lost_since_ns_ >= options_.reinit_after_lost_ns && !options_.stereo) {
    restart_mono(r);
  }
  r.state = state_;
  r.nav = predicted;
  r.quality = 0.0f;
  LastFrame lf;
  lf.t_ns = frame.t_ns;
  lf.pyramid = std::move(pyr);
  lf.nav = predicted;
  last_ = std::move(lf);
  return r;
}

bool Tracker::track_from_prediction(const StereoFrame& frame, ImagePyramid& pyr,
                                    const NavState& predicted, const ImuPreintegration& pim,
                                    bool use_imu, std::optional<OrbFeatures>& features,
                                    std::string& why, FrameResult& r, StageTimer& timer) {
  const Eigen::Isometry3d T_w_c_pred = T_w_c0(predicted);
  Correspondences corr;
  TrackMethod method = TrackMethod::kDescriptors;
  if (options_.descriptors == DescriptorMode::kHybrid) {
    const std::optional<Eigen::Isometry3d> aligned = align_to_last(pyr, T_w_c_pred);
    timer.stage("direct_align");
    // Without the photometric refinement the prediction is the guess: search wider.
    corr = direct_correspondences(pyr, aligned ? *aligned : T_w_c_pred,
                                  aligned && use_imu ? options_.patch_search_radius_px
                                                     : 3.0 * options_.patch_search_radius_px);
    timer.stage("patch_align");
    method = TrackMethod::kDirect;
  }
  if (corr.obs.size() < static_cast<size_t>(2 * options_.pose_opt.min_inliers)) {
    // Every-frame mode, or the direct correspondences failed (Sec. 3.1.3): descriptors.
    features = builder_.orb().extract(frame.cam0);
    timer.stage("orb_extract");
    corr = descriptor_correspondences(*features, T_w_c_pred);
    timer.stage("descriptor_match");
    method = TrackMethod::kDescriptors;
  }

  const PoseOptResult opt =
      use_imu ? optimise(predicted, corr, pim) : optimise_vision_only(predicted, corr);
  timer.stage("pose_opt");
  if (opt.valid()) {
    std::vector<TrackedObservation> tracked;
    for (size_t i = 0; i < corr.obs.size(); ++i)
      if (opt.inliers[i]) tracked.push_back({corr.point_ids[i], corr.obs[i].uv});
    state_ = TrackState::kTracking;
    lost_since_ns_ = -1;
    r.method = method;
    accept(frame, std::move(pyr), opt.state, std::move(tracked), &opt,
           features ? &*features : nullptr, r, timer);
    timer.stage("keyframe");
    if (bootstrap_) {
      advance_bootstrap(pim, r);
    } else if (!options_.stereo && !mapper_present_) {
      refine_scale(use_imu, r);
      timer.stage("scale_check");
    }
    return true;
  }
  why = "tracking failed (" + opt.reason + ")";
  return false;
}

void Tracker::advance_bootstrap(const ImuPreintegration& pim, FrameResult& r) {
  const Eigen::Isometry3d& T_b_c = options_.calib.cam0.T_b_c;
  bootstrap_->poses.push_back(
      {last_->t_ns, bootstrap_->up_to_scale ? T_w_c0(last_->nav) : last_->nav.T_w_b()});
  if (!bootstrap_->up_to_scale) bootstrap_->pims.push_back(pim);
  const int64_t span_ns = bootstrap_->poses.back().t_ns - bootstrap_->poses.front().t_ns;
  r.state = TrackState::kInitialising;
  if (span_ns < options_.vi_alignment_window_ns) {
    r.message += (r.message.empty() ? "" : "; ") + std::string("aligning vision and IMU (") +
                 std::to_string(span_ns / 1000000) + " of " +
                 std::to_string(options_.vi_alignment_window_ns / 1000000) + " ms)";
    return;
  }
  const ViAlignmentResult a = bootstrap_->up_to_scale
                                  ? align_mono(bootstrap_->poses, options_.mono.alignment)
                                  : align_visual_inertial(bootstrap_->poses, bootstrap_->pims);
  if (!a.ok) {
    // Mono: more motion may bring the acceleration the scale needs, so the window grows for a
    // while. Then (and for stereo at once) it slides on: a later stretch may be better
    // conditioned.
    if (!bootstrap_->up_to_scale || span_ns >= options_.mono.max_alignment_window_ns) {
      bootstrap_->poses.erase(bootstrap_->poses.begin());
      if (!bootstrap_->pims.empty()) bootstrap_->pims.erase(bootstrap_->pims.begin());
    }
    r.message += (r.message.empty() ? "" : "; ") + std::string("vision-IMU alignment failed (") +
                 a.reason + "), retrying over " + std::to_string(span_ns / 1000000) + " ms";
    return;
  }
  const Eigen::Matrix3d& R = a.R_wg_w;
  const WorldSimilarity S{R, a.scale};
  map_.transform_world(S, T_b_c);
  last_keyframe_T_w_c_ = S.camera(last_keyframe_T_w_c_);
  NavState nav = S.body(last_->nav, T_b_c);
  nav.v_w = R * a.v_w.back();
  nav.gyro_bias = a.gyro_bias;
  nav.accel_bias = a.accel_bias;
  last_->nav = nav;
  Eigen::Matrix<double, 15, 1> sigma;
  sigma << Eigen::Vector3d::Constant(1e-3), Eigen::Vector3d::Constant(1e-3),
      Eigen::Vector3d::Constant(0.05), Eigen::Vector3d::Constant(0.005),
      Eigen::Vector3d::Constant(a.accel_bias_estimated ? 0.05 : 0.2);
  last_->information = information_from_sigmas(sigma);
  last_->has_information = true;
  const bool bootstrap_up_to_scale = bootstrap_->up_to_scale;
  bootstrap_.reset();
  scale_window_.clear();
  r.state = state_;
  r.nav = nav;
  r.message += (r.message.empty() ? "" : "; ") +
               std::string("vision and IMU aligned: gravity tilt corrected by ") +
               std::to_string(Eigen::AngleAxisd(R).angle() * 180.0 / M_PI) + " deg" +
               (a.weak_excitation
                    ? (a.accel_bias_estimated ? " (little excitation: accel bias near its prior)"
                                              : " (little excitation: accel bias held)")
                    : "") +
               (bootstrap_up_to_scale ? ", scale " + std::to_string(a.scale) + " +- " +
                                            std::to_string(a.scale_sigma) + " over " +
                                            std::to_string(span_ns / 1000000) + " ms"
                                      : "");
}

ViAlignmentResult Tracker::align_mono(const std::vector<TimedPose>& camera_poses,
                                      const ViAlignmentOptions& options) const {
  // Poses at least alignment_spacing_ns apart (the newest kept): a dense window of every frame
  // costs the tracking thread 150 ms (room_mav, 4 s at 20 Hz) for little more information.
  std::vector<TimedPose> poses;
  for (size_t i = 0; i < camera_poses.size(); ++i)
    if (poses.empty() || i + 1 == camera_poses.size() ||
        camera_poses[i].t_ns - poses.back().t_ns >= options_.mono.alignment_spacing_ns)
      poses.push_back(camera_poses[i]);
  if (poses.size() > 2 &&
      poses.back().t_ns - poses[poses.size() - 2].t_ns < options_.mono.alignment_spacing_ns / 2)
    poses.erase(poses.end() - 2);
  ImuBias bias;
  bias.gyro = last_->nav.gyro_bias;
  bias.accel = last_->nav.accel_bias;
  std::vector<ImuPreintegration> pims;
  for (size_t k = 0; k + 1 < poses.size(); ++k) {
    pims.push_back(preintegrate(imu_.window(poses[k].t_ns, poses[k + 1].t_ns), poses[k].t_ns,
                                poses[k + 1].t_ns, bias, options_.imu));
    if (!imu_usable(pims.back())) {
      ViAlignmentResult refused;
      refused.reason = "an IMU gap in the window";
      return refused;
    }
  }
  return align_visual_inertial_up_to_scale(poses, options_.calib.cam0.T_b_c, pims, options);
}

void Tracker::refine_scale(bool imu_bridged, FrameResult& r) {
  if (!imu_bridged) scale_window_.clear();  // starts again at this frame
  std::vector<TimedPose>& w = scale_window_;
  w.push_back({last_->t_ns, T_w_c0(last_->nav)});
  while (w.size() > 2 && w.back().t_ns - w[1].t_ns >= options_.mono.refine_window_ns)
    w.erase(w.begin());
  if (w.back().t_ns - w.front().t_ns < options_.mono.refine_window_ns ||
      last_->t_ns - last_scale_check_ns_ < options_.mono.refine_period_ns)
    return;
  last_scale_check_ns_ = last_->t_ns;
  ViAlignmentOptions o = options_.mono.alignment;
  o.max_scale_sigma = options_.mono.refine_max_scale_sigma;
  const ViAlignmentResult a = align_mono(w, o);
  // Corrected only when the IMU says the scale is off by more than twice its uncertainty.
  if (!a.ok || std::abs(a.scale - 1.0) <= 2.0 * a.scale_sigma) return;
  // About the current camera: the pose does not jump, the map (and the path behind) rescales.
  WorldSimilarity S;
  S.scale = a.scale;
  S.t = (1.0 - a.scale) * T_w_c0(last_->nav).translation();
  const Eigen::Isometry3d& T_b_c = options_.calib.cam0.T_b_c;
  map_.transform_world(S, T_b_c);
  last_keyframe_T_w_c_ = S.camera(last_keyframe_T_w_c_);
  last_->nav = S.body(last_->nav, T_b_c);
  last_->nav.v_w = a.v_w.back();
  ++counters_.scale_corrections;
  scale_window_.clear();
  r.nav = last_->nav;
  r.message += (r.message.empty() ? "" : "; ") + std::string("map rescaled by ") +
               std::to_string(a.scale) + " +- " + std::to_string(a.scale_sigma) +
               " (IMU over the last " + std::to_string(options_.mono.refine_window_ns / 1000000) +
               " ms)";
}

int64_t Tracker::imu_behind_ns(int64_t t_ns) const {
  return imu_.empty() ? t_ns : std::max<int64_t>(0, t_ns - imu_.latest_t_ns());
}

bool Tracker::imu_usable(const ImuPreintegration& pim) const {
  return pim.t1_ns() > pim.t0_ns() &&
         pim.status().largest_gap_ns <= options_.max_interpolated_imu_gap_ns &&
         pim.status().extrapolated_ns <= options_.max_interpolated_imu_gap_ns;
}

std::string Tracker::check_against_prediction(const NavState& reloc, const NavState& predicted,
                                              int64_t t_ns) const {
  // While the IMU has carried the state for a short time, its prediction bounds where the body
  // can be: a relocalisation far from it is a false match (repeated structure, a keyframe built
  // at a wrong pose). After a long loss the prediction no longer says much.
  const double dt_s = ns_to_s(t_ns - last_tracked_t_ns_);
  if (dt_s > ns_to_s(options_.reloc_gate.trust_imu_ns)) return "";
  const double gate_m =
      options_.reloc_gate.position_m + 0.5 * options_.reloc_gate.accel_error_mps2 * dt_s * dt_s;
  const double gate_rad = options_.reloc_gate.rotation_rad;
  const double jump_m = (reloc.p_w_b - predicted.p_w_b).norm();
  const double jump_rad = Eigen::AngleAxisd(predicted.q_w_b.inverse() * reloc.q_w_b).angle();
  if (jump_m <= gate_m && jump_rad <= gate_rad) return "";
  return "relocalisation rejected: " + std::to_string(jump_m) + " m / " +
         std::to_string(jump_rad * 180.0 / M_PI) + " deg from the IMU prediction (gate " +
         std::to_string(gate_m) + " m / " + std::to_string(gate_rad * 180.0 / M_PI) +
         " deg after " + std::to_string(dt_s) + " s without tracking)";
}

PoseOptResult Tracker::optimise_vision_only(const NavState& predicted, const Correspondences& c) {
  PoseOptResult opt = optimizer_.optimise_pose(predicted, c.obs);
  if (opt.valid()) {
    // Velocity by finite difference; the IMU term of the next frames refines it.
    const double dt_s = ns_to_s(predicted.t_ns - last_->t_ns);
    if (dt_s > 0) opt.state.v_w = (opt.state.p_w_b - last_->nav.p_w_b) / dt_s;
    opt.information.setZero();  // no 15-dim information: accept() sets a loose prior
  }
  return opt;
}

ImuPreintegration Tracker::preintegrate_since_last(int64_t t_ns) {
  ImuBias bias;
  bias.gyro = last_->nav.gyro_bias;
  bias.accel = last_->nav.accel_bias;
  ImuPreintegration pim =
      preintegrate(imu_.window(last_->t_ns, t_ns), last_->t_ns, t_ns, bias, options_.imu);
  if (pim.status().has_gap()) ++counters_.imu_gaps;
  return pim;
}

std::optional<Eigen::Isometry3d> Tracker::align_to_last(const ImagePyramid& pyr,
                                                        const Eigen::Isometry3d& T_w_c_pred) {
  if (last_->tracked.size() < static_cast<size_t>(options_.direct.sparse.min_points))
    return std::nullopt;
  const Eigen::Isometry3d T_w_c_last = T_w_c0(last_->nav);
  const Eigen::Isometry3d T_c_w_last = T_w_c_last.inverse();
  std::vector<Eigen::Vector3d> p_ref;
  p_ref.reserve(last_->tracked.size());
  for (const TrackedObservation& t : last_->tracked)
    if (const MapPoint* p = map_.point(t.point_id)) p_ref.push_back(T_c_w_last * p->p_w);
  if (p_ref.size() < static_cast<size_t>(options_.direct.sparse.min_points)) return std::nullopt;
  const SparseAlignResult res = aligner_.align(last_->pyramid, pyr, options_.calib.cam0.intrinsics,
                                               p_ref, T_w_c_pred.inverse() * T_w_c_last);
  if (!res.valid()) return std::nullopt;
  return T_w_c_last * res.T_cur_ref.inverse();
}

Tracker::Correspondences Tracker::direct_correspondences(const ImagePyramid& pyr,
                                                         const Eigen::Isometry3d& T_w_c,
                                                         double search_radius_px) {
  const PinholeRadtan& cam = options_.calib.cam0.intrinsics;
  const Eigen::Isometry3d T_c_w = T_w_c.inverse();
  std::unordered_set<int64_t> in_last;
  for (const TrackedObservation& t : last_->tracked) in_last.insert(t.point_id);

  // Candidates visible in the predicted view; points tracked in the previous frame first,
  // then the most often tracked, one per grid cell before any cell gets a second.
  struct Candidate {
    const MapPoint* point;
    Eigen::Vector2d uv;
    int cell;
    int priority;
  };
  std::vector<Candidate> candidates;
  const int grid = options_.point_grid_px;
  const int cols = (cam.width + grid - 1) / grid;
  for (const auto& [id, p] : map_.points()) {
    const Eigen::Vector3d p_c = T_c_w * p.p_w;
    Eigen::Vector2d uv;
    if (p_c.z() < 0.1 || !cam.project(p_c, &uv) || !cam.in_image(uv, 8.0)) continue;
    const int cell = static_cast<int>(uv.y()) / grid * cols + static_cast<int>(uv.x()) / grid;
    candidates.push_back({&p, uv, cell, (in_last.count(id) ? 1000000 : 0) + p.times_tracked});
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return a.priority != b.priority ? a.priority > b.priority : a.point->id < b.point->id;
  });
  // Round k gives each cell its k-th point, until the budget is spent.
  std::vector<int> per_cell(static_cast<size_t>(cols * ((cam.height + grid - 1) / grid)), 0);
  std::vector<uint8_t> taken(candidates.size(), 0);
  std::vector<const Candidate*> selected;
  const size_t budget = static_cast<size_t>(options_.max_points_per_frame);
  for (int round = 0; selected.size() < budget && selected.size() < candidates.size(); ++round)
    for (size_t i = 0; i < candidates.size() && selected.size() < budget; ++i) {
      const Candidate& c = candidates[i];
      if (taken[i] || per_cell[c.cell] != round) continue;
      ++per_cell[c.cell];
      taken[i] = 1;
      selected.push_back(&c);
    }

  // The points are aligned independently (each result in its own slot, so the outcome does
  // not depend on the thread count): split over the cores.
  std::vector<const Keyframe*> ref_kf(selected.size(), nullptr);
  for (size_t i = 0; i < selected.size(); ++i) {
    const std::shared_ptr<Keyframe> kf = map_.keyframe(selected[i]->point->ref_keyframe_id);
    if (kf && !kf->pyramid.levels.empty()) ref_kf[i] = kf.get();
  }
  std::vector<PatchAlignResult> results(selected.size());
  cv::parallel_for_(cv::Range(0, static_cast<int>(selected.size())), [&](const cv::Range& range) {
    for (int i = range.start; i < range.end; ++i) {
      const Keyframe* kf = ref_kf[i];
      if (!kf) continue;
      const Candidate* c = selected[i];
      const Eigen::Isometry3d T_cur_ref = T_c_w * kf->T_w_c0;
      const Eigen::Vector3d p_ref = kf->T_w_c0.inverse() * c->point->p_w;
      const Eigen::Matrix2d A = affine_warp_cur_ref(
          cam, p_ref, T_cur_ref, kf->T_w_c0.linear().transpose() * c->point->n_w);
      results[i] = align_patch(kf->pyramid, c->point->ref_uv, A, pyr, c->uv, search_radius_px,
                               options_.direct.patch);
    }
  });
  Correspondences out;
  for (size_t i = 0; i < selected.size(); ++i) {
    if (!ref_kf[i] || !results[i].ok()) continue;
    PoseObservation o;
    o.p_w = selected[i]->point->p_w;
    o.uv = results[i].uv_cur;
    out.obs.push_back(o);
    out.point_ids.push_back(selected[i]->point->id);
  }
  return out;
}

Tracker::Correspondences Tracker::descriptor_correspondences(const OrbFeatures& features,
                                                             const Eigen::Isometry3d& T_w_c) {
  const PinholeRadtan& cam = options_.calib.cam0.intrinsics;
  const Eigen::Isometry3d T_c_w = T_w_c.inverse();
  std::vector<const MapPoint*> visible;
  std::vector<Eigen::Vector2d> predicted;
  for (const auto& [id, p] : map_.points()) {
    const Eigen::Vector3d p_c = T_c_w * p.p_w;
    Eigen::Vector2d uv;
    if (p_c.z() < 0.1 || !cam.project(p_c, &uv)) continue;
    visible.push_back(&p);
    predicted.push_back(uv);
  }
  // Deterministic order regardless of hash-map iteration.
  std::vector<size_t> order(visible.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return visible[a]->id < visible[b]->id; });
  cv::Mat query(static_cast<int>(visible.size()), 32, CV_8U);
  std::vector<Eigen::Vector2d> predicted_sorted;
  for (size_t k = 0; k < order.size(); ++k) {
    std::memcpy(query.ptr<uint8_t>(static_cast<int>(k)), visible[order[k]]->descriptor.data(), 32);
    predicted_sorted.push_back(predicted[order[k]]);
  }
  std::vector<Eigen::Vector2f> kp_uv;
  for (const cv::KeyPoint& kp : features.keypoints) kp_uv.emplace_back(kp.pt.x, kp.pt.y);
  const KeypointGrid grid(kp_uv, cam.width, cam.height);
  const std::vector<int> match =
      match_by_projection(query, predicted_sorted, features.descriptors, grid, options_.matching);
  Correspondences out;
  for (size_t k = 0; k < match.size(); ++k) {
    if (match[k] < 0) continue;
    const cv::KeyPoint& kp = features.keypoints[match[k]];
    PoseObservation o;
    o.p_w = visible[order[k]]->p_w;
    o.uv = features.uv(match[k]);
    o.sigma_px = level_sigma_px(kp.octave, options_.orb.scale_factor);
    out.obs.push_back(o);
    out.point_ids.push_back(visible[order[k]]->id);
  }
  return out;
}

PoseOptResult Tracker::optimise(const NavState& predicted, const Correspondences& c,
                                const ImuPreintegration& pim) {
  PreviousState prev;
  prev.state = last_->nav;
  prev.fixed = !last_->has_information;
  prev.information = options_.prior_fading * last_->information;
  if (pim.t1_ns() > pim.t0_ns()) {
    try {
      return optimizer_.optimise_inertial(predicted, c.obs, pim, prev);
    } catch (const std::invalid_argument&) {
      // Degenerate preintegration (e.g. no IMU across the interval): vision alone.
    }
  }
  return optimizer_.optimise_pose(predicted, c.obs);
}

void Tracker::accept(const StereoFrame& frame, ImagePyramid pyr, const NavState& nav,
                     std::vector<TrackedObservation> tracked, const PoseOptResult* opt,
                     const OrbFeatures* features, FrameResult& r, StageTimer& timer) {
  for (const TrackedObservation& t : tracked)
    if (MapPoint* p = map_.point(t.point_id)) ++p->times_tracked;

  // Eq. 14 on rotation-compensated pixels: the keyframe's rays turned by the rotation since,
  // so that turning in place (which adds no triangulation baseline) does not spawn keyframes.
  const Eigen::Isometry3d T_w_c = T_w_c0(nav);
  const Eigen::Matrix3d R_cur_kf = T_w_c.linear().transpose() * last_keyframe_T_w_c_.linear();
  std::vector<Eigen::Vector2d> uv_kf, uv_cur;
  for (const TrackedObservation& t : tracked) {
    const auto it = last_keyframe_rays_.find(t.point_id);
    Eigen::Vector2d uv;
    if (it == last_keyframe_rays_.end() ||
        !options_.calib.cam0.intrinsics.project(R_cur_kf * it->second, &uv))
      continue;
    uv_kf.push_back(uv);
    uv_cur.push_back(t.uv);
  }
  const KeyframeDecision decision =
      decide_keyframe(options_.keyframe, pose_change_norm(last_keyframe_T_w_c_, T_w_c),
                      mean_parallax(uv_kf, uv_cur), static_cast<int>(tracked.size()),
                      frame.t_ns - last_keyframe_t_ns_);
  const FeatureSource found_by =
      r.method == TrackMethod::kDirect ? FeatureSource::kDirect : FeatureSource::kDescriptor;
  for (const TrackedObservation& t : tracked) r.features.push_back({t.uv.cast<float>(), found_by});
  if (decision.is_keyframe || r.state == TrackState::kRelocalised) {
    KeyframeBuildStats stats;
    auto kf = builder_.build(frame, pyr, nav, tracked, features, map_, &stats, &timer);
    if (const auto prev = map_.latest_keyframe()) kf->prev_keyframe_id = prev->id;
    kf->imu = imu_.window(last_keyframe_t_ns_, frame.t_ns);
    // The new points are tracked from the next frame on.
    for (size_t i = 0; i < kf->point_ids.size(); ++i)
      if (kf->point_ids[i] >= 0 &&
          !std::any_of(tracked.begin(), tracked.end(),
                       [&](const TrackedObservation& t) { return t.point_id == kf->point_ids[i]; }))
        tracked.push_back({kf->point_ids[i], kf->features.uv(i)});
    for (size_t i = r.features.size(); i < tracked.size(); ++i)
      r.features.push_back({tracked[i].uv.cast<float>(), FeatureSource::kNew});
    map_.add_keyframe(kf);
    ++counters_.keyframes;
    remember_keyframe_view(frame.t_ns, T_w_c, tracked);
    r.is_keyframe = true;
    r.keyframe = kf;
    const std::string why = decision.is_keyframe ? decision.reason : "relocalised";
    r.message += (r.message.empty() ? "" : "; ") + std::string("keyframe (") + why + ", " +
                 std::to_string(stats.new_points) + " new points)";
  }
  last_tracked_t_ns_ = frame.t_ns;
  r.state = state_;
  r.nav = nav;
  r.tracked_points = static_cast<int>(tracked.size());
  if (opt) r.pose_covariance = opt->pose_covariance;
  r.quality = static_cast<float>(
      std::min(1.0, static_cast<double>(r.tracked_points) / (2.0 * options_.keyframe.min_tracked)));

  LastFrame lf;
  lf.t_ns = frame.t_ns;
  lf.pyramid = std::move(pyr);
  lf.nav = nav;
  lf.tracked = std::move(tracked);
  if (opt && !opt->information.isZero()) {
    lf.information = opt->information;
    lf.has_information = true;
  } else {
    // Relocalised or tracked without the IMU: velocity and biases are guesses, so the next
    // frame's IMU term starts from a loose prior rather than holding them fixed.
    lf.information = information_from_sigmas(initial_sigmas(false));
    lf.has_information = true;
  }
  last_ = std::move(lf);
}

bool Tracker::initialise(const StereoFrame& frame, const ImagePyramid& pyr, FrameResult& r) {
  r.state = TrackState::kInitialising;
  if (!options_.stereo) return initialise_mono(frame, pyr, r);
  if (!frame.stereo()) {
    r.message = "initialising: waiting for a stereo frame";
    return false;
  }
  const std::vector<ImuSample> window =
      imu_.window(frame.t_ns - options_.static_init_window_ns, frame.t_ns);
  // Gravity needs a full window of IMU history (a static one gives the gyro bias too).
  const int64_t span = window.empty() ? 0 : frame.t_ns - window.front().t_ns;
  const cv::Mat previous = init_previous_image_;
  init_previous_image_ = frame.cam0;
  if (span < options_.static_init_window_ns) {
    r.message = "initialising: collecting IMU for the gravity direction (" +
                std::to_string(span / 1000000) + " of " +
                std::to_string(options_.static_init_window_ns / 1000000) + " ms)";
    return false;
  }
  StaticInitResult gravity = initialise_from_static(window, options_.imu);
  // Constant velocity looks static to the IMU: the images tell.
  if (gravity.ok && !previous.empty() && image_moved(previous, frame.cam0)) {
    gravity.ok = false;
    gravity.reason = "the IMU looks static but the image moves";
  }
  NavState nav;
  nav.t_ns = frame.t_ns;
  nav.q_w_b = gravity.q_w_b;
  if (gravity.ok) nav.gyro_bias = gravity.gyro_bias;
  start_map_in_place(frame, pyr, nav, r);
  if (state_ == TrackState::kInitialising) return false;
  // The first state's prior: see initial_sigmas.
  last_->information = information_from_sigmas(initial_sigmas(gravity.ok));
  last_->has_information = true;
  if (gravity.ok) {
    r.message += "; static start: gravity and gyro bias from the IMU";
    return true;
  }
  // Moving: the mean acceleration is not gravity. Track on vision alone for a while, then
  // align the visual poses with the IMU (gravity, velocity, biases) before reporting poses.
  bootstrap_ = Bootstrap{false, {{frame.t_ns, nav.T_w_b()}}, {}};
  r.state = TrackState::kInitialising;
  r.message += "; moving start (" + gravity.reason + "): aligning vision and IMU";
  return true;
}

bool Tracker::initialise_mono(const StereoFrame& frame, const ImagePyramid& pyr, FrameResult& r) {
  const MonoInitResult two = mono_init_.add_frame(frame.t_ns, frame.cam0);
  if (!two.ok) {
    r.message = "initialising (mono): " + two.reason;
    return false;
  }
  // The IMU must bridge the two views: they start the alignment's window.
  const std::vector<ImuSample> samples = imu_.window(two.ref_t_ns, frame.t_ns);
  const ImuPreintegration pim =
      preintegrate(samples, two.ref_t_ns, frame.t_ns, ImuBias{}, options_.imu);
  if (!imu_usable(pim)) {
    mono_init_.reset();
    r.message = "initialising (mono): the IMU does not cover the two views: a new reference";
    return false;
  }
  // Attitude guess: the mean acceleration taken for gravity (the alignment corrects the tilt).
  const StaticInitResult level = initialise_from_static(samples, options_.imu);
  std::vector<double> depths;
  for (const Eigen::Vector3d& p : two.p_ref) depths.push_back(p.z());
  std::nth_element(depths.begin(), depths.begin() + depths.size() / 2, depths.end());
  const double scale = options_.mono.initial_median_depth_m / depths[depths.size() / 2];
  const Eigen::Isometry3d& T_b_c = options_.calib.cam0.T_b_c;
  Eigen::Isometry3d T_w_b_ref = Eigen::Isometry3d::Identity();
  T_w_b_ref.linear() = level.q_w_b.toRotationMatrix();
  const Eigen::Isometry3d T_w_c_ref = T_w_b_ref * T_b_c;
  Eigen::Isometry3d T_ref_cur = two.T_ref_cur;
  T_ref_cur.translation() *= scale;
  const Eigen::Isometry3d T_w_c_cur = T_w_c_ref * T_ref_cur;
  NavState nav;
  nav.t_ns = frame.t_ns;
  nav.set_T_w_b(T_w_c_cur * T_b_c.inverse());

  // The first keyframe sees the two-view points where they are now; they take the keypoints
  // (and descriptors) they are attached to there, and the few ORB cannot describe go.
  map_.clear();
  std::vector<TrackedObservation> tracked;
  for (size_t k = 0; k < two.p_ref.size(); ++k) {
    MapPoint p;
    p.id = map_.new_point_id();
    p.p_w = T_w_c_ref * (scale * two.p_ref[k]);
    map_.add_point(p);
    tracked.push_back({p.id, two.uv_cur[k]});
  }
  KeyframeBuildStats stats;
  auto kf = builder_.build(frame, pyr, nav, tracked, nullptr, map_, &stats);
  std::unordered_set<int64_t> attached;
  for (size_t i = 0; i < kf->point_ids.size(); ++i) {
    MapPoint* p = kf->point_ids[i] >= 0 ? map_.point(kf->point_ids[i]) : nullptr;
    if (!p) continue;
    std::memcpy(p->descriptor.data(), kf->features.descriptors.ptr<uint8_t>(static_cast<int>(i)),
                32);
    p->octave = kf->features.keypoints[i].octave;
    attached.insert(p->id);
  }
  for (const TrackedObservation& t : tracked)
    if (!attached.count(t.point_id)) map_.remove_point(t.point_id);
  if (attached.size() < static_cast<size_t>(options_.init_min_points)) {
    map_.clear();
    mono_init_.reset();
    r.message = "initialising (mono): only " + std::to_string(attached.size()) +
                " two-view points kept (" + std::to_string(options_.init_min_points) +
                " needed): a new reference";
    return false;
  }
  map_.add_keyframe(kf);
  ++counters_.keyframes;
  begin_local_map(pyr, nav, kf, r);
  // Vision alone until the IMU gives scale and gravity; the first interval is the two views'.
  // The reference pose starts the window when the IMU interval to it is short enough for one
  // bias (a reference kept through a still start can be seconds old).
  if (frame.t_ns - two.ref_t_ns <= options_.vi_alignment_window_ns)
    bootstrap_ = Bootstrap{true, {{two.ref_t_ns, T_w_c_ref}, {frame.t_ns, T_w_c_cur}}, {}};
  else
    bootstrap_ = Bootstrap{true, {{frame.t_ns, T_w_c_cur}}, {}};
  r.state = TrackState::kInitialising;
  r.message = "initialising (mono): two views " +
              std::to_string(ns_to_s(frame.t_ns - two.ref_t_ns)).substr(0, 4) + " s apart (" +
              (two.homography ? "homography" : "essential matrix") + ", " +
              std::to_string(attached.size()) + " points); aligning vision and IMU for the scale";
  return true;
}

void Tracker::restart_mono(FrameResult& r) {
  state_ = TrackState::kInitialising;
  mono_init_.reset();
  bootstrap_.reset();
  scale_window_.clear();
  map_.clear();
  map_id_ = new_map_id();
  ++counters_.reinitialisations;
  r.message += "; a mono map restarts from two views: map id now " + std::to_string(map_id_);
}

bool Tracker::loss_bridged(int64_t t_ns, const NavState& nav) const {
  const std::shared_ptr<Keyframe> last_kf = map_.latest_keyframe();
  if (!last_kf || lost_beyond_imu_bridge(t_ns)) return false;
  ImuBias bias;
  bias.gyro = nav.gyro_bias;
  bias.accel = nav.accel_bias;
  return imu_usable(preintegrate(imu_.window(last_kf->state.t_ns, t_ns), last_kf->state.t_ns, t_ns,
                                 bias, options_.imu));
}

void Tracker::start_map_in_place(const StereoFrame& frame, const ImagePyramid& pyr,
                                 const NavState& nav, FrameResult& r, int32_t atlas_map_id) {
  LocalMap trial_map = map_;
  trial_map.retire_window();
  KeyframeBuildStats stats;
  auto kf = builder_.build(frame, pyr, nav, {}, nullptr, trial_map, &stats);
  if (stats.new_points < options_.init_min_points) {
    r.message += (r.message.empty() ? "" : "; ") + std::string("map start needs ") +
                 std::to_string(options_.init_min_points) + " stereo points, found " +
                 std::to_string(stats.new_points);
    return;
  }
  const bool first = state_ == TrackState::kInitialising;
  // A short loss the IMU bridged without a gap (a camera blackout, a dark passage): the pose the
  // new local map starts from is the old map's, dead-reckoned, and the map id stays. Its first
  // keyframe names no previous one: an IMU factor over the whole loss, from the last keyframe's
  // state, pulled the mapper's new keyframes 8 cm / 1.3 deg off the tracker's dead reckoning
  // (blackout scenario: ATE 1.17 cm instead of 0.75). After a longer loss, or across an IMU
  // gap, the start has no link to the old map: a new epoch.
  // Placed by the atlas: the map id it named, which the mapper joined to the place's world.
  const bool atlas = atlas_map_id >= 0;
  const bool continues = !first && !atlas && loss_bridged(frame.t_ns, nav);
  map_ = std::move(trial_map);
  map_.add_keyframe(kf);
  ++counters_.keyframes;
  if (!first) {
    ++counters_.reinitialisations;
    if (continues)
      ++counters_.maps_continued;
    else
      map_id_ = atlas ? atlas_map_id : new_map_id();
  }
  begin_local_map(pyr, nav, kf, r);
  r.message += (r.message.empty() ? "" : "; ") +
               std::string(first   ? "map initialised"
                           : atlas ? "new local map started where the atlas placed the frame"
                                   : "new local map started in place") +
               " with " + std::to_string(stats.new_points) + " stereo points" +
               (first       ? ""
                : continues ? ": map id " + std::to_string(map_id_) +
                                  " continues, the IMU carried the pose over the loss"
                            : ": map id now " + std::to_string(map_id_));
}

void Tracker::begin_local_map(const ImagePyramid& pyr, const NavState& nav,
                              const std::shared_ptr<Keyframe>& kf, FrameResult& r) {
  state_ = TrackState::kTracking;
  lost_since_ns_ = -1;
  std::vector<TrackedObservation> tracked;
  for (size_t i = 0; i < kf->point_ids.size(); ++i)
    if (kf->point_ids[i] >= 0) tracked.push_back({kf->point_ids[i], kf->features.uv(i)});
  remember_keyframe_view(kf->state.t_ns, kf->T_w_c0, tracked);

  last_tracked_t_ns_ = kf->state.t_ns;
  r.state = state_;
  r.map_id = map_id_;
  r.nav = nav;
  r.is_keyframe = true;
  r.keyframe = kf;
  r.tracked_points = static_cast<int>(tracked.size());
  for (const TrackedObservation& t : tracked)
    r.features.push_back({t.uv.cast<float>(), FeatureSource::kNew});
  r.quality = 0.5f;
  LastFrame lf;
  lf.t_ns = kf->state.t_ns;
  lf.pyramid = pyr;
  lf.nav = nav;
  lf.tracked = std::move(tracked);
  // The initial prior (initialise() tightens it for a static start).
  lf.information = information_from_sigmas(initial_sigmas(false));
  lf.has_information = true;
  last_ = std::move(lf);
}

void Tracker::remember_keyframe_view(int64_t t_ns, const Eigen::Isometry3d& T_w_c,
                                     const std::vector<TrackedObservation>& tracked) {
  last_keyframe_t_ns_ = t_ns;
  last_keyframe_T_w_c_ = T_w_c;
  last_keyframe_rays_.clear();
  for (const TrackedObservation& t : tracked)
    last_keyframe_rays_[t.point_id] = options_.calib.cam0.intrinsics.unproject(t.uv);
}

}  // namespace hs
