#include "mapper/offline/observation_check.h"

#include <algorithm>
#include <utility>
#include <vector>

#include "common/geometry/triangulation.h"

namespace hs {

namespace {

struct Sighting {
  int64_t t_ns;
  Eigen::Isometry3d T_c_w;
  const PinholeRadtan* camera;
  int index;  // 0: cam0, 1: cam1
  Eigen::Vector2d uv;
};

std::optional<Eigen::Vector2d> residual(const Sighting& s, const Eigen::Vector3d& p_w) {
  const Eigen::Vector3d p_c = s.T_c_w * p_w;
  if (!(p_c.z() > 1e-3)) return std::nullopt;
  return Eigen::Vector2d(s.uv - s.camera->project(p_c));
}

// An outlier breaks the track: only consecutive inliers make a pair.
void add_track(std::vector<std::pair<int64_t, std::optional<Eigen::Vector2d>>>& track,
               TrackCorrelation& out) {
  std::sort(track.begin(), track.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  for (size_t k = 0; k < track.size(); ++k) {
    if (!track[k].second) continue;
    out.squares += track[k].second->squaredNorm();
    if (k + 1 == track.size() || !track[k + 1].second) continue;
    out.lagged_products += track[k].second->dot(*track[k + 1].second);
    ++out.pairs;
  }
}

}  // namespace

ObservationCheck check_observations(const KeyframeGraph& graph, const StereoCalib& calib,
                                    const KeyframePoseLookup& T_w_b,
                                    const ObservationCheckOptions& options) {
  ObservationCheck out;
  std::vector<Sighting> sightings;
  std::vector<PointView> views;
  std::vector<std::pair<int64_t, std::optional<Eigen::Vector2d>>> track;  // cam0, by time
  for (int64_t id : graph.point_ids()) {
    const MapperPoint& p = *graph.point(id);
    sightings.clear();
    views.clear();
    int keyframes = 0;
    std::optional<Eigen::Vector3d> start;
    for (const Observation& o : p.observations) {
      const MapperKeyframe* kf = graph.keyframe(o.keyframe_id);
      const std::optional<Eigen::Isometry3d> T = kf ? T_w_b(kf->state.t_ns) : std::nullopt;
      if (!T) continue;
      ++keyframes;
      const MapperKeypoint& kp = kf->keypoints[static_cast<size_t>(o.keypoint)];
      const Eigen::Isometry3d T_w_c0 = *T * calib.cam0.T_b_c;
      sightings.push_back(
          {kf->state.t_ns, T_w_c0.inverse(), &calib.cam0.intrinsics, 0, {kp.u, kp.v}});
      if (kp.u_right < 0.f) continue;
      sightings.push_back({kf->state.t_ns,
                           (*T * calib.cam1.T_b_c).inverse(),
                           &calib.cam1.intrinsics,
                           1,
                           {kp.u_right, kp.v_right}});
      if (!start && kp.depth > 0.f)
        start =
            T_w_c0 * (Eigen::Vector3d(
                          calib.cam0.intrinsics.unproject_normalised({kp.u, kp.v}).homogeneous()) *
                      static_cast<double>(kp.depth));
    }
    if (keyframes < options.min_keyframes) continue;
    // From the first stereo sighting's depth (the map's own position without one).
    for (const Sighting& s : sightings)
      views.push_back({s.T_c_w, s.camera->unproject_normalised(s.uv)});
    const std::optional<RefinedPoint> refined =
        refine_point(start.value_or(p.p_w), views, options.iterations);
    if (!refined) continue;
    ++out.points;
    track.clear();
    for (const Sighting& s : sightings) {
      std::optional<Eigen::Vector2d> r = residual(s, refined->p_w);
      if (r && r->norm() > options.max_residual_px) r.reset();
      if (s.index == 0) track.emplace_back(s.t_ns, r);
      if (!r) {
        ++out.outliers;
        continue;
      }
      ResidualStats& stats = out.camera[static_cast<size_t>(s.index)];
      ++stats.count;
      stats.sum += *r;
      stats.sum_squared += r->squaredNorm();
    }
    add_track(track, out.track);
  }
  return out;
}

}  // namespace hs
