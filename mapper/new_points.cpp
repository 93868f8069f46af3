#include "mapper/new_points.h"

namespace hs {
namespace {

FreeKeypoints free_keypoints(const MapperKeyframe& kf, const CameraCalib& cam) {
  FreeKeypoints v(kf.state.T_w_b() * cam.T_b_c, cam.intrinsics);
  for (size_t i = 0; i < kf.keypoints.size(); ++i) {
    const MapperKeypoint& kp = kf.keypoints[i];
    if (kp.point_id < 0)
      v.add(static_cast<int>(i), Eigen::Vector2d(kp.u, kp.v), kp.octave, kf.descriptors[i].data());
  }
  return v;
}

}  // namespace

std::vector<NewPoint> triangulate_new_points(const KeyframeGraph& graph, int64_t id,
                                             const StereoCalib& calib,
                                             const NewPointOptions& options) {
  std::vector<NewPoint> out;
  const MapperKeyframe* kf = graph.keyframe(id);
  if (!kf || options.covisible_keyframes == 0) return out;
  const FreeKeypoints a = free_keypoints(*kf, calib.cam0);
  std::vector<bool> used_a(a.keypoints().size(), false);
  for (int64_t other : graph.most_covisible(id, options.covisible_keyframes)) {
    const FreeKeypoints b = free_keypoints(*graph.keyframe(other), calib.cam0);
    for (const EpipolarPoint& e :
         triangulate_epipolar(a, b, calib.cam0.intrinsics, options, used_a)) {
      NewPoint p;
      p.p_w = e.p_w;
      p.a = {id, a.keypoints()[e.a].index};
      p.b = {other, b.keypoints()[e.b].index};
      out.push_back(p);
    }
  }
  return out;
}

}  // namespace hs
