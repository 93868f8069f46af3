#pragma once
// The HS-SLAM tracker (paper Algorithm 1, stereo-inertial): per frame, IMU prediction (Eq. 16),
// coarse-to-fine direct alignment against the previous frame (Eq. 17-18), per-point patch
// alignment of local-map points against their reference keyframes, motion-only
// visual-inertial optimisation (Eq. 5-6), the failure check, relocalisation (Eq. 7-8), and the
// keyframe decision (Eq. 13-15) with ORB extraction only at keyframes. It keeps its own bounded
// local map, so it runs without a mapper. Single-threaded and deterministic.
#include <memory>
#include <optional>
#include <unordered_map>
#include <vector>

#include "common/core/map_correction.h"
#include "common/core/reloc_answer.h"
#include "common/dataset/stereo_frame.h"
#include "common/imu/vi_alignment.h"
#include "tracker/direct_align.h"
#include "tracker/imu_buffer.h"
#include "tracker/keyframe_builder.h"
#include "tracker/local_map.h"
#include "tracker/mono_initialiser.h"
#include "tracker/pose_opt.h"
#include "tracker/relocaliser.h"
#include "tracker/stage_timer.h"
#include "tracker/tracker_options.h"
#include "tracker/tracker_types.h"

namespace hs {

// Cumulative; every field is published in TRACKER_STATUS (tracker/node/node_messages.cpp).
struct TrackerCounters {
  int64_t frames = 0;
  int64_t keyframes = 0;
  int64_t rejected_out_of_order = 0;  // frame timestamp not after the previous frame's
  int64_t rejected_bad_image = 0;     // wrong size / type, or empty
  int64_t rejected_clock_offset = 0;  // frame too far from the IMU clock
  int64_t missing_right_image = 0;    // stereo rig, cam1 absent (tracked with cam0 only)
  int64_t imu_gaps = 0;               // frame intervals with an IMU gap (bridged)
  int64_t lost_frames = 0;
  int64_t relocalisations = 0;
  int64_t relocalisations_rejected = 0;  // too far from the IMU prediction
  int64_t frames_without_imu = 0;        // IMU gap or IMU behind: tracked on vision alone
  int64_t reinitialisations = 0;         // local maps started in place after a loss
  int64_t maps_continued = 0;            // ... of them continuing the map (short loss, IMU bridged)
  int64_t atlas_requests = 0;            // lost frames sent to the mapper's atlas
  int64_t atlas_relocalisations = 0;     // ... placed by it: a local map started there
  int64_t atlas_answers_ignored = 0;     // not for the pending request, or tracking resumed
  int64_t scale_corrections = 0;         // mono: the map rescaled by the IMU's scale estimate
  int64_t corrections_applied = 0;       // mapper corrections (MAP_UPDATE)
  int64_t corrections_ignored = 0;       // for another map id, or no keyframe the tracker still has
  int64_t correction_jumps = 0;          // applied, but moved the pose enough to change the map id
  // Sensor time from the newest keyframe a correction corrects to the frame it is applied after:
  // how stale the mapper's corrections are (0 in process; the mapper's latency over LCM).
  int64_t last_correction_lag_ms = 0;
  int64_t max_correction_lag_ms = 0;
};

// What applying one mapper correction did.
struct CorrectionResult {
  bool applied = false;
  double shift_m = 0.0;  // how far the current pose moved
  double shift_rad = 0.0;
  std::string message;
};

class Tracker {
 public:
  explicit Tracker(const TrackerOptions& options);

  // IMU samples must be added before the frames they cover (in sensor-time order overall).
  ImuReject add_imu(const ImuSample& sample) { return imu_.push(sample); }
  FrameResult track(const StereoFrame& frame);
  // Applies a mapper correction to the local map (keyframe states, point positions, removed
  // points) and moves the current state with the newest corrected keyframe the tracker has.
  CorrectionResult apply(const MapCorrection& correction);
  // The mapper's answer to the pending atlas request (FrameResult::atlas_query): when found,
  // the next lost frame starts a local map at the place the atlas gives, carried forward by the
  // IMU, in the answer's map id. Returns what it did, for the status message.
  std::string apply(const RelocAnswer& answer);
  // A mapper consumes the keyframes: they carry a stereo view of every tracked point.
  // A mono map's scale is then the mapper's (its visual-inertial bundle adjustment), not rescaled
  // here as well.
  // `atlas`: it answers relocalisation requests (FrameResult::atlas_query).
  void set_mapper_present(bool atlas = true) {
    builder_.set_stereo_for_tracked(true);
    mapper_present_ = true;
    atlas_present_ = atlas;
  }

