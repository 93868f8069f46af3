#include "mapper/place_verify.h"

#include <ceres/ceres.h>

#include <cmath>
#include <memory>

#include "common/features/descriptor_match.h"
#include "common/geometry/pnp.h"
#include "mapper/pose_manifold.h"
#include "mapper/reprojection_cost.h"

namespace hs {
namespace {

cv::Mat descriptor_rows(const std::vector<Descriptor>& all, const std::vector<int>& rows) {
  cv::Mat m(static_cast<int>(rows.size()), 32, CV_8U);
  for (size_t k = 0; k < rows.size(); ++k)
    std::memcpy(m.ptr<uint8_t>(static_cast<int>(k)), all[static_cast<size_t>(rows[k])].data(), 32);
  return m;
}

// One matched point seen by the two keyframes: its cam0 (and cam1 when stereo) pixels in each.
struct Track {
  int q = -1, c = -1;                             // keypoint indices
  Eigen::Vector3d p_c = Eigen::Vector3d::Zero();  // in the candidate's body frame
};

class PairAdjustment {
 public:
  PairAdjustment(const MapperKeyframe& query, const MapperKeyframe& candidate,
                 const StereoCalib& calib, const PlaceVerifyOptions& options)
      : query_(query),
        candidate_(candidate),
        options_(options),
        cams_{RigCamera(calib.cam0), RigCamera(calib.cam1)} {}

  // Refines T_c_q (and the tracks' points) over `tracks`; returns per track whether every
  // observation passes the chi2 test.
  std::vector<bool> run(std::vector<Track>& tracks, Eigen::Isometry3d& T_c_q) const {
    double identity[kPoseSize] = {0, 0, 0, 1, 0, 0, 0};
    double pose[kPoseSize];
    const Eigen::Quaterniond q(T_c_q.linear());
    std::copy(q.coeffs().data(), q.coeffs().data() + 4, pose);
    std::copy(T_c_q.translation().data(), T_c_q.translation().data() + 3, pose + 4);
    ceres::Problem::Options po;
    po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(po);
    PoseManifold manifold;
    ceres::HuberLoss huber(std::sqrt(options_.chi2));
    problem.AddParameterBlock(identity, kPoseSize, &manifold);
    problem.SetParameterBlockConstant(identity);
    problem.AddParameterBlock(pose, kPoseSize, &manifold);
    std::vector<std::unique_ptr<ReprojectionCost>> costs;
    std::vector<std::vector<const ReprojectionCost*>> of_track(tracks.size());
    for (size_t k = 0; k < tracks.size(); ++k) {
      for (const auto& [kf, index, block] : {std::tuple(&candidate_, tracks[k].c, identity),
                                             std::tuple(&query_, tracks[k].q, pose)}) {
        const MapperKeypoint& kp = kf->keypoints[static_cast<size_t>(index)];
        const double sigma = options_.pixel_sigma * std::pow(options_.octave_scale, kp.octave);
        const Eigen::Vector2d uv[2] = {{kp.u, kp.v}, {kp.u_right, kp.v_right}};
        for (int cam = 0; cam < (kp.u_right >= 0 ? 2 : 1); ++cam) {
          costs.push_back(
              std::make_unique<ReprojectionCost>(cams_[cam], uv[cam], sigma, options_.min_depth_m));
          problem.AddResidualBlock(costs.back().get(), &huber, block, tracks[k].p_c.data());
          of_track[k].push_back(costs.back().get());
        }
      }
    }
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::DENSE_SCHUR;
    so.max_num_iterations = 20;
    so.num_threads = 1;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    T_c_q = Eigen::Isometry3d::Identity();
    T_c_q.linear() = pose_q_w_b(pose).toRotationMatrix();
    T_c_q.translation() = pose_p_w_b(pose);

    std::vector<bool> good(tracks.size(), true);
    for (size_t k = 0; k < tracks.size(); ++k) {
      for (size_t o = 0; o < of_track[k].size(); ++o) {
        const double* blocks[2] = {observation_is_candidate(tracks[k], o) ? identity : pose,
                                   tracks[k].p_c.data()};
        Eigen::Vector2d r;
        if (!of_track[k][o]->Evaluate(blocks, r.data(), nullptr) ||
            !(r.squaredNorm() <= options_.chi2))
          good[k] = false;
      }
    }
    return good;
  }

