// A camera with an external-trigger input, for the HIL guest: it exposes a frame on each rising
// edge of a GPIO line and delivers it through a v4l2loopback device, whose capture side hs-camera
// reads like a real camera's (the driver stamps each buffer on CLOCK_MONOTONIC when it is written).
// The trigger input is gpio-sim's view of hs-trigger's output line (sysfs sim_gpioN/value: the
// line is hs-trigger's, so it cannot also be requested here). Pulse --skip is missed, like a
// camera still reading out when the pulse comes. Each frame's pixels hold its pulse number.
//   hil-triggered-camera DEVICE VALUE_FILE WIDTH HEIGHT SKIP
#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <vector>

namespace {

volatile std::sig_atomic_t g_stop = 0;

void on_signal(int) {
  g_stop = 1;
}

int fail(const char* what) {
  std::fprintf(stderr, "hil-triggered-camera: %s: %s\n", what, std::strerror(errno));
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 6) {
    std::fprintf(stderr, "usage: hil-triggered-camera DEVICE VALUE_FILE WIDTH HEIGHT SKIP\n");
    return 2;
  }
  const unsigned width = static_cast<unsigned>(std::atoi(argv[3]));
  const unsigned height = static_cast<unsigned>(std::atoi(argv[4]));
  const long skip = std::atol(argv[5]);
  const int video = ::open(argv[1], O_RDWR);
  if (video < 0) return fail(argv[1]);
  v4l2_format fmt{};
  fmt.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
  fmt.fmt.pix.width = width;
  fmt.fmt.pix.height = height;
  fmt.fmt.pix.pixelformat = V4L2_PIX_FMT_GREY;
  fmt.fmt.pix.field = V4L2_FIELD_NONE;
  fmt.fmt.pix.bytesperline = width;
  fmt.fmt.pix.sizeimage = width * height;
  if (::ioctl(video, VIDIOC_S_FMT, &fmt) < 0) return fail("VIDIOC_S_FMT (output)");
  // Streaming on the output side allocates the buffers: readers can open before the first frame.
  int type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
  if (::ioctl(video, VIDIOC_STREAMON, &type) < 0) return fail("VIDIOC_STREAMON (output)");
  const int value = ::open(argv[2], O_RDONLY);
  if (value < 0) return fail(argv[2]);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::printf("hil-triggered-camera: %ux%u GREY on %s, triggered by %s: ready\n", width, height,
              argv[1], argv[2]);
  std::fflush(stdout);

  std::vector<unsigned char> frame(static_cast<size_t>(width) * height);
  long pulses = 0, written = 0, skipped = 0;
  char last = '0';
  const timespec poll_period{0, 200'000};
  while (!g_stop) {
    char v = 0;
    if (::pread(value, &v, 1, 0) != 1) return fail("reading the trigger line");
    if (v == '1' && last == '0') {
      ++pulses;
      if (pulses == skip) {
        ++skipped;
      } else {
        std::memset(frame.data(), static_cast<int>(pulses & 0xff), frame.size());
        if (::write(video, frame.data(), frame.size()) != static_cast<ssize_t>(frame.size()))
          return fail("writing a frame");
        ++written;
      }
    }
    last = v;
    ::nanosleep(&poll_period, nullptr);
  }
  std::printf("hil-triggered-camera: %ld pulses, %ld frames written, %ld skipped\n", pulses,
              written, skipped);
  return 0;
}
