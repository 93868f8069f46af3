#pragma once
// Two-view reconstruction for the monocular map start (paper Sec. 3.1.1, Eq. 1-4): from matched
// normalised image coordinates of two frames, the relative pose (translation up to scale) and
// the triangulated points. Two models are fitted by RANSAC on the same matches, the essential
// matrix (a general scene; in normalised coordinates the paper's E = K^T F K is F itself) and a
// homography (a planar scene, or little translation), and the one that explains the matches
// better is decomposed. Of the candidate motions the physically valid one is chosen by
// cheirality: the most points in front of both cameras with enough parallax, clearly more than
// any other candidate. A degenerate pair (too little parallax, too few matches, an ambiguous
// choice) is refused with the reason, never guessed.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace hs {

struct TwoViewOptions {
  // Inlier threshold in normalised units (1 px noise at fx 460: sigma 1/460); the tests below
  // are chi2 at 95%, as ORB-SLAM's model scoring: 1 DoF for the epipolar line, 2 for a transfer.
  double sigma = 1.0 / 460.0;
  int ransac_iterations = 200;
  int min_matches = 50;
  // A model is taken when its share of the two scores is above this (homography: ORB-SLAM's
  // 0.45, a homography fits a general scene's matches near the epipoles too).
  double homography_score_ratio = 0.45;
  double min_parallax_rad = 1.0 * M_PI / 180.0;  // median over the triangulated points
  int min_triangulated = 50;
  double min_triangulated_share = 0.9;  // of the model's inliers
  // The best motion candidate must have this much more good points than the second best.
  double ambiguity_ratio = 0.7;
};

struct TwoViewResult {
  bool ok = false;
  std::string reason;  // why it failed, e.g. "not enough parallax"
  bool homography = false;
  double homography_score_share = 0.0;                      // S_H / (S_H + S_E)
  Eigen::Isometry3d T_a_b = Eigen::Isometry3d::Identity();  // |t| = 1 (scale unknown)
  std::vector<int> inliers;                                 // matches of the chosen model
  std::vector<Eigen::Vector3d> p_a;  // triangulated, in frame a, per entry of `triangulated`
  std::vector<int> triangulated;     // match indices with a valid point
  double median_parallax_rad = 0.0;
};

// xy_a[i] and xy_b[i] (x/z, y/z) are one match seen in frames a and b.
TwoViewResult reconstruct_two_view(const std::vector<Eigen::Vector2d>& xy_a,
                                   const std::vector<Eigen::Vector2d>& xy_b,
                                   const TwoViewOptions& options = {});

// The four motions an essential matrix (b -> a: x_a^T E x_b = 0) allows: (R, t) and (R, -t)
// for the two rotations of its SVD; T_a_b with |t| = 1.
std::vector<Eigen::Isometry3d> decompose_essential(const Eigen::Matrix3d& E_a_b);

}  // namespace hs
