#pragma once
// Mapper keyframes made from stereo images the way hs-tracker makes them: ORB and stereo points by
// the tracker's KeyframeBuilder, sent through the KEYFRAME message and read back by the mapper.
#include <memory>
#include <string>

#include "mapper/keyframe_from_msg.h"
#include "tracker/keyframe_builder.h"
#include "tracker/node/node_messages.h"

namespace hs::test {

class StereoKeyframes {
 public:
  explicit StereoKeyframes(const TrackerOptions& options = {})
      : options_(options), builder_(options_), map_(options_.local_map) {}

  MapperKeyframe make(int64_t t_ns, const cv::Mat& cam0, const cv::Mat& cam1) {
    StereoFrame frame{t_ns, ++seq_, cam0, cam1};
    NavState nav;
    nav.t_ns = t_ns;
    const std::shared_ptr<Keyframe> kf = builder_.build(
        frame, build_pyramid(cam0, options_.pyramid_levels), nav, {}, nullptr, map_, nullptr);
    return keyframe_from_msg(keyframe_msg(*kf, map_, 0), "test");
  }
  const StereoCalib& calib() const { return options_.calib; }

 private:
  TrackerOptions options_;
  KeyframeBuilder builder_;
  LocalMap map_;
  int64_t seq_ = 0;
};

}  // namespace hs::test
