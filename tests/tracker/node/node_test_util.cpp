#include "tests/tracker/node/node_test_util.h"

#include "common/lcm/convert.h"
#include "common/sim/dataset_gen.h"
#include "tracker/offline/offline_run.h"

namespace hs::test {

SimSequence make_sim_sequence(double duration_s) {
  sim::Scenario scenario = sim::load_scenario(HS_SOURCE_DIR "/config/sim/room_mav.yaml");
  scenario.duration_s = duration_s;
  SimSequence seq;
  seq.options.calib = scenario.camera.calib;
  sim::DatasetGenerator gen(scenario);
  const EventSource source = sim_source(gen);
  Tracker tracker(seq.options);
  std::vector<ImuSample> batch;
  const auto flush = [&] {
    if (batch.empty()) return;
    seq.messages.push_back({seq.options.channels.imu, encode(imu_batch_to_msg(batch, 0)), false});
    batch.clear();
  };
  DatasetEvent e;
  while (source(e)) {
    if (const auto* s = std::get_if<ImuSample>(&e)) {
      tracker.add_imu(*s);
      seq.imu.push_back(*s);
      batch.push_back(*s);
      if (batch.size() == 10) flush();
    } else if (const auto* frame = std::get_if<StereoFrame>(&e)) {
      flush();
      seq.messages.push_back({seq.options.channels.cam_stereo,
                              encode(frame_to_msg(*frame, ImageEncoding::kMono8)), true});
      seq.reference.push_back(tracker.track(*frame));
    }
  }
  return seq;
}

}  // namespace hs::test