  const TrackerCounters& counters() const { return counters_; }
  const ImuBufferCounters& imu_counters() const { return imu_.counters(); }
  const LocalMap& map() const { return map_; }
  const TrackerOptions& options() const { return options_; }
  TrackState state() const { return state_; }
  // Gravity in the tracker's world: -z until a mapper refines it.
  const Eigen::Vector3d& gravity_w() const { return optimizer_.gravity(); }

 private:
  struct LastFrame {
    int64_t t_ns = 0;
    ImagePyramid pyramid;
    NavState nav;
    std::vector<TrackedObservation> tracked;
    Matrix15d information = Matrix15d::Zero();
    bool has_information = false;
  };
  struct Correspondences {
    std::vector<PoseObservation> obs;
    std::vector<int64_t> point_ids;
  };

  // Moving start: visual poses and the preintegrations between them, until the window spans
  // options_.vi_alignment_window_ns and align_visual_inertial() finds gravity. Mono: cam0 poses
  // known up to scale, and the scale is found too (align_mono: no preintegrations kept).
  struct Bootstrap {
    bool up_to_scale = false;
    std::vector<TimedPose> poses;  // body poses; mono: cam0 poses
    std::vector<ImuPreintegration> pims;
  };

  FrameResult track_frame(const StereoFrame& frame);
  // Frame-to-frame tracking from the prediction (Algorithm 1: direct alignment, patch or
  // descriptor correspondences, pose optimisation). True: the frame was accepted (pyr moved
  // into it). False: `why` says what failed; `features` holds the ORB features if extracted.
  bool track_from_prediction(const StereoFrame& frame, ImagePyramid& pyr, const NavState& predicted,
                             const ImuPreintegration& pim, bool use_imu,
                             std::optional<OrbFeatures>& features, std::string& why, FrameResult& r,
                             StageTimer& timer);
  std::string validate(const StereoFrame& frame);
  void advance_bootstrap(const ImuPreintegration& pim, FrameResult& r);
  // Mono: scale, gravity, velocities and biases from cam0 poses known up to scale, the IMU
  // preintegrated between a thinned set of them.
  ViAlignmentResult align_mono(const std::vector<TimedPose>& camera_poses,
                               const ViAlignmentOptions& options) const;
  // Mono: the map's scale checked against the IMU over a recent window, and corrected.
  // `imu_bridged`: the IMU covered the interval since the previous frame.
  void refine_scale(bool imu_bridged, FrameResult& r);
  bool initialise(const StereoFrame& frame, const ImagePyramid& pyr, FrameResult& result);
  bool initialise_mono(const StereoFrame& frame, const ImagePyramid& pyr, FrameResult& result);
  // Mono, lost too long: back to the two-view start, in a new map.
  void restart_mono(FrameResult& result);
  ImuPreintegration preintegrate_since_last(int64_t t_ns);
  Eigen::Isometry3d T_w_c0(const NavState& nav) const;
  // Stage 1 (Eq. 17-18): relative pose to the previous frame by sparse alignment.
  std::optional<Eigen::Isometry3d> align_to_last(const ImagePyramid& pyr,
                                                 const Eigen::Isometry3d& T_w_c_pred);
  // Stage 2: local-map points found in the current image by patch alignment.
  Correspondences direct_correspondences(const ImagePyramid& pyr, const Eigen::Isometry3d& T_w_c,
                                         double search_radius_px);
  Correspondences descriptor_correspondences(const OrbFeatures& features,
                                             const Eigen::Isometry3d& T_w_c);
  PoseOptResult optimise(const NavState& predicted, const Correspondences& c,
                         const ImuPreintegration& pim);
  PoseOptResult optimise_vision_only(const NavState& predicted, const Correspondences& c);
  int64_t imu_behind_ns(int64_t t_ns) const;  // frame time minus the newest IMU sample's, >= 0
  bool imu_usable(const ImuPreintegration& pim) const;
  // Empty when a relocalised pose is consistent with the IMU prediction, else why not.
  std::string check_against_prediction(const NavState& reloc, const NavState& predicted,
                                       int64_t t_ns) const;
  void accept(const StereoFrame& frame, ImagePyramid pyr, const NavState& nav,
              std::vector<TrackedObservation> tracked, const PoseOptResult* opt,
              const OrbFeatures* features, FrameResult& result, StageTimer& timer);
  void remember_keyframe_view(int64_t t_ns, const Eigen::Isometry3d& T_w_c,
                              const std::vector<TrackedObservation>& tracked);
  // `atlas_map_id` >= 0: the atlas placed the frame; the local map continues that map id.
  void start_map_in_place(const StereoFrame& frame, const ImagePyramid& pyr, const NavState& nav,
                          FrameResult& result, int32_t atlas_map_id = -1);
  // The IMU carried the pose over the loss since the last tracked frame, without a gap, and
  // not for longer than continue_map_within_ns: a new local map continues the map.
  bool loss_bridged(int64_t t_ns, const NavState& nav) const;
  // Longer since the last tracked frame than the IMU is trusted to carry the pose.
  bool lost_beyond_imu_bridge(int64_t t_ns) const {
    return t_ns - last_tracked_t_ns_ > options_.continue_map_within_ns;
  }
  // Lost beyond what the IMU bridges, with a mapper: sends (or keeps) a request to its atlas.
  // True while the tracker should wait for the answer rather than start a new map.
  bool ask_atlas(const StereoFrame& frame, const ImagePyramid& pyr, const OrbFeatures& features,
                 const NavState& predicted, FrameResult& result);
  int32_t new_map_id() { return ++last_map_id_; }
  // Tracking resumes from `kf`, the first keyframe of a new local map (already in map_).
  void begin_local_map(const ImagePyramid& pyr, const NavState& nav,
                       const std::shared_ptr<Keyframe>& kf, FrameResult& result);

