#include "tracker/relocaliser.h"

#include <algorithm>

#include "common/features/descriptor_match.h"
#include "common/geometry/pnp.h"

namespace hs {

double photometric_distance(const cv::Mat& a, const cv::Mat& b) {
  cv::Scalar ma, sa, mb, sb;
  cv::meanStdDev(a, ma, sa);
  cv::meanStdDev(b, mb, sb);
  if (sa[0] < 1e-6 || sb[0] < 1e-6) return 2.0;
  cv::Mat na, nb;
  a.convertTo(na, CV_32F, 1.0 / sa[0], -ma[0] / sa[0]);
  b.convertTo(nb, CV_32F, 1.0 / sb[0], -mb[0] / sb[0]);
  return cv::norm(na, nb, cv::NORM_L2SQR) / static_cast<double>(a.total());
}

RelocResult Relocaliser::against_keyframe(const Keyframe& kf, const OrbFeatures& current,
                                          const NavState& guess, const LocalMap& map) const {
  RelocResult r;
  r.keyframe_id = kf.id;
  // Keyframe keypoints that observe a live map point.
  std::vector<int> rows;
  std::vector<Eigen::Vector3d> p_w;
  const auto positions = map.point_positions(kf);
  for (size_t i = 0; i < positions.size(); ++i) {
    if (!positions[i]) continue;
    rows.push_back(static_cast<int>(i));
    p_w.push_back(*positions[i]);
  }
  if (current.size() == 0) {
    r.message = "no ORB features in the current image";
    return r;
  }
  if (rows.size() < static_cast<size_t>(options_.reloc_min_inliers)) {
    r.message = "keyframe " + std::to_string(kf.id) + " has too few map points";
    return r;
  }
  cv::Mat kf_desc(static_cast<int>(rows.size()), 32, CV_8U);
  for (size_t k = 0; k < rows.size(); ++k)
    kf.features.descriptors.row(rows[k]).copyTo(kf_desc.row(static_cast<int>(k)));
  const auto pairs = match_mutual(current.descriptors, kf_desc, options_.matching);
  if (pairs.size() < static_cast<size_t>(options_.reloc_min_inliers)) {
    r.message =
        std::to_string(pairs.size()) + " descriptor matches with keyframe " + std::to_string(kf.id);
    return r;
  }

  const PinholeRadtan& cam = options_.calib.cam0.intrinsics;
  std::vector<Eigen::Vector3d> obj;
  std::vector<Eigen::Vector2d> img;
  for (const auto& [q, t] : pairs) {
    obj.push_back(p_w[t]);
    img.push_back(cam.unproject_normalised(current.uv(q)));
  }
  PnpOptions pnp;
  pnp.threshold = 3.0 / cam.fx;
  const PnpResult solved = solve_pnp_ransac(obj, img, pnp);
  if (!solved.ok || solved.inliers.size() < static_cast<size_t>(options_.reloc_min_inliers)) {
    r.message = "PnP found " + std::to_string(solved.inliers.size()) + " inliers";
    return r;
  }
  const Eigen::Isometry3d T_w_b = solved.T_c_a.inverse() * options_.calib.cam0.T_b_c.inverse();

  NavState start = guess;
  start.set_T_w_b(T_w_b);
  std::vector<PoseObservation> obs;
  std::vector<int64_t> ids;
  for (const auto& [q, t] : pairs) {
    PoseObservation o;
    o.p_w = p_w[t];
    o.uv = current.uv(q);
    o.sigma_px = level_sigma_px(current.keypoints[q].octave, options_.orb.scale_factor);
    obs.push_back(o);
    ids.push_back(kf.point_ids[rows[t]]);
  }
  const PoseOptResult opt = optimizer_.optimise_pose(start, obs);
  if (!opt.valid() || opt.num_inliers < options_.reloc_min_inliers) {
    r.message =
        std::string("pose refinement: ") + (opt.reason.empty() ? "too few inliers" : opt.reason);
    return r;
  }
  r.ok = true;
  r.nav = opt.state;
  r.inliers = opt.num_inliers;
  for (size_t k = 0; k < obs.size(); ++k)
    if (opt.inliers[k]) r.tracked.push_back({ids[k], obs[k].uv});
  r.message = "relocalised against keyframe " + std::to_string(kf.id) + " with " +
              std::to_string(r.inliers) + " inliers";
  return r;
}

RelocResult Relocaliser::global(const cv::Mat& thumbnail, const OrbFeatures& current,
                                const NavState& guess, const LocalMap& map, int candidates) const {
  std::vector<std::pair<double, const Keyframe*>> ranked;
  for (const auto* list : {&map.window(), &map.database()})
    for (const auto& kf : *list)
      if (kf->thumbnail.size() == thumbnail.size())
        ranked.emplace_back(photometric_distance(thumbnail, kf->thumbnail), kf.get());
  std::sort(ranked.begin(), ranked.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  RelocResult last;
  last.message = "no keyframe to relocalise against";
  for (int i = 0; i < std::min<int>(candidates, static_cast<int>(ranked.size())); ++i) {
    RelocResult r = against_keyframe(*ranked[i].second, current, guess, map);
    if (r.ok) return r;
    last = r;
  }
  return last;
}

}  // namespace hs
