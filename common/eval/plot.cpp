#include "common/eval/plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "common/core/atomic_file.h"
#include "common/core/error.h"
#include "common/core/types.h"

namespace hs {
namespace {

const cv::Scalar kBlack(0, 0, 0), kGrid(225, 225, 225), kGray(110, 110, 110);
const cv::Scalar kBlue(200, 90, 20), kRed(40, 40, 220), kGreen(60, 160, 60), kOrange(0, 140, 255);
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kFontScale = 0.5;

// A "nice" tick step (1, 2 or 5 times a power of ten) giving about `count` ticks over `range`.
double tick_step(double range, int count) {
  const double raw = range / count;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0})
    if (m * mag >= raw) return m * mag;
  return 10.0 * mag;
}

std::string tick_label(double v, double step) {
  const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, std::abs(v) < step * 1e-6 ? 0.0 : v);
  return buf;
}

void text(cv::Mat& img, const std::string& s, cv::Point at, double scale = kFontScale,
          const cv::Scalar& color = kBlack) {
  cv::putText(img, s, at, kFont, scale, color, 1, cv::LINE_AA);
}

cv::Size text_size(const std::string& s, double scale = kFontScale) {
  int baseline = 0;
  return cv::getTextSize(s, kFont, scale, 1, &baseline);
}

// Maps data coordinates [x0,x1] x [y0,y1] onto the pixel rectangle `box` (y up).
struct Axes {
  cv::Rect box;
  double x0, x1, y0, y1;

  cv::Point2d px(double x, double y) const {
    return {box.x + (x - x0) / (x1 - x0) * box.width,
            box.y + box.height - (y - y0) / (y1 - y0) * box.height};
  }

  // Grid, frame, tick labels and axis labels.
  void draw(cv::Mat& img, const std::string& x_label, const std::string& y_label) const {
    const double sx = tick_step(x1 - x0, 8), sy = tick_step(y1 - y0, 6);
    for (double x = std::ceil(x0 / sx) * sx; x <= x1 + 1e-9 * sx; x += sx) {
      const int u = static_cast<int>(std::lround(px(x, y0).x));
      cv::line(img, {u, box.y}, {u, box.y + box.height}, kGrid, 1);
      cv::line(img, {u, box.y + box.height}, {u, box.y + box.height + 5}, kBlack, 1);
      const std::string s = tick_label(x, sx);
      text(img, s, {u - text_size(s).width / 2, box.y + box.height + 22});
    }
    int label_width = 0;
    for (double y = std::ceil(y0 / sy) * sy; y <= y1 + 1e-9 * sy; y += sy) {
      const int v = static_cast<int>(std::lround(px(x0, y).y));
      cv::line(img, {box.x, v}, {box.x + box.width, v}, kGrid, 1);
      cv::line(img, {box.x - 5, v}, {box.x, v}, kBlack, 1);
      const std::string s = tick_label(y, sy);
      label_width = std::max(label_width, text_size(s).width);
      text(img, s, {box.x - 10 - text_size(s).width, v + 5});
    }
    cv::rectangle(img, box, kBlack, 1);
    text(img, x_label,
         {box.x + box.width / 2 - text_size(x_label).width / 2, box.y + box.height + 45});
    cv::Mat label(text_size(y_label).height + 10, text_size(y_label).width + 4, img.type(),
                  cv::Scalar::all(255));
    text(label, y_label, {2, label.rows - 5});
    cv::rotate(label, label, cv::ROTATE_90_COUNTERCLOCKWISE);
    const int lx = std::max(0, box.x - 15 - label_width - label.cols);
    const int ly = std::max(0, box.y + box.height / 2 - label.rows / 2);
    if (lx + label.cols <= img.cols && ly + label.rows <= img.rows)
      label.copyTo(img(cv::Rect(lx, ly, label.cols, label.rows)));
  }

