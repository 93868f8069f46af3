#include "tools/viewer/viewer_render.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

namespace hs {
namespace {

const cv::Scalar kText(230, 230, 230);
const cv::Scalar kDim(130, 130, 130);
const cv::Scalar kBackground(28, 28, 28);
const cv::Scalar kLostColour(60, 60, 230);

std::string format(const char* fmt, double a, double b = 0, double c = 0, double d = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c, d);
  return buf;
}

void text(cv::Mat& canvas, const std::string& s, cv::Point at, const cv::Scalar& colour = kText,
          double scale = 0.5) {
  cv::putText(canvas, s, at, cv::FONT_HERSHEY_SIMPLEX, scale, colour, 1, cv::LINE_AA);
}

const char* state_name(int8_t state) {
  switch (state) {
    case hsslam::odometry_t::INITIALISING:
      return "INITIALISING";
    case hsslam::odometry_t::TRACKING:
      return "TRACKING";
    case hsslam::odometry_t::LOST:
      return "LOST";
    case hsslam::odometry_t::RELOCALISED:
      return "RELOCALISED";
  }
  return "?";
}

const char* method_name(int8_t method) {
  switch (method) {
    case hsslam::tracker_status_t::DIRECT:
      return "direct";
    case hsslam::tracker_status_t::DESCRIPTORS:
      return "descriptors";
    case hsslam::tracker_status_t::RELOCALISED_REFERENCE:
      return "relocalised (reference keyframe)";
    case hsslam::tracker_status_t::RELOCALISED_GLOBAL:
      return "relocalised (global)";
  }
  return "-";
}

cv::Scalar feature_colour(int8_t source) {
  switch (source) {
    case hsslam::tracker_status_t::FEATURE_DIRECT:
      return kDirectColour;
    case hsslam::tracker_status_t::FEATURE_DESCRIPTOR:
      return kDescriptorColour;
    default:
      return kNewColour;
  }
}

cv::Scalar map_colour(int32_t map_id) {
  static const cv::Scalar palette[] = {
      {255, 200, 80}, {80, 220, 255}, {200, 120, 255}, {120, 255, 160}, {255, 120, 160}};
  return palette[static_cast<size_t>(std::abs(map_id)) % 5];
}

void draw_frame(cv::Mat& canvas, const ViewerModel& model, const ViewerLayout& layout) {
  const auto& st = model.latest_status();
  std::string title = "HS-SLAM viewer";
  if (st) {
    title += format("   t %.2f s   ", 1e-9 * static_cast<double>(st->t_ns - model.first_t_ns())) +
             state_name(st->state) + "   " + method_name(st->method) +
             format("   %.0f points", st->tracked_points) + (st->is_keyframe ? "   KEYFRAME" : "");
  }
  text(canvas, title, {8, 20});
  cv::rectangle(canvas, layout.image, kDim, 1);
  const auto& frame = model.frame();
  if (!frame || frame->image.empty()) {
    text(canvas, "waiting for CAM_STEREO and TRACKER_STATUS", layout.image.tl() + cv::Point(20, 40),
         kDim);
    return;
  }
  const cv::Size size = frame->image.size();
  const cv::Point2f tl = layout.image_to_canvas(size, {0, 0});
  const cv::Point2f br = layout.image_to_canvas(
      size, {static_cast<float>(size.width), static_cast<float>(size.height)});
  const cv::Rect dst(cv::Point(cvRound(tl.x), cvRound(tl.y)),
                     cv::Point(cvRound(br.x), cvRound(br.y)));
  cv::Mat scaled, bgr;
  cv::resize(frame->image, scaled, dst.size(), 0, 0, cv::INTER_AREA);
  cv::cvtColor(scaled, bgr, scaled.channels() == 1 ? cv::COLOR_GRAY2BGR : cv::COLOR_BGR2RGB);
  bgr.copyTo(canvas(dst & cv::Rect({}, canvas.size())));
  const hsslam::tracker_status_t& s = frame->status;
  int counts[4] = {0, 0, 0, 0};
  const size_t n = std::min({s.feature_u.size(), s.feature_v.size(), s.feature_source.size()});
  for (size_t i = 0; i < n; ++i) {
    const cv::Point2f at = layout.image_to_canvas(size, {s.feature_u[i], s.feature_v[i]});
    cv::circle(canvas, at, 3, feature_colour(s.feature_source[i]), cv::FILLED, cv::LINE_AA);
    ++counts[std::clamp<int>(s.feature_source[i], 0, 3)];
  }
  const int y = layout.image.y + layout.image.height + 22;
  const std::pair<cv::Scalar, std::string> legend[] = {
      {kDirectColour, format("direct %.0f", counts[1])},
      {kDescriptorColour, format("descriptor %.0f", counts[2])},
      {kNewColour, format("new (stereo) %.0f", counts[3])}};
  int x = layout.image.x + 10;
  for (const auto& [colour, label] : legend) {
    cv::circle(canvas, {x, y - 5}, 5, colour, cv::FILLED, cv::LINE_AA);
    text(canvas, label, {x + 10, y});
    x += 180;
  }
}

void draw_timing(cv::Mat& canvas, const ViewerModel& model, const ViewerLayout& layout) {
  const TimingSummary t = model.timing();
  const cv::Rect& r = layout.timing;
  int y = r.y + 16;
  if (t.frames == 0) {
    text(canvas, "timing: no tracked frame yet", {r.x + 8, y}, kDim);
    return;
  }
  text(canvas,
       format("tracking %.2f ms/frame (others %.2f, keyframes %.2f), max %.1f", t.mean_ms,
              t.mean_other_ms, t.mean_keyframe_ms, t.max_ms) +
           format(" over %.0f frames", t.frames),
       {r.x + 8, y});
  double largest = 0;
  for (const auto& [name, ms] : t.mean_stage_ms) largest = std::max(largest, ms);
  const int bar_x = r.x + 150, bar_w = r.width - 230;
  const int rows = std::max(1, static_cast<int>(t.mean_stage_ms.size()));
  const int step = std::clamp((r.height - 30) / rows, 10, 18);
  y += 8;
  for (const auto& [name, ms] : t.mean_stage_ms) {
    y += step;
    if (y > r.y + r.height) break;
    text(canvas, name, {r.x + 8, y}, kText, 0.4);
    const int w = largest > 0 ? static_cast<int>(bar_w * ms / largest) : 0;
    cv::rectangle(canvas, cv::Rect(bar_x, y - step + 5, std::max(1, w), step - 6),
                  cv::Scalar(200, 160, 90), cv::FILLED);
    text(canvas, format("%.2f ms", ms), {bar_x + w + 6, y}, kText, 0.4);
  }
}

// World x-y to top-view pixels: equal scale, y up.
struct TopView {
  cv::Rect area;
  Eigen::Vector2d centre;
  double px_per_m = 1;
  cv::Point to_px(const Eigen::Vector3d& p) const {
    return {cvRound(area.x + area.width / 2.0 + (p.x() - centre.x()) * px_per_m),
            cvRound(area.y + area.height / 2.0 - (p.y() - centre.y()) * px_per_m)};
  }
};

double grid_step(double span_m) {
  for (double step : {0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 500.0})
    if (span_m / step <= 10) return step;
  return 1000.0;
}

void draw_top_view(cv::Mat& canvas, const ViewerModel& model, const ViewerLayout& layout) {
  const cv::Rect& area = layout.top_view;
  cv::rectangle(canvas, area, kDim, 1);
  Eigen::Vector2d lo(1e18, 1e18), hi(-1e18, -1e18);
  for (const TrajectoryPoint& p : model.trajectory()) {
    lo = lo.cwiseMin(p.p_w.head<2>());
    hi = hi.cwiseMax(p.p_w.head<2>());
  }
  for (const auto& [id, k] : model.keyframes()) {
    lo = lo.cwiseMin(k.p_w.head<2>());
    hi = hi.cwiseMax(k.p_w.head<2>());
  }
  int corrected = 0;
  for (const auto& [id, k] : model.keyframes()) corrected += k.corrected;
  text(canvas,
       format("top view x-y | %.0f keyframes (%.0f corrected) | %.0f points | %.0f MAP_UPDATE",
              static_cast<double>(model.keyframes().size()), corrected,
              static_cast<double>(model.points().size()), static_cast<double>(model.map_updates())),
       {area.x, area.y - 10}, kText, 0.45);
  if (lo.x() > hi.x()) {
    text(canvas, "waiting for POSE / KEYFRAME", area.tl() + cv::Point(20, 40), kDim);
    return;
  }
  // The path with a margin decides the scale; map points outside it are clipped.
  const Eigen::Vector2d span = (hi - lo).cwiseMax(Eigen::Vector2d(1.0, 1.0)) * 1.3;
  TopView v;
  v.area = area;
  v.centre = 0.5 * (lo + hi);
  v.px_per_m = std::min(area.width / span.x(), area.height / span.y());
  cv::Mat roi = canvas(area);
  const double step = grid_step(std::max(area.width, area.height) / v.px_per_m);
  const double x0 = std::floor((v.centre.x() - area.width / 2.0 / v.px_per_m) / step) * step;
  const double y0 = std::floor((v.centre.y() - area.height / 2.0 / v.px_per_m) / step) * step;
  for (double gx = x0; gx < x0 + area.width / v.px_per_m + step; gx += step) {
    const cv::Point a = v.to_px({gx, 0, 0}) - area.tl();
    cv::line(roi, {a.x, 0}, {a.x, area.height}, cv::Scalar(50, 50, 50));
  }
  for (double gy = y0; gy < y0 + area.height / v.px_per_m + step; gy += step) {
    const cv::Point a = v.to_px({0, gy, 0}) - area.tl();
    cv::line(roi, {0, a.y}, {area.width, a.y}, cv::Scalar(50, 50, 50));
  }
  text(canvas, format("grid %.1f m", step), {area.x + 6, area.y + area.height - 8}, kDim, 0.4);
  for (const auto& [id, p] : model.points()) {
    const cv::Point px = v.to_px(p) - area.tl();
    if (px.inside(cv::Rect({}, area.size()))) roi.at<cv::Vec3b>(px) = cv::Vec3b(190, 190, 190);
  }
  const auto& traj = model.trajectory();
  for (size_t i = 1; i < traj.size(); ++i) {
    if (traj[i].map_id != traj[i - 1].map_id) continue;  // a new map: no line across the jump
    const bool lost = traj[i].state == hsslam::odometry_t::LOST;
    cv::line(roi, v.to_px(traj[i - 1].p_w) - area.tl(), v.to_px(traj[i].p_w) - area.tl(),
             lost ? kLostColour : map_colour(traj[i].map_id), 2, cv::LINE_AA);
  }
  for (const auto& [id, k] : model.keyframes()) {
    const cv::Point c = v.to_px(k.p_w) - area.tl();
    cv::rectangle(roi, cv::Rect(c - cv::Point(3, 3), cv::Size(7, 7)),
                  k.corrected ? cv::Scalar(255, 0, 255) : cv::Scalar(0, 230, 230), 1);
  }
  if (!traj.empty()) {
    const TrajectoryPoint& now = traj.back();
    const cv::Point c = v.to_px(now.p_w) - area.tl();
    const cv::Point tip =
        c + cv::Point(cvRound(20 * std::cos(now.yaw)), cvRound(-20 * std::sin(now.yaw)));
    cv::arrowedLine(roi, c, tip, cv::Scalar(60, 60, 255), 2, cv::LINE_AA, 0, 0.4);
  }
}

}  // namespace

cv::Point2f ViewerLayout::image_to_canvas(const cv::Size& size, const cv::Point2f& uv) const {
  const float s = std::min(static_cast<float>(image.width) / static_cast<float>(size.width),
                           static_cast<float>(image.height) / static_cast<float>(size.height));
  const float ox = image.x + 0.5f * (static_cast<float>(image.width) - s * size.width);
  const float oy = image.y + 0.5f * (static_cast<float>(image.height) - s * size.height);
  return {ox + s * uv.x, oy + s * uv.y};
}

cv::Mat render_view(const ViewerModel& model, const ViewerLayout& layout) {
  cv::Mat canvas(layout.canvas, CV_8UC3, kBackground);
  draw_frame(canvas, model, layout);
  draw_timing(canvas, model, layout);
  draw_top_view(canvas, model, layout);
  if (model.bad_messages() > 0)
    text(canvas,
         format("%.0f bad messages, last: ", static_cast<double>(model.bad_messages())) +
             model.last_bad_message(),
         {8, layout.canvas.height - 8}, kLostColour, 0.4);
  return canvas;
}

}  // namespace hs
