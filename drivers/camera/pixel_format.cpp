#include "drivers/camera/pixel_format.h"

#include <linux/videodev2.h>

#include <stdexcept>

namespace hs {

PixelFormat pixel_format_from_fourcc(uint32_t fourcc) {
  switch (fourcc) {
    case V4L2_PIX_FMT_GREY:
      return PixelFormat::kGrey;
    case V4L2_PIX_FMT_Y16:
      return PixelFormat::kY16;
    case V4L2_PIX_FMT_YUYV:
      return PixelFormat::kYuyv;
  }
  throw std::runtime_error("pixel format '" + fourcc_name(fourcc) +
                           "' not supported (GREY, Y16, YUYV)");
}

uint32_t fourcc_of(PixelFormat format) {
  switch (format) {
    case PixelFormat::kGrey:
      return V4L2_PIX_FMT_GREY;
    case PixelFormat::kY16:
      return V4L2_PIX_FMT_Y16;
    case PixelFormat::kYuyv:
      return V4L2_PIX_FMT_YUYV;
  }
  return 0;
}

std::string fourcc_name(uint32_t fourcc) {
  std::string s;
  for (int i = 0; i < 4; ++i) {
    const char c = static_cast<char>((fourcc >> (8 * i)) & 0xFF);
    s += (c >= 32 && c < 127) ? c : '?';
  }
  return s;
}

PixelFormat pixel_format_from_name(const std::string& name) {
  if (name == "GREY" || name == "Y8") return PixelFormat::kGrey;
  if (name == "Y16") return PixelFormat::kY16;
  if (name == "YUYV") return PixelFormat::kYuyv;
  throw std::runtime_error("pixel format '" + name + "' not supported (GREY, Y16, YUYV)");
}

int bytes_per_pixel(PixelFormat format) {
  return format == PixelFormat::kGrey ? 1 : 2;
}

cv::Mat to_mono8(PixelFormat format, const uint8_t* data, size_t size, int width, int height,
                 int bytes_per_line) {
  const int bpp = bytes_per_pixel(format);
  if (width <= 0 || height <= 0 || bytes_per_line < width * bpp)
    throw std::runtime_error("bad image geometry " + std::to_string(width) + "x" +
                             std::to_string(height) + ", " + std::to_string(bytes_per_line) +
                             " bytes per line");
  const size_t needed = static_cast<size_t>(bytes_per_line) * static_cast<size_t>(height);
  if (size < needed)
    throw std::runtime_error("short frame: " + std::to_string(size) + " bytes, " +
                             std::to_string(needed) + " needed");
  cv::Mat out(height, width, CV_8UC1);
  for (int y = 0; y < height; ++y) {
    const uint8_t* row = data + static_cast<size_t>(y) * static_cast<size_t>(bytes_per_line);
    uint8_t* dst = out.ptr<uint8_t>(y);
    switch (format) {
      case PixelFormat::kGrey:
        std::copy(row, row + width, dst);
        break;
      case PixelFormat::kY16:   // little-endian: the high byte is the second
      case PixelFormat::kYuyv:  // Y0 U Y1 V: luma at even bytes
        for (int x = 0; x < width; ++x) dst[x] = row[2 * x + (format == PixelFormat::kY16)];
        break;
    }
  }
  return out;
}

}  // namespace hs