  // Polyline clipped to the box; dashed if dash_px > 0 (dashes follow the drawn length).
  void polyline(cv::Mat& img, const std::vector<cv::Point2d>& pts, const cv::Scalar& color,
                int thickness, double dash_px = 0) const {
    cv::Mat roi = img(box);
    const cv::Point2d origin(box.x, box.y);
    double run = 0.0;  // drawn length so far, sets the dash phase
    for (size_t i = 1; i < pts.size(); ++i) {
      const cv::Point2d a = pts[i - 1] - origin, b = pts[i] - origin;
      const double len = std::hypot(b.x - a.x, b.y - a.y);
      if (dash_px <= 0) {
        cv::line(roi, a, b, color, thickness, cv::LINE_AA);
        continue;
      }
      for (double pos = 0.0; pos < len;) {
        const double phase = std::fmod(run + pos, 2 * dash_px);
        const double end = std::min(len, pos + (phase < dash_px ? dash_px : 2 * dash_px) - phase);
        if (phase < dash_px)
          cv::line(roi, a + (b - a) * (pos / len), a + (b - a) * (end / len), color, thickness,
                   cv::LINE_AA);
        pos = end;
      }
      run += len;
    }
  }
};

// Data ranges padded by 5%, never empty.
void padded_range(double lo, double hi, double min_span, double& out_lo, double& out_hi) {
  const double span = std::max(hi - lo, min_span);
  const double mid = 0.5 * (lo + hi);
  out_lo = mid - 0.55 * span;
  out_hi = mid + 0.55 * span;
}

enum class Mark { kLine, kDashed, kDot };

struct LegendItem {
  std::string label;
  cv::Scalar color;
  Mark mark;
};

void legend(cv::Mat& img, cv::Point at, const std::vector<LegendItem>& items) {
  int width = 0;
  for (const LegendItem& item : items) width = std::max(width, text_size(item.label).width);
  const cv::Rect frame(at.x, at.y, width + 60, static_cast<int>(items.size()) * 22 + 8);
  cv::rectangle(img, frame, cv::Scalar::all(255), cv::FILLED);
  cv::rectangle(img, frame, kGray, 1);
  for (size_t i = 0; i < items.size(); ++i) {
    const int y = at.y + 18 + static_cast<int>(i) * 22;
    const LegendItem& item = items[i];
    if (item.mark == Mark::kDot) {
      cv::circle(img, {at.x + 26, y - 5}, 5, item.color, cv::FILLED, cv::LINE_AA);
    } else {
      const int period = item.mark == Mark::kDashed ? 12 : 36;
      const int dash = item.mark == Mark::kDashed ? 7 : 36;
      for (int x = 0; x < 36; x += period)
        cv::line(img, {at.x + 8 + x, y - 5}, {at.x + 8 + x + dash, y - 5}, item.color, 2,
                 cv::LINE_AA);
    }
    text(img, item.label, {at.x + 52, y});
  }
}

void draw_top_view(cv::Mat& img, const cv::Rect& area, const EvalResult& r) {
  const auto& gt = r.matched.gt.poses;
  const auto& est = r.matched.est.poses;
  double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
  for (const auto* poses : {&gt, &est})
    for (const StampedPose& p : *poses) {
      xmin = std::min(xmin, p.T_w_b.translation().x());
      xmax = std::max(xmax, p.T_w_b.translation().x());
      ymin = std::min(ymin, p.T_w_b.translation().y());
      ymax = std::max(ymax, p.T_w_b.translation().y());
    }
  // Equal scale on both axes so the path shape is not distorted.
  const double span = std::max({xmax - xmin, (ymax - ymin) * area.width / area.height, 1e-3});
  Axes ax{area, 0, 0, 0, 0};
  padded_range(xmin, xmax, span, ax.x0, ax.x1);
  padded_range(ymin, ymax, span * area.height / area.width, ax.y0, ax.y1);
  ax.draw(img, "x [m]", "y [m]");
  auto pixels = [&ax](const std::vector<StampedPose>& poses) {
    std::vector<cv::Point2d> pts;
    for (const StampedPose& p : poses)
      pts.push_back(ax.px(p.T_w_b.translation().x(), p.T_w_b.translation().y()));
    return pts;
  };
  const std::vector<cv::Point2d> gt_px = pixels(gt), est_px = pixels(est);
  ax.polyline(img, gt_px, kGray, 2, 6.0);
  ax.polyline(img, est_px, kBlue, 2);
  cv::circle(img, est_px.front(), 5, kGreen, cv::FILLED, cv::LINE_AA);
  cv::circle(img, est_px.back(), 5, kRed, cv::FILLED, cv::LINE_AA);
  legend(img, {area.x + 10, area.y + 10},
         {{"ground truth", kGray, Mark::kDashed},
          {std::string("estimate (align: ") + align_mode_name(r.options.align) + ")", kBlue,
           Mark::kLine},
          {"start", kGreen, Mark::kDot},
          {"end", kRed, Mark::kDot}});
}

