#pragma once
// Draws a ViewerModel into one picture (1280x720, BGR): the current cam0 image with the frame's
// features coloured by how they were found, the tracker's state and timing, and a top view
// (world x-y) of the trajectory, keyframes and map points.
#include <opencv2/core.hpp>

#include "tools/viewer/viewer_model.h"

namespace hs {

// Feature colours (BGR), also used by the legend.
const cv::Scalar kDirectColour(60, 200, 60);      // patch alignment: green
const cv::Scalar kDescriptorColour(0, 140, 255);  // ORB matching: orange
const cv::Scalar kNewColour(255, 150, 40);        // new from the keyframe's stereo pair: blue

struct ViewerLayout {
  cv::Size canvas{1280, 720};
  cv::Rect image{0, 30, 640, 408};  // the cam0 image, scaled to fit (aspect kept)
  cv::Rect timing{0, 470, 640, 250};
  cv::Rect top_view{650, 30, 620, 680};

  // Where pixel `uv` of an image of `size` lands on the canvas.
  cv::Point2f image_to_canvas(const cv::Size& size, const cv::Point2f& uv) const;
};

cv::Mat render_view(const ViewerModel& model, const ViewerLayout& layout = {});

}  // namespace hs