  TrackerOptions options_;
  ImuBuffer imu_;
  LocalMap map_;
  PoseOptimizer optimizer_;
  SparseAligner aligner_;
  KeyframeBuilder builder_;
  Relocaliser relocaliser_;
  TrackerCounters counters_;

  TrackState state_ = TrackState::kInitialising;
  int32_t map_id_ = 0;
  int32_t last_map_id_ = 0;  // map ids are never reused (one may be promised to the atlas)
  struct AtlasRequest {
    int64_t seq = 0;
    int32_t next_map_id = 0;
    Eigen::Isometry3d T_w_b = Eigen::Isometry3d::Identity();  // the guess sent
  };
  std::optional<AtlasRequest> atlas_request_;  // pending
  int64_t atlas_asked_since_ns_ = -1;          // the loss's first request
  int32_t atlas_map_id_ = 0;                   // the map id its requests offer
  int64_t next_atlas_seq_ = 0;
  struct AtlasFix {
    Eigen::Isometry3d correction = Eigen::Isometry3d::Identity();  // guess -> the atlas' place
    int32_t map_id = 0;
    std::string message;
  };
  std::optional<AtlasFix> atlas_fix_;
  std::optional<LastFrame> last_;
  int64_t last_keyframe_t_ns_ = 0;
  Eigen::Isometry3d last_keyframe_T_w_c_ = Eigen::Isometry3d::Identity();
  // Rays (camera frame) of the points tracked at the last keyframe, for the parallax (Eq. 14).
  std::unordered_map<int64_t, Eigen::Vector3d> last_keyframe_rays_;
  int64_t lost_since_ns_ = -1;
  int64_t last_tracked_t_ns_ = 0;  // last frame tracked or relocalised
  std::optional<Bootstrap> bootstrap_;
  // Mono, once aligned: recent cam0 poses for the scale check, bridged by the IMU throughout
  // (empty: starts at the next frame).
  std::vector<TimedPose> scale_window_;
  int64_t last_scale_check_ns_ = 0;
  bool mapper_present_ = false;
  bool atlas_present_ = false;
  cv::Mat init_previous_image_;  // while initialising: to tell a static start from a moving one
  MonoInitialiser mono_init_;
};

}  // namespace hs
