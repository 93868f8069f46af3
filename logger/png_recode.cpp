#include "logger/png_recode.h"

#include <opencv2/imgcodecs.hpp>

#include "hsslam/stereo_frame_t.hpp"

namespace hs {

bool recode_stereo_png(std::vector<uint8_t>* data, std::string* error) {
  hsslam::stereo_frame_t msg;
  if (msg.decode(data->data(), 0, static_cast<int>(data->size())) < 0) {
    *error = "not a stereo_frame_t (fingerprint or length)";
    return false;
  }
  // Fast compression: the logger must keep up with 20 Hz stereo on one core.
  const std::vector<int> params = {cv::IMWRITE_PNG_COMPRESSION, 1};
  for (hsslam::image_t& im : msg.images) {
    if (im.encoding != hsslam::image_t::MONO8) continue;
    if (im.width <= 0 || im.height <= 0 || im.stride < im.width ||
        static_cast<int64_t>(im.stride) * im.height != im.size) {
      *error = "image of " + std::to_string(im.width) + "x" + std::to_string(im.height) +
               " with stride " + std::to_string(im.stride) + " and " + std::to_string(im.size) +
               " bytes";
      return false;
    }
    const cv::Mat view(im.height, im.width, CV_8UC1, im.data.data(),
                       static_cast<size_t>(im.stride));
    std::vector<uint8_t> png;
    if (!cv::imencode(".png", view, png, params)) {
      *error = "PNG encoding failed";
      return false;
    }
    im.data = std::move(png);
    im.size = static_cast<int32_t>(im.data.size());
    im.stride = 0;
    im.encoding = hsslam::image_t::PNG;
  }
  std::vector<uint8_t> out(static_cast<size_t>(msg.getEncodedSize()));
  if (msg.encode(out.data(), 0, static_cast<int>(out.size())) < 0) {
    *error = "re-encoding failed";
    return false;
  }
  *data = std::move(out);
  return true;
}

}  // namespace hs