 private:
  // Observations were added candidate first (cam0, then cam1 if stereo), then query.
  bool observation_is_candidate(const Track& t, size_t o) const {
    const size_t in_candidate = candidate_.keypoints[static_cast<size_t>(t.c)].u_right >= 0 ? 2 : 1;
    return o < in_candidate;
  }

  const MapperKeyframe& query_;
  const MapperKeyframe& candidate_;
  const PlaceVerifyOptions& options_;
  RigCamera cams_[2];
};

}  // namespace

PlaceMatch verify_place(const MapperKeyframe& query, const MapperKeyframe& candidate,
                        const StereoCalib& calib, const PlaceVerifyOptions& options) {
  PlaceMatch m;
  std::vector<int> stereo_rows;  // candidate keypoints with a stereo depth
  for (size_t i = 0; i < candidate.keypoints.size(); ++i)
    if (candidate.keypoints[i].depth > 0) stereo_rows.push_back(static_cast<int>(i));
  if (stereo_rows.size() < static_cast<size_t>(options.min_inliers) || query.descriptors.empty()) {
    m.message = "keyframe " + std::to_string(candidate.id) + " has " +
                std::to_string(stereo_rows.size()) + " stereo points";
    return m;
  }
  const cv::Mat query_desc(static_cast<int>(query.descriptors.size()), 32, CV_8U,
                           const_cast<uint8_t*>(query.descriptors.front().data()));
  DescriptorMatchOptions match;
  match.max_distance = options.max_hamming;
  match.ratio = static_cast<float>(options.ratio);
  const auto pairs =
      match_mutual(query_desc, descriptor_rows(candidate.descriptors, stereo_rows), match);
  m.matches = static_cast<int>(pairs.size());
  if (m.matches < options.min_inliers) {
    m.message = std::to_string(m.matches) + " descriptor matches";
    return m;
  }

  const PinholeRadtan& K = calib.cam0.intrinsics;
  std::vector<Track> tracks;
  std::vector<Eigen::Vector3d> p_c;
  std::vector<Eigen::Vector2d> xy_q;
  for (const auto& [q, r] : pairs) {
    Track t{q, stereo_rows[static_cast<size_t>(r)], {}};
    const MapperKeypoint& kc = candidate.keypoints[static_cast<size_t>(t.c)];
    const MapperKeypoint& kq = query.keypoints[static_cast<size_t>(q)];
    t.p_c = calib.cam0.T_b_c * (kc.depth * K.unproject_normalised({kc.u, kc.v}).homogeneous());
    p_c.push_back(t.p_c);
    xy_q.push_back(K.unproject_normalised({kq.u, kq.v}));
    tracks.push_back(t);
  }
  PnpOptions pnp;
  pnp.threshold = options.pnp_threshold_px / K.fx;
  pnp.iterations = options.pnp_iterations;
  const PnpResult solved = solve_pnp_ransac(p_c, xy_q, pnp);
  m.pnp_inliers = static_cast<int>(solved.inliers.size());
  if (!solved.ok || m.pnp_inliers < options.min_inliers) {
    m.message = "PnP: " + std::to_string(m.pnp_inliers) + " inliers of " +
                std::to_string(m.matches) + " matches";
    return m;
  }
  // solved.T_c_a maps candidate-body points into the query's cam0.
  Eigen::Isometry3d T_c_q = (calib.cam0.T_b_c * solved.T_c_a).inverse();
  std::vector<Track> kept;
  for (int i : solved.inliers) kept.push_back(tracks[static_cast<size_t>(i)]);
  const PairAdjustment adjust(query, candidate, calib, options);
  std::vector<bool> good = adjust.run(kept, T_c_q);
  std::vector<Track> second;
  for (size_t k = 0; k < kept.size(); ++k)
    if (good[k]) second.push_back(kept[k]);
  if (second.size() < static_cast<size_t>(options.min_inliers)) {
    m.message = "refinement: " + std::to_string(second.size()) + " consistent matches";
    return m;
  }
  good = adjust.run(second, T_c_q);
  for (size_t k = 0; k < second.size(); ++k)
    if (good[k]) m.inlier_keypoints.emplace_back(second[k].q, second[k].c);
  m.inliers = static_cast<int>(m.inlier_keypoints.size());
  m.T_c_q = T_c_q;
  m.ok = m.inliers >= options.min_inliers;
  m.message = std::to_string(m.inliers) + " inliers of " + std::to_string(m.matches) +
              " matches with keyframe " + std::to_string(candidate.id);
  return m;
}

}  // namespace hs
