#pragma once
// One V4L2 capture device streaming into mmap'ed buffers. Opening checks what hs-camera needs and
// fails with the reason: missing or busy device, no streaming capture, a format or frame rate
// the device will not take. Dequeue reports a lost device (unplugged: ENODEV, EIO) as such.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "drivers/camera/frame_time.h"
#include "drivers/camera/pixel_format.h"

namespace hs {

struct V4l2Format {
  int width = 752;
  int height = 480;
  PixelFormat format = PixelFormat::kGrey;
  double fps = 20.0;
  int64_t exposure_ns = 0;  // 0: leave the device's exposure as it is
  // false: the exposure is set on the camera by other means (its vendor tool, trigger-width
  // mode); exposure_ns is then only what the frame times assume.
  bool exposure_control = true;
  int gain = -1;  // -1: leave it
};

// A dequeued buffer: valid until requeue(index).
struct V4l2Frame {
  int index = -1;
  const uint8_t* data = nullptr;
  size_t bytes_used = 0;
  uint32_t sequence = 0;
  BufferTime time;
};

class V4l2Device {
 public:
  // Opens, configures and starts streaming; throws std::runtime_error naming the device.
  V4l2Device(const std::string& path, const V4l2Format& format, int buffers = 4);
  ~V4l2Device();
  V4l2Device(const V4l2Device&) = delete;
  V4l2Device& operator=(const V4l2Device&) = delete;

  enum class Status { kFrame, kTimeout, kLost };
  // Waits up to timeout_ms for a frame.
  Status dequeue(int timeout_ms, V4l2Frame* frame);
  void requeue(int index);

  int fd() const { return fd_; }
  const std::string& path() const { return path_; }
  // What the device agreed to.
  int width() const { return width_; }
  int height() const { return height_; }
  int bytes_per_line() const { return bytes_per_line_; }
  PixelFormat format() const { return format_; }
  int64_t exposure_ns() const { return exposure_ns_; }
  std::string lost_reason() const { return lost_reason_; }

 private:
  [[noreturn]] void fail(const std::string& what) const;
  void set_control(uint32_t id, int value, const char* name);

  std::string path_;
  int fd_ = -1;
  int width_ = 0, height_ = 0, bytes_per_line_ = 0;
  PixelFormat format_ = PixelFormat::kGrey;
  int64_t exposure_ns_ = 0;
  std::vector<std::pair<void*, size_t>> maps_;
  bool streaming_ = false;
  std::string lost_reason_;
};

}  // namespace hs
