#pragma once
// V4L2 pixel formats hs-camera accepts, converted to the 8-bit mono images the tracker uses:
// GREY (Y8), Y16 (little-endian, the top 8 bits kept) and YUYV (the luma bytes). A buffer that
// is shorter than its format needs is an error, never read past.
#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

namespace hs {

enum class PixelFormat { kGrey, kY16, kYuyv };

// From a V4L2 fourcc (V4L2_PIX_FMT_*); throws std::runtime_error naming an unsupported one.
PixelFormat pixel_format_from_fourcc(uint32_t fourcc);
uint32_t fourcc_of(PixelFormat format);
// "GREY", "Y16 ", "YUYV", or the four characters of any fourcc.
std::string fourcc_name(uint32_t fourcc);
// From the config's name: GREY (or Y8), Y16, YUYV.
PixelFormat pixel_format_from_name(const std::string& name);
int bytes_per_pixel(PixelFormat format);

// `bytes_per_line` >= width * bytes_per_pixel; `size` >= bytes_per_line * height. The result
// owns its pixels (CV_8UC1, width x height).
cv::Mat to_mono8(PixelFormat format, const uint8_t* data, size_t size, int width, int height,
                 int bytes_per_line);

}  // namespace hs
