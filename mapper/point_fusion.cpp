#include "mapper/point_fusion.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "common/features/descriptor_match.h"

namespace hs {

std::vector<int64_t> neighbourhood_points(const KeyframeGraph& graph, int64_t keyframe_id,
                                          size_t n) {
  std::vector<int64_t> keyframes = graph.most_covisible(keyframe_id, n);
  keyframes.push_back(keyframe_id);
  std::set<int64_t> points;
  for (int64_t k : keyframes)
    for (const MapperKeypoint& kp : graph.keyframe(k)->keypoints)
      if (kp.point_id >= 0) points.insert(kp.point_id);
  return {points.begin(), points.end()};
}

std::vector<ProjectedMatch> match_projected_points(
    const KeyframeGraph& graph, const MapperKeyframe& kf, const Eigen::Isometry3d& T_w_b,
    const std::vector<int64_t>& points, const StereoCalib& calib, const PointFusionOptions& options,
    int* projected) {
  const Eigen::Isometry3d T_c_w = calib.cam0.T_b_c.inverse() * T_w_b.inverse();
  const PinholeRadtan& K = calib.cam0.intrinsics;
  std::vector<Eigen::Vector2d> predicted;
  std::vector<int64_t> ids;
  std::vector<double> depths;
  cv::Mat descriptors(0, 32, CV_8U);
  for (int64_t id : points) {
    const MapperPoint* p = graph.point(id);
    if (!p) continue;
    const Eigen::Vector3d p_c = T_c_w * p->p_w;
    Eigen::Vector2d uv;
    if (!K.project(p_c, &uv)) continue;
    predicted.push_back(uv);
    ids.push_back(id);
    depths.push_back(p_c.z());
    descriptors.push_back(cv::Mat(1, 32, CV_8U, const_cast<uint8_t*>(p->descriptor.data())));
  }
  if (projected) *projected = static_cast<int>(predicted.size());
  if (predicted.empty() || kf.keypoints.empty()) return {};
  std::vector<Eigen::Vector2f> uv_kf;
  for (const MapperKeypoint& kp : kf.keypoints) uv_kf.emplace_back(kp.u, kp.v);
  const KeypointGrid grid(uv_kf, K.width, K.height);
  DescriptorMatchOptions match;
  match.max_distance = options.max_hamming;
  match.ratio = static_cast<float>(options.ratio);
  match.search_radius_px = options.radius_px;
  const cv::Mat kf_descriptors(static_cast<int>(kf.descriptors.size()), 32, CV_8U,
                               const_cast<uint8_t*>(kf.descriptors.front().data()));
  const std::vector<int> found =
      match_by_projection(descriptors, predicted, kf_descriptors, grid, match);
  std::vector<ProjectedMatch> out;
  for (size_t i = 0; i < found.size(); ++i) {
    if (found[i] < 0) continue;
    const float depth = kf.keypoints[static_cast<size_t>(found[i])].depth;
    if (options.max_depth_error > 0 && depth > 0 &&
        std::abs(depth - depths[i]) > options.max_depth_error * depths[i])
      continue;
    out.push_back({found[i], ids[i]});
  }
  return out;
}

FusionResult fuse_points_into(KeyframeGraph& graph, int64_t id, const std::vector<int64_t>& points,
                              const StereoCalib& calib, const PointFusionOptions& options,
                              const std::function<bool(int64_t)>& preferred,
                              bool ties_as_detections) {
  FusionResult r;
  const MapperKeyframe& kf = *graph.keyframe(id);
  const std::vector<ProjectedMatch> matches =
      match_projected_points(graph, kf, kf.state.T_w_b(), points, calib, options, nullptr);
  for (const ProjectedMatch& m : matches) {
    const MapperPoint* found = graph.point(m.point_id);
    if (!found) continue;  // fused away by an earlier match
    const bool seen = std::any_of(found->observations.begin(), found->observations.end(),
                                  [&](const Observation& o) { return o.keyframe_id == id; });
    if (seen) continue;
    const int64_t current = kf.keypoints[static_cast<size_t>(m.keypoint)].point_id;
    if (current < 0) {
      graph.add_observation(m.point_id, {id, m.keypoint});
      ++r.observations_added;
      continue;
    }
    const MapperPoint& other = *graph.point(current);
    const bool keep_found = preferred(m.point_id) != preferred(current)
                                ? preferred(m.point_id)
                                : found->observations.size() >= other.observations.size();
    const int64_t keep = keep_found ? m.point_id : current;
    const int64_t drop = keep_found ? current : m.point_id;
    if (preferred(drop)) continue;  // two fixed points: neither may go
    graph.fuse_point(drop, keep, ties_as_detections);
    r.merged.emplace_back(drop, keep);
    ++r.fused;
  }
  return r;
}

}  // namespace hs
