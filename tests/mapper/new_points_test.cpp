#include "mapper/new_points.h"

#include <gtest/gtest.h>

#include <map>
#include <optional>
#include <random>

#include "tests/mapper/keyframe_test_util.h"

namespace hs {
namespace {

// Two keyframes 1 m apart (test::keyframe_msg poses: ids 0 and 10) sharing tracker points 1-3,
// and free keypoints (no point) where scene points project, each point's descriptor the same
// in both.
class NewPointScene : public ::testing::Test {
 protected:
  void SetUp() override {
    a_ = test::keyframe(0, -1, {1, 2, 3});
    b_ = test::keyframe(10, 0, {1, 2, 3});
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> x(-1.5, 1.5), y(-1.0, 1.0), z(3.0, 8.0);
    for (int k = 0; k < 40; ++k) {
      const Eigen::Vector3d p_c(x(rng), y(rng), z(rng));
      const Eigen::Vector3d p_w = a_.state.T_w_b() * calib_.cam0.T_b_c * p_c;
      if (!pixel(a_, p_w) || !pixel(b_, p_w)) continue;
      const int64_t d = next_++;
      see(a_, p_w, 0, 0, d);
      see(b_, p_w, 0, 0, d);
      good_[d] = p_w;
    }
  }

  // Where p_w projects in kf, if in view.
  std::optional<Eigen::Vector2d> pixel(const MapperKeyframe& kf, const Eigen::Vector3d& p_w) const {
    const Eigen::Isometry3d T_c_w = (kf.state.T_w_b() * calib_.cam0.T_b_c).inverse();
    Eigen::Vector2d uv;
    if (!calib_.cam0.intrinsics.project(T_c_w * p_w, &uv)) return std::nullopt;
    return uv;
  }
  // A keypoint of kf where p_w projects (shifted by du pixels) with descriptor d; false when it
  // is out of view.
  bool see(MapperKeyframe& kf, const Eigen::Vector3d& p_w, double du, int octave, int64_t d) {
    const std::optional<Eigen::Vector2d> uv = pixel(kf, p_w);
    if (!uv) return false;
    MapperKeypoint kp;
    kp.u = static_cast<float>(uv->x() + du);
    kp.v = static_cast<float>(uv->y());
    kp.octave = octave;
    kf.keypoints.push_back(kp);
    const std::vector<uint8_t> bytes = test::point_descriptor(d);
    std::copy(bytes.begin(), bytes.end(), kf.descriptors.emplace_back().begin());
    return true;
  }

  std::vector<NewPoint> run(const NewPointOptions& options = on()) {
    graph_.insert(a_);
    graph_.insert(b_);
    return triangulate_new_points(graph_, 10, calib_, options);
  }
  static NewPointOptions on() {
    NewPointOptions o;
    o.covisible_keyframes = 10;
    return o;
  }

  StereoCalib calib_ = euroc_stereo_calib();
  MapperKeyframe a_, b_;
  KeyframeGraph graph_;
  int64_t next_ = 5000;
  std::map<int64_t, Eigen::Vector3d> good_;  // descriptor id -> point
};

TEST_F(NewPointScene, MatchesAlongTheEpipolarLineAndPlacesThePoints) {
  ASSERT_GE(good_.size(), 15u);
  const std::vector<NewPoint> made = run();
  ASSERT_EQ(made.size(), good_.size());
  for (const NewPoint& p : made) {
    EXPECT_EQ(p.a.keyframe_id, 10);
    EXPECT_EQ(p.b.keyframe_id, 0);
    const MapperKeyframe& a = *graph_.keyframe(10);
    const MapperKeyframe& b = *graph_.keyframe(0);
    // Same descriptor: the same scene point.
    EXPECT_EQ(a.descriptors[static_cast<size_t>(p.a.keypoint)],
              b.descriptors[static_cast<size_t>(p.b.keypoint)]);
    EXPECT_EQ(a.keypoints[static_cast<size_t>(p.a.keypoint)].point_id, -1);
  }
  double worst = 0;
  for (const NewPoint& p : made) {
    double nearest = 1e9;
    for (const auto& [id, p_w] : good_) nearest = std::min(nearest, (p.p_w - p_w).norm());
    worst = std::max(worst, nearest);
  }
  EXPECT_LT(worst, 1e-3) << "float pixels: sub-millimetre at 3-8 m";
}

TEST_F(NewPointScene, RefusesWhatTheGeometryOrTheDescriptorsDoNotSupport) {
  const size_t good = good_.size();
  const Eigen::Isometry3d T_w_c = a_.state.T_w_b() * calib_.cam0.T_b_c;
  // Off the epipolar line (vertical: the camera moves along its -y): 15 px right.
  const int64_t off_line = next_++;
  ASSERT_TRUE(see(a_, T_w_c * Eigen::Vector3d(0.2, 0.1, 5.0), 0, 0, off_line));
  ASSERT_TRUE(see(b_, T_w_c * Eigen::Vector3d(0.2, 0.1, 5.0), 15, 0, off_line));
  // Too little parallax: 1 km away, 1 m of baseline.
  const int64_t far = next_++;
  ASSERT_TRUE(see(a_, T_w_c * Eigen::Vector3d(10.0, 5.0, 1000.0), 0, 0, far));
  ASSERT_TRUE(see(b_, T_w_c * Eigen::Vector3d(10.0, 5.0, 1000.0), 0, 0, far));
  // Ambiguous: two keypoints of the older keyframe on the new one's epipolar line, with the
  // same descriptor (two points on one ray of the new keyframe).
  const int64_t twice = next_++;
  const Eigen::Isometry3d T_w_c_new = b_.state.T_w_b() * calib_.cam0.T_b_c;
  const Eigen::Vector3d ray(-0.075, -0.05, 1.0);
  ASSERT_TRUE(see(b_, T_w_c_new * (4.0 * ray), 0, 0, twice));
  ASSERT_TRUE(see(a_, T_w_c_new * (4.0 * ray), 0, 0, twice));
  ASSERT_TRUE(see(a_, T_w_c_new * (6.0 * ray), 0, 0, twice));
  // Pyramid levels that disagree with the distances (octave 0 and 5: 2.5x, the point as far
  // from both cameras).
  const int64_t scales = next_++;
  ASSERT_TRUE(see(a_, T_w_c * Eigen::Vector3d(0.5, -0.3, 4.5), 0, 0, scales));
  ASSERT_TRUE(see(b_, T_w_c * Eigen::Vector3d(0.5, -0.3, 4.5), 0, 5, scales));
  EXPECT_EQ(run().size(), good);
}

TEST_F(NewPointScene, KeypointsThatSeeAPointAreLeftAlone) {
  ASSERT_GE(good_.size(), 15u);
  EXPECT_TRUE(run(NewPointOptions{}).empty()) << "off by default";
  // Once added, the same keypoints are no longer free.
  for (const NewPoint& p : triangulate_new_points(graph_, 10, calib_, on()))
    graph_.add_point(p.p_w, {p.a, p.b});
  EXPECT_TRUE(triangulate_new_points(graph_, 10, calib_, on()).empty());
  EXPECT_EQ(graph_.shared_points(0, 10), 3 + static_cast<int>(good_.size()));
}

}  // namespace
}  // namespace hs
