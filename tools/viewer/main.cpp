// hs-viewer: a live view of a running (or replayed) HS-SLAM: the current image with the
// tracker's features, the trajectory, keyframes and map points from above, and timing. Opens a
// window where a display exists; --headless writes PNG frames and/or a video instead.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <opencv2/highgui.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <string>

#include "common/config/channels.h"
#include "common/core/monotonic_clock.h"
#include "common/core/stop_signal.h"
#include "common/lcm/convert.h"
#include "common/lcm/decode.h"
#include "common/lcm/lcm_connection.h"
#include "tools/viewer/viewer_model.h"
#include "tools/viewer/viewer_render.h"

namespace {

constexpr const char* kWindow = "HS-SLAM";

// One handler for every channel: decodes by channel and feeds the model; bad messages are
// counted and shown, never fatal.
struct Feeder {
  hs::ViewerModel* model;
  hs::ChannelNames channels;
  int64_t last_message_ns = 0;

  static void on(const lcm::ReceiveBuffer* rbuf, const std::string& channel, Feeder* self) {
    self->last_message_ns = hs::monotonic_ns();
    hs::ViewerModel& m = *self->model;
    const hs::ChannelNames& ch = self->channels;
    try {
      if (channel == ch.cam_stereo) {
        const auto msg =
            hs::decode_message<hsslam::stereo_frame_t>(rbuf->data, rbuf->data_size, channel);
        hs::StereoFrame frame = hs::frame_from_msg(msg, channel);
        m.on_image(frame.t_ns, frame.cam0);
      } else if (channel == ch.tracker_status) {
        m.on_status(
            hs::decode_message<hsslam::tracker_status_t>(rbuf->data, rbuf->data_size, channel));
      } else if (channel == ch.pose) {
        m.on_pose(hs::decode_message<hsslam::odometry_t>(rbuf->data, rbuf->data_size, channel));
      } else if (channel == ch.keyframe) {
        m.on_keyframe(hs::decode_message<hsslam::keyframe_t>(rbuf->data, rbuf->data_size, channel));
      } else if (channel == ch.map_update) {
        m.on_map_update(
            hs::decode_message<hsslam::map_update_t>(rbuf->data, rbuf->data_size, channel));
      }
    } catch (const std::exception& e) {
      m.on_bad_message(e.what());
    }
  }
};

bool has_display() {
  return std::getenv("DISPLAY") || std::getenv("WAYLAND_DISPLAY");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hs-viewer: live view of the tracker's image, features, trajectory, map and timing"};
  std::string url = hs::default_lcm_url(), config, out_dir, video, snapshot;
  bool headless = false;
  double fps = 5.0, idle_exit_s = 0.0;
  app.add_option("--lcm-url", url, "LCM URL ($LCM_DEFAULT_URL or the project default)")
      ->capture_default_str();
  app.add_option("--config", config, "a config with a channels: section (renamed channels)");
  app.add_flag("--headless", headless, "no window: write --out frames and/or a --video");
  app.add_option("--out", out_dir, "headless: write DIR/view_NNNNNN.png at --fps");
  app.add_option("--video", video, "headless: write an MJPG video (.avi) at --fps");
  app.add_option("--snapshot", snapshot, "write the last view to this PNG at exit");
  app.add_option("--fps", fps, "views per second drawn (when something changed)")
      ->check(CLI::Range(0.1, 60.0))
      ->capture_default_str();
  app.add_option("--idle-exit", idle_exit_s,
                 "exit this many seconds after the last message (0: run until SIGINT/SIGTERM)");
  CLI11_PARSE(app, argc, argv);
  if (!headless && !has_display()) {
    std::fprintf(stderr,
                 "hs-viewer: no display (DISPLAY / WAYLAND_DISPLAY unset): use --headless with "
                 "--out DIR, --video FILE.avi or --snapshot FILE.png\n");
    return 2;
  }
  if (headless && out_dir.empty() && video.empty() && snapshot.empty()) {
    std::fprintf(stderr, "hs-viewer: --headless needs --out, --video or --snapshot\n");
    return 2;
  }

  hs::install_stop_signals();
  try {
    hs::ViewerModel model;
    Feeder feeder{&model, config.empty() ? hs::ChannelNames{} : hs::load_channel_names(config)};
    auto lcm = hs::connect_lcm(url);
    if (const std::string w = hs::receive_buffer_warning(url); !w.empty())
      std::fprintf(stderr, "hs-viewer: warning: %s\n", w.c_str());
    const hs::ChannelNames& ch = feeder.channels;
    for (const std::string& channel :
         {ch.cam_stereo, ch.tracker_status, ch.pose, ch.keyframe, ch.map_update})
      lcm->subscribeFunction(channel, &Feeder::on, &feeder);
    if (!out_dir.empty()) std::filesystem::create_directories(out_dir);
    cv::VideoWriter writer;
    const hs::ViewerLayout layout;
    if (!video.empty() &&
        !writer.open(video, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), fps, layout.canvas))
      throw std::runtime_error("cannot write the video " + video + " (MJPG .avi)");
    if (!headless) cv::namedWindow(kWindow, cv::WINDOW_AUTOSIZE | cv::WINDOW_GUI_NORMAL);
    std::printf("hs-viewer: listening on %s\n", url.c_str());
    std::fflush(stdout);

    const int64_t period_ns = static_cast<int64_t>(1e9 / fps);
    int64_t next_draw = hs::monotonic_ns();
    uint64_t drawn_version = 0;
    int written = 0;
    cv::Mat view = hs::render_view(model, layout);
    while (!hs::stop_requested()) {
      // Everything waiting, then one view: a burst never waits behind drawing.
      for (int status = lcm->handleTimeout(10); status > 0; status = lcm->handleTimeout(0)) {
      }
      if (!lcm->good() && !hs::stop_requested()) throw std::runtime_error("LCM receive failed");
      const int64_t now = hs::monotonic_ns();
      if (idle_exit_s > 0 && feeder.last_message_ns > 0 &&
          now - feeder.last_message_ns > static_cast<int64_t>(idle_exit_s * 1e9))
        break;
      if (now >= next_draw && model.version() != drawn_version) {
        next_draw = now + period_ns;
        drawn_version = model.version();
        view = hs::render_view(model, layout);
        if (!out_dir.empty()) {
          char name[32];
          std::snprintf(name, sizeof name, "/view_%06d.png", written);
          cv::imwrite(out_dir + name, view);
        }
        if (writer.isOpened()) writer.write(view);
        ++written;
        if (!headless) cv::imshow(kWindow, view);
      }
      if (!headless) {
        const int key = cv::waitKey(1);
        if (key == 'q' || key == 27 || cv::getWindowProperty(kWindow, cv::WND_PROP_VISIBLE) < 1)
          break;
      }
    }
    view = hs::render_view(model, layout);
    if (!snapshot.empty() && !cv::imwrite(snapshot, view))
      throw std::runtime_error("cannot write " + snapshot);
    std::printf(
        "hs-viewer: %d views drawn; %zu poses, %zu keyframes, %zu map points, %lld "
        "MAP_UPDATE, %lld bad messages\n",
        written, model.trajectory().size(), model.keyframes().size(), model.points().size(),
        static_cast<long long>(model.map_updates()), static_cast<long long>(model.bad_messages()));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hs-viewer: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
