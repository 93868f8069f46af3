// A lost tracker asks the mapper's atlas where it is (issue 7: the global relocalisation of
// Eq. 8 searches the atlas, which lives in the mapper: the tracker's board holds only its
// local map). Request and answer are asynchronous: over LCM the answer comes frames later.
#include "tracker/tracker.h"

namespace hs {

bool Tracker::ask_atlas(const StereoFrame& frame, const ImagePyramid& pyr,
                        const OrbFeatures& features, const NavState& predicted, FrameResult& r) {
  if (!atlas_present_ || options_.atlas_wait_ns <= 0 || loss_bridged(frame.t_ns, predicted))
    return false;
  // Waited long enough since the first request: a new map starts in place.
  if (atlas_asked_since_ns_ >= 0 && frame.t_ns - atlas_asked_since_ns_ > options_.atlas_wait_ns)
    return false;
  if (!atlas_request_) {  // one out at a time: an answer not found lets the next frame ask
    // The frame's stereo points, at the guess, in a map of their own: the tracker's stays.
    auto points = std::make_shared<LocalMap>();
    KeyframeBuildStats stats;
    auto kf = builder_.build(frame, pyr, predicted, {}, &features, *points, &stats);
    if (stats.new_points < options_.reloc_min_inliers) {
      r.message +=
          "; not sent to the atlas: " + std::to_string(stats.new_points) + " stereo points";
    } else {
      AtlasQuery q;
      q.seq = next_atlas_seq_++;
      // One map id offered per loss: the mapper joins it to a world only when it finds the frame.
      if (atlas_asked_since_ns_ < 0) {
        atlas_asked_since_ns_ = frame.t_ns;
        atlas_map_id_ = new_map_id();
      }
      q.next_map_id = atlas_map_id_;
      q.frame = std::move(kf);
      q.points = std::move(points);
      atlas_request_ = AtlasRequest{q.seq, q.next_map_id, predicted.T_w_b()};
      ++counters_.atlas_requests;
      r.message += "; asked the atlas (request " + std::to_string(q.seq) + ")";
      r.atlas_query = std::move(q);
    }
  }
  return atlas_request_.has_value();
}

std::string Tracker::apply(const RelocAnswer& a) {
  const std::string name = "atlas answer " + std::to_string(a.seq);
  if (!atlas_request_ || a.seq != atlas_request_->seq) {
    ++counters_.atlas_answers_ignored;
    return name + " ignored: not the pending request";
  }
  const AtlasRequest request = *atlas_request_;
  atlas_request_.reset();
  if (!a.found) return name + ": " + a.message;
  if (state_ != TrackState::kLost || a.map_id != request.next_map_id) {
    ++counters_.atlas_answers_ignored;
    return name + " ignored: " +
           (state_ != TrackState::kLost ? std::string("tracking resumed meanwhile")
                                        : "map id " + std::to_string(a.map_id) + ", not the " +
                                              std::to_string(request.next_map_id) + " offered");
  }
  atlas_fix_ = AtlasFix{a.T_w_b * request.T_w_b.inverse(), a.map_id, name + ": " + a.message};
  return name + ": found (" + std::to_string(a.inliers) + " inliers), the next frame starts there";
}

}  // namespace hs