void draw_error_panel(cv::Mat& img, const cv::Rect& area, const EvalResult& r) {
  const ErrorSeries& s = r.ape.series;
  const double t0 = ns_to_s(s.t_ns.front());
  const double duration = ns_to_s(s.t_ns.back()) - t0;
  Axes ax{area, 0.0, std::max(duration, 1e-3), 0.0, 1.0};
  ax.y1 = std::max(r.ape.stats.max * 1.1, 1e-4);  // rounding-level errors stay on the floor
  const std::string unit = relation_unit(r.ape.relation);
  ax.draw(img, "t [s]",
          std::string("APE ") + relation_name(r.ape.relation) +
              (unit.empty() ? "" : " [" + unit + "]"));
  std::vector<cv::Point2d> pts;
  for (size_t i = 0; i < s.values.size(); ++i)
    pts.push_back(ax.px(ns_to_s(s.t_ns[i]) - t0, s.values[i]));
  ax.polyline(img, pts, kBlue, 1);
  if (pts.size() == 1) cv::circle(img, pts[0], 3, kBlue, cv::FILLED);
  const std::vector<std::pair<std::string, double>> lines = {
      {"rmse", r.ape.stats.rmse}, {"mean", r.ape.stats.mean}, {"median", r.ape.stats.median}};
  const cv::Scalar colors[] = {kRed, kGreen, kOrange};
  std::vector<LegendItem> items = {{"APE", kBlue, Mark::kLine}};
  for (size_t k = 0; k < lines.size(); ++k) {
    ax.polyline(img, {ax.px(ax.x0, lines[k].second), ax.px(ax.x1, lines[k].second)}, colors[k], 1,
                5.0);
    char buf[64];
    std::snprintf(buf, sizeof(buf), "%s %.4g", lines[k].first.c_str(), lines[k].second);
    items.push_back({buf, colors[k], Mark::kDashed});
  }
  int width = 0;
  for (const LegendItem& item : items) width = std::max(width, text_size(item.label).width);
  legend(img, {area.x + area.width - width - 70, area.y + 10}, items);
}

}  // namespace

void write_plot(const std::string& path, const EvalResult& result, const std::string& title) {
  if (result.matched.est.poses.empty() || result.ape.series.values.empty())
    throw InputError(path, "nothing to plot");
  cv::Mat img(1100, 1200, CV_8UC3, cv::Scalar::all(255));
  text(img, title, {110, 22}, 0.6);
  char line[256];
  std::snprintf(line, sizeof(line),
                "%zu poses matched | APE %s rmse %.4g %s | RPE rmse %.4g m, %.4g deg | align %s",
                result.matched.est.poses.size(), relation_name(result.ape.relation),
                result.ape.stats.rmse, relation_unit(result.ape.relation),
                result.rpe_trans.stats.rmse, result.rpe_rot.stats.rmse,
                align_mode_name(result.options.align));
  text(img, line, {110, 42});
  draw_top_view(img, cv::Rect(110, 55, 1060, 675), result);
  draw_error_panel(img, cv::Rect(110, 810, 1060, 230), result);
  std::vector<uchar> png;
  if (!cv::imencode(".png", img, png)) throw InputError(path, "cannot encode PNG");
  write_file_atomically(path, std::string(png.begin(), png.end()));
}

}  // namespace hs
