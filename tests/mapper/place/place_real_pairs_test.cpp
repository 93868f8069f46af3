// Place recognition and verification on real EuRoC V1_01 stereo pairs (../shared/data, in CI
// only). Which pairs show the same place is read from the ground truth: 1403715386.76 s revisits
// the place of 1403715288.31 s (0.42 m, 37 deg apart, 98 s later), and 1403715400.26 s and
// 400.76 s see the same scene from 0.31 m and 16 deg apart; the cross pairs look at opposite
// sides of the room (more than 150 deg apart) and must be rejected.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <opencv2/imgcodecs.hpp>

#include "common/dataset/euroc_csv.h"
#include "mapper/place_index.h"
#include "mapper/place_verify.h"
#include "tests/mapper/place/stereo_keyframe_util.h"

namespace hs {
namespace {

const std::string kEuroc = HS_SOURCE_DIR "/../shared/data/euroc";
const std::string kPairs = kEuroc + "/V1_01_loop_pairs";
constexpr int64_t kEarly = 1403715288312143104, kRevisit = 1403715386762142976;
constexpr int64_t kBoxA = 1403715400262142976, kBoxB = 1403715400762142976;

class PlaceRealPairs : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(kPairs))
      GTEST_SKIP() << kPairs << " not found (real EuRoC data is only in CI)";
    const std::vector<NavState> gt = read_ground_truth_csv(kEuroc + "/groundtruth/V1_01_easy.csv");
    for (int64_t t : {kEarly, kRevisit, kBoxA, kBoxB}) {
      const std::string name = "/" + std::to_string(t) + ".png";
      const cv::Mat cam0 = cv::imread(kPairs + "/cam0" + name, cv::IMREAD_GRAYSCALE);
      const cv::Mat cam1 = cv::imread(kPairs + "/cam1" + name, cv::IMREAD_GRAYSCALE);
      ASSERT_FALSE(cam0.empty() || cam1.empty()) << name;
      keyframes_.emplace(t, keyframes_maker_.make(t, cam0, cam1));
      for (const NavState& s : gt)
        if (std::abs(s.t_ns - t) < 1'000'000) T_w_b_[t] = s.T_w_b();
      ASSERT_TRUE(T_w_b_.count(t)) << "no ground truth at " << t;
    }
  }

  test::StereoKeyframes keyframes_maker_;
  std::map<int64_t, MapperKeyframe> keyframes_;
  std::map<int64_t, Eigen::Isometry3d> T_w_b_;
};

TEST_F(PlaceRealPairs, RevisitsAreFoundAndTheirRelativePoseIsWithin5cmAnd2deg) {
  PlaceIndex index;
  for (const auto& [t, kf] : keyframes_) index.add(kf.id, kf.descriptors);
  for (const auto& [query, place] : {std::pair(kRevisit, kEarly), std::pair(kBoxB, kBoxA)}) {
    const MapperKeyframe& q = keyframes_.at(query);
    const MapperKeyframe& c = keyframes_.at(place);
    const auto candidates = index.query(q.descriptors, 3, [&](int64_t id) { return id == q.id; });
    ASSERT_FALSE(candidates.empty());
    for (const PlaceCandidate& k : candidates)
      std::printf("query %ld: keyframe %ld, %d votes, score %.1f\n", static_cast<long>(query),
                  static_cast<long>(k.keyframe_id), k.votes, k.score);
    EXPECT_EQ(candidates.front().keyframe_id, c.id) << "query at " << query;

    const PlaceMatch m = verify_place(q, c, keyframes_maker_.calib(), {});
    ASSERT_TRUE(m.ok) << m.message;
    const Eigen::Isometry3d T_c_q = T_w_b_.at(place).inverse() * T_w_b_.at(query);
    const double dt_m = (m.T_c_q.translation() - T_c_q.translation()).norm();
    const double dr_deg =
        Eigen::AngleAxisd(m.T_c_q.linear().transpose() * T_c_q.linear()).angle() * 180.0 / M_PI;
    std::printf("query %ld vs %ld: %s; error %.1f mm, %.2f deg (true motion %.2f m)\n",
                static_cast<long>(query), static_cast<long>(place), m.message.c_str(), dt_m * 1e3,
                dr_deg, T_c_q.translation().norm());
    EXPECT_LT(dt_m, 0.05);
    EXPECT_LT(dr_deg, 2.0);
  }
}

TEST_F(PlaceRealPairs, OppositeSidesOfTheRoomAreRejected) {
  for (int64_t a : {kEarly, kRevisit})
    for (int64_t b : {kBoxA, kBoxB}) {
      for (const auto& [q, c] : {std::pair(a, b), std::pair(b, a)}) {
        const PlaceMatch m =
            verify_place(keyframes_.at(q), keyframes_.at(c), keyframes_maker_.calib(), {});
        EXPECT_FALSE(m.ok) << q << " vs " << c << ": " << m.message;
        std::printf("%ld vs %ld rejected: %s\n", static_cast<long>(q), static_cast<long>(c),
                    m.message.c_str());
      }
    }
}

}  // namespace
}  // namespace hs
