// MapperNode over in-process LCM (memq://): a lost tracker's RELOC_REQUEST is answered on
// RELOC_ANSWER from the atlas (issue 7); a guess far from the place is refused (a look-alike
// implies a jump), a malformed request is counted and gets no answer.
#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <lcm/lcm-cpp.hpp>
#include <thread>

#include "common/lcm/convert.h"
#include "common/lcm/decode.h"
#include "hsslam/heartbeat_t.hpp"
#include "hsslam/reloc_answer_t.hpp"
#include "hsslam/reloc_request_t.hpp"
#include "mapper/node/mapper_node.h"
#include "mapper/offline/mapper_report.h"
#include "tests/lcm/lcm_test_util.h"
#include "tracker/offline/offline_run.h"

namespace hs {
namespace {

using test::collect;

int64_t counter(const hsslam::heartbeat_t& hb, const std::string& name) {
  for (size_t i = 0; i < hb.counter_names.size(); ++i)
    if (hb.counter_names[i] == name) return hb.counter_values[i];
  return -1;
}

TEST(MapperNodeReloc, AnswersWhereTheAtlasPlacesALostFrameAndCountsABadRequest) {
  // The KEYFRAME messages of 10 s of room_mav, and the map an in-process mapper made of them.
  sim::Scenario s = sim::load_scenario(HS_SOURCE_DIR "/config/sim/room_mav.yaml");
  s.duration_s = 10.0;
  TrackerOptions options;
  options.calib = s.camera.calib;
  Mapper mapper(options.calib, reproducible(MapperOptions{}));
  MapperRunStats stats;
  std::vector<hsslam::keyframe_t> keyframes;
  OfflineRunOptions run_options;
  const BackEnd back_end = in_process_back_end(mapper, stats);
  run_options.back_end = [&](const hsslam::keyframe_t& kf) {
    keyframes.push_back(kf);
    return back_end(kf);
  };
  sim::DatasetGenerator gen(s);
  run_offline(options, sim_source(gen), run_options);
  ASSERT_GT(keyframes.size(), 10u);

  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  MapperNodeOptions node_options;
  node_options.heartbeat_period_ns = 20'000'000;
  MapperNode node(lcm, options.calib, reproducible(MapperOptions{}), node_options);
  std::vector<hsslam::reloc_answer_t> answers;
  std::vector<hsslam::heartbeat_t> heartbeats;
  lcm.subscribeFunction("RELOC_ANSWER", &collect<hsslam::reloc_answer_t>, &answers);
  lcm.subscribeFunction("HEARTBEAT", &collect<hsslam::heartbeat_t>, &heartbeats);
  node.start();
  // Every keyframe but the one the tracker will be lost at.
  const size_t k = keyframes.size() / 2;
  for (size_t i = 0; i < keyframes.size(); ++i)
    if (i != k) lcm.publish("KEYFRAME", &keyframes[i]);
  const auto pump = [&](const std::function<bool()>& done) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (std::chrono::steady_clock::now() < deadline && !done()) {
      lcm.handleTimeout(10);
      node.poll();
    }
  };
  pump([&] { return node.stats().keyframes_mapped + 1 == static_cast<int64_t>(keyframes.size()); });

  // The tracker lost in its map 0 at keyframe k's place, offering map id 5; then with a guess
  // 2 m off; then with its own map id.
  const hsslam::keyframe_t& lost = keyframes[k];
  hsslam::reloc_request_t request{};
  request.seq = 11;
  request.next_map_id = 5;
  request.frame = lost;
  hsslam::reloc_request_t far = request;
  far.seq = 12;
  far.next_map_id = 6;
  far.frame.pose.p_w_b[0] += 2.0;
  hsslam::reloc_request_t bad = request;
  bad.seq = 13;
  bad.next_map_id = lost.map_id;
  lcm.publish("RELOC_REQUEST", &bad);
  lcm.publish("RELOC_REQUEST", &request);
  lcm.publish("RELOC_REQUEST", &far);
  pump([&] {
    return answers.size() >= 2 && !heartbeats.empty() &&
           counter(heartbeats.back(), "reloc_answers_published") >= 2;
  });
  node.stop();
  while (lcm.handleTimeout(0) > 0) {
  }

  ASSERT_EQ(answers.size(), 2u) << "the malformed request gets no answer";
  const RelocAnswer a = reloc_answer_from_msg(answers[0], "RELOC_ANSWER");
  EXPECT_EQ(a.seq, 11);
  EXPECT_EQ(a.t_ns, lost.t_ns);
  ASSERT_TRUE(a.found) << a.message;
  EXPECT_EQ(a.map_id, 5);
  EXPECT_GE(a.inliers, 30);
  // Where the in-process mapper, which had the keyframe, put it.
  const std::optional<Eigen::Isometry3d> T_w_kf = mapper.keyframe_pose(lost.pose.id);
  ASSERT_TRUE(T_w_kf);
  const double err_m = (a.T_w_b.translation() - T_w_kf->translation()).norm();
  const double err_deg =
      Eigen::AngleAxisd(a.T_w_b.linear().transpose() * T_w_kf->linear()).angle() * 180 / M_PI;
  EXPECT_LT(err_m, 0.02) << a.message;
  EXPECT_LT(err_deg, 0.5) << a.message;
  const RelocAnswer refused = reloc_answer_from_msg(answers[1], "RELOC_ANSWER");
  EXPECT_EQ(refused.seq, 12);
  EXPECT_FALSE(refused.found);
  EXPECT_NE(refused.message.find("from the tracker's guess"), std::string::npos) << refused.message;
  ASSERT_FALSE(heartbeats.empty());
  EXPECT_EQ(counter(heartbeats.back(), "reloc_requests_received"), 3);
  EXPECT_EQ(counter(heartbeats.back(), "bad_reloc_request_messages"), 1);
  EXPECT_EQ(counter(heartbeats.back(), "relocalisations"), 1);
  std::printf("answer: %.1f mm, %.3f deg from the keyframe's pose; %s\nrefused: %s\n", err_m * 1e3,
              err_deg, a.message.c_str(), refused.message.c_str());
}

}  // namespace
}  // namespace hs
