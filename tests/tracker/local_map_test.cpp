#include "tracker/local_map.h"

#include <gtest/gtest.h>

namespace hs {
namespace {

std::shared_ptr<Keyframe> keyframe_observing(LocalMap& map, std::vector<int64_t> ids) {
  auto kf = std::make_shared<Keyframe>();
  kf->id = map.new_keyframe_id();
  kf->pyramid = build_pyramid(cv::Mat(32, 32, CV_8UC1, cv::Scalar(7)), 3);
  kf->thumbnail = kf->pyramid.levels.back();
  kf->point_ids = std::move(ids);
  return kf;
}

TEST(LocalMap, WindowIsBoundedAndUnreferencedPointsLeave) {
  LocalMapOptions o;
  o.max_keyframes = 2;
  o.max_database_keyframes = 2;
  LocalMap map(o);
  for (int i = 0; i < 4; ++i) {
    MapPoint p;
    p.id = map.new_point_id();
    map.add_point(p);
  }
  map.add_keyframe(keyframe_observing(map, {0, 1}));
  map.add_keyframe(keyframe_observing(map, {1, 2}));
  EXPECT_EQ(map.points().size(), 4u);  // nothing left the window yet
  map.add_keyframe(keyframe_observing(map, {2, 3, -1}));
  EXPECT_EQ(map.window().size(), 2u);
  ASSERT_EQ(map.database().size(), 1u);
  EXPECT_TRUE(map.database().front()->pyramid.levels.empty());
  EXPECT_FALSE(map.database().front()->thumbnail.empty());
  EXPECT_EQ(map.point(0), nullptr);  // only the departed keyframe saw it
  EXPECT_NE(map.point(1), nullptr);
  EXPECT_NE(map.keyframe(0), nullptr);  // still findable in the database
  map.add_keyframe(keyframe_observing(map, {}));
  map.add_keyframe(keyframe_observing(map, {}));
  EXPECT_EQ(map.database().size(), 2u);
  EXPECT_EQ(map.keyframe(0), nullptr);
  EXPECT_TRUE(map.points().empty());
}

}  // namespace
}  // namespace hs
