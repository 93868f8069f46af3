#include "tracker/mono_initialiser.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace hs {

MonoInitialiser::MonoInitialiser(const PinholeRadtan& camera, const MonoInitOptions& options)
    : camera_(camera), options_(options) {
  options_.two_view.sigma = options_.pixel_sigma / camera.fx;
}

void MonoInitialiser::start_reference(int64_t t_ns, const cv::Mat& image) {
  Reference r;
  r.t_ns = t_ns;
  cv::goodFeaturesToTrack(image, r.corners, options_.max_corners, options_.corner_quality,
                          options_.min_corner_distance_px);
  r.current = r.corners;
  r.last_image = image.clone();
  ref_ = std::move(r);
}

MonoInitResult MonoInitialiser::add_frame(int64_t t_ns, const cv::Mat& image) {
  MonoInitResult out;
  if (!ref_) {
    start_reference(t_ns, image);
    out.ref_t_ns = t_ns;
    out.tracked = static_cast<int>(ref_->corners.size());
    out.reason = "reference frame taken (" + std::to_string(out.tracked) + " corners)";
    return out;
  }
  Reference& ref = *ref_;
  out.ref_t_ns = ref.t_ns;
  const cv::Size window(options_.flow_window_px, options_.flow_window_px);
  std::vector<cv::Point2f> next, back;
  std::vector<uint8_t> ok, ok_back;
  std::vector<float> err;
  if (!ref.current.empty()) {
    cv::calcOpticalFlowPyrLK(ref.last_image, image, ref.current, next, ok, err, window,
                             options_.flow_levels);
    cv::calcOpticalFlowPyrLK(image, ref.last_image, next, back, ok_back, err, window,
                             options_.flow_levels);
  }
  const cv::Rect2f inside(0.f, 0.f, static_cast<float>(image.cols - 1),
                          static_cast<float>(image.rows - 1));
  std::vector<cv::Point2f> corners, current;
  for (size_t i = 0; i < next.size(); ++i) {
    if (!ok[i] || !ok_back[i] || !inside.contains(next[i]) ||
        cv::norm(back[i] - ref.current[i]) > options_.max_forward_backward_px)
      continue;
    corners.push_back(ref.corners[i]);
    current.push_back(next[i]);
  }
  ref.corners = std::move(corners);
  ref.current = std::move(current);
  ref.last_image = image.clone();
  out.tracked = static_cast<int>(ref.current.size());
  if (out.tracked < options_.min_tracked) {
    out.reason = "only " + std::to_string(out.tracked) + " corners followed: new reference";
    start_reference(t_ns, image);
    out.ref_t_ns = t_ns;
    return out;
  }
  std::vector<double> flow;
  for (size_t i = 0; i < ref.current.size(); ++i)
    flow.push_back(cv::norm(ref.current[i] - ref.corners[i]));
  std::nth_element(flow.begin(), flow.begin() + flow.size() / 2, flow.end());
  out.median_flow_px = flow[flow.size() / 2];
  if (out.median_flow_px < options_.min_flow_px) {
    out.reason = "not enough motion (median flow " + std::to_string(out.median_flow_px) +
                 " px, need " + std::to_string(options_.min_flow_px) + ")";
    return out;
  }

  std::vector<Eigen::Vector2d> xy_ref, xy_cur;
  for (size_t i = 0; i < ref.current.size(); ++i) {
    xy_ref.push_back(camera_.unproject_normalised({ref.corners[i].x, ref.corners[i].y}));
    xy_cur.push_back(camera_.unproject_normalised({ref.current[i].x, ref.current[i].y}));
  }
  const TwoViewResult tv = reconstruct_two_view(xy_ref, xy_cur, options_.two_view);
  if (!tv.ok) {
    out.reason = tv.reason;
    return out;
  }
  out.ok = true;
  out.T_ref_cur = tv.T_a_b;
  out.homography = tv.homography;
  for (size_t k = 0; k < tv.triangulated.size(); ++k) {
    const size_t i = static_cast<size_t>(tv.triangulated[k]);
    out.uv_ref.emplace_back(ref.corners[i].x, ref.corners[i].y);
    out.uv_cur.emplace_back(ref.current[i].x, ref.current[i].y);
    out.p_ref.push_back(tv.p_a[k]);
  }
  return out;
}

}  // namespace hs
