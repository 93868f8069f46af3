#include "drivers/camera/v4l2_device.h"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace hs {
namespace {

int xioctl(int fd, unsigned long request, void* arg) {
  int r;
  do {
    r = ::ioctl(fd, request, arg);
  } while (r < 0 && errno == EINTR);
  return r;
}

}  // namespace

void V4l2Device::fail(const std::string& what) const {
  throw std::runtime_error(path_ + ": " + what);
}

V4l2Device::V4l2Device(const std::string& path, const V4l2Format& want, int buffers) : path_(path) {
  fd_ = ::open(path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) {
    const int err = errno;
    throw std::runtime_error(path + ": cannot open: " + std::strerror(err) +
                             (err == EBUSY ? " (another program has it)" : ""));
  }
  try {
    v4l2_capability cap{};
    if (xioctl(fd_, VIDIOC_QUERYCAP, &cap) < 0) fail("not a V4L2 device");
    const uint32_t caps =
        (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
    if (!(caps & V4L2_CAP_VIDEO_CAPTURE) || !(caps & V4L2_CAP_STREAMING))
      fail("no streaming video capture");

    v4l2_format fmt{};
    fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    fmt.fmt.pix.width = static_cast<uint32_t>(want.width);
    fmt.fmt.pix.height = static_cast<uint32_t>(want.height);
    fmt.fmt.pix.pixelformat = fourcc_of(want.format);
    fmt.fmt.pix.field = V4L2_FIELD_NONE;
    fmt.fmt.pix.bytesperline = 0;  // let the driver choose the stride afresh
    fmt.fmt.pix.sizeimage = 0;
    if (xioctl(fd_, VIDIOC_S_FMT, &fmt) < 0) {
      const int err = errno;
      fail(std::string("cannot set the format: ") + std::strerror(err) +
           (err == EBUSY ? " (another program is streaming from it)" : ""));
    }
    if (fmt.fmt.pix.pixelformat != fourcc_of(want.format) ||
        static_cast<int>(fmt.fmt.pix.width) != want.width ||
        static_cast<int>(fmt.fmt.pix.height) != want.height)
      fail("format " + fourcc_name(fourcc_of(want.format)) + " " + std::to_string(want.width) +
           "x" + std::to_string(want.height) + " refused: the device offers " +
           fourcc_name(fmt.fmt.pix.pixelformat) + " " + std::to_string(fmt.fmt.pix.width) + "x" +
           std::to_string(fmt.fmt.pix.height));
    width_ = static_cast<int>(fmt.fmt.pix.width);
    height_ = static_cast<int>(fmt.fmt.pix.height);
    bytes_per_line_ = static_cast<int>(fmt.fmt.pix.bytesperline);
    if (bytes_per_line_ == 0) bytes_per_line_ = width_ * bytes_per_pixel(want.format);
    format_ = want.format;

    v4l2_streamparm parm{};
    parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    parm.parm.capture.timeperframe.numerator = 1000;
    parm.parm.capture.timeperframe.denominator =
        static_cast<uint32_t>(std::lround(want.fps * 1000));
    if (xioctl(fd_, VIDIOC_S_PARM, &parm) < 0)
      fail(std::string("cannot set the frame rate: ") + std::strerror(errno));
    const v4l2_fract got = parm.parm.capture.timeperframe;
    if (got.numerator == 0 ||
        std::abs(static_cast<double>(got.denominator) / got.numerator - want.fps) > 0.01 * want.fps)
      fail("frame rate " + std::to_string(want.fps) + " Hz refused (the device gives " +
           std::to_string(got.numerator ? static_cast<double>(got.denominator) / got.numerator
                                        : 0.0) +
           " Hz)");
    if (want.exposure_ns > 0 && want.exposure_control) {
      set_control(V4L2_CID_EXPOSURE_AUTO, V4L2_EXPOSURE_MANUAL, "manual exposure");
      set_control(V4L2_CID_EXPOSURE_ABSOLUTE, static_cast<int>(want.exposure_ns / 100'000),
                  "exposure");  // in units of 100 us
    }
    exposure_ns_ = want.exposure_ns;
    if (want.gain >= 0) set_control(V4L2_CID_GAIN, want.gain, "gain");

    v4l2_requestbuffers req{};
    req.count = static_cast<uint32_t>(buffers);
    req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    req.memory = V4L2_MEMORY_MMAP;
    if (xioctl(fd_, VIDIOC_REQBUFS, &req) < 0 || req.count < 2)
      fail(std::string("cannot get mmap buffers: ") + std::strerror(errno));
    for (uint32_t i = 0; i < req.count; ++i) {
      v4l2_buffer buf{};
      buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      buf.memory = V4L2_MEMORY_MMAP;
      buf.index = i;
      if (xioctl(fd_, VIDIOC_QUERYBUF, &buf) < 0) fail("cannot query a buffer");
      void* p = ::mmap(nullptr, buf.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, buf.m.offset);
      if (p == MAP_FAILED) fail(std::string("cannot map a buffer: ") + std::strerror(errno));
      maps_.emplace_back(p, buf.length);
      if (xioctl(fd_, VIDIOC_QBUF, &buf) < 0) fail("cannot queue a buffer");
    }
    int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (xioctl(fd_, VIDIOC_STREAMON, &type) < 0)
      fail(std::string("cannot start streaming: ") + std::strerror(errno));
    streaming_ = true;
  } catch (...) {
    for (const auto& [p, n] : maps_) ::munmap(p, n);
    ::close(fd_);
    throw;
  }
}

V4l2Device::~V4l2Device() {
  if (streaming_) {
    int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    xioctl(fd_, VIDIOC_STREAMOFF, &type);
  }
  for (const auto& [p, n] : maps_) ::munmap(p, n);
  ::close(fd_);
}

void V4l2Device::set_control(uint32_t id, int value, const char* name) {
  v4l2_control c{};
  c.id = id;
  c.value = value;
  if (xioctl(fd_, VIDIOC_S_CTRL, &c) < 0)
    fail(std::string("cannot set ") + name + ": " + std::strerror(errno));
}

V4l2Device::Status V4l2Device::dequeue(int timeout_ms, V4l2Frame* frame) {
  pollfd p{fd_, POLLIN, 0};
  const int ready = ::poll(&p, 1, timeout_ms);
  if (ready == 0 || (ready < 0 && errno == EINTR)) return Status::kTimeout;
  if (ready < 0 || (p.revents & (POLLERR | POLLHUP | POLLNVAL)) != 0) {
    lost_reason_ = ready < 0 ? std::strerror(errno) : "device hung up";
    return Status::kLost;
  }
  v4l2_buffer buf{};
  buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  buf.memory = V4L2_MEMORY_MMAP;
  if (xioctl(fd_, VIDIOC_DQBUF, &buf) < 0) {
    if (errno == EAGAIN) return Status::kTimeout;
    lost_reason_ = std::strerror(errno);
    return Status::kLost;  // ENODEV (unplugged), EIO
  }
  frame->index = static_cast<int>(buf.index);
  frame->data = static_cast<const uint8_t*>(maps_.at(buf.index).first);
  frame->bytes_used = buf.bytesused;
  frame->sequence = buf.sequence;
  frame->time.t_ns = static_cast<int64_t>(buf.timestamp.tv_sec) * 1'000'000'000 +
                     static_cast<int64_t>(buf.timestamp.tv_usec) * 1000;
  frame->time.flags = buf.flags;
  return Status::kFrame;
}

void V4l2Device::requeue(int index) {
  v4l2_buffer buf{};
  buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  buf.memory = V4L2_MEMORY_MMAP;
  buf.index = static_cast<uint32_t>(index);
  xioctl(fd_, VIDIOC_QBUF, &buf);
}

}  // namespace hs
