#include "common/geometry/two_view.h"

#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <stdexcept>

#include "common/geometry/triangulation.h"

namespace hs {
namespace {

constexpr double kChi2OneDof = 3.841;  // 95%
constexpr double kChi2TwoDof = 5.991;

std::vector<cv::Point2d> to_cv(const std::vector<Eigen::Vector2d>& xy) {
  std::vector<cv::Point2d> out;
  out.reserve(xy.size());
  for (const Eigen::Vector2d& p : xy) out.emplace_back(p.x(), p.y());
  return out;
}

Eigen::Vector3d homogeneous(const Eigen::Vector2d& xy) {
  return Eigen::Vector3d(xy.x(), xy.y(), 1.0);
}

// Squared distance of x to the line l (homogeneous), over sigma^2.
double line_chi2(const Eigen::Vector3d& l, const Eigen::Vector2d& x, double sigma) {
  const double d = l.dot(homogeneous(x));
  return d * d / (l.head<2>().squaredNorm() * sigma * sigma);
}

// Squared transfer error of x_from mapped by H against x_to, over sigma^2 (infinite when H
// maps it to infinity).
double transfer_chi2(const Eigen::Matrix3d& H, const Eigen::Vector2d& x_from,
                     const Eigen::Vector2d& x_to, double sigma) {
  const Eigen::Vector3d m = H * homogeneous(x_from);
  if (std::abs(m.z()) < 1e-12) return std::numeric_limits<double>::infinity();
  return (m.hnormalized() - x_to).squaredNorm() / (sigma * sigma);
}

// ORB-SLAM's model score: each direction of each match adds (5.991 - chi2) when below its test
// (the same 5.991 in both models makes the scores comparable); inliers pass both directions.
struct ModelScore {
  double score = 0.0;
  std::vector<int> inliers;
};

// `chi2(i)`: match i's two directions.
template <typename Chi2>
ModelScore score_model(size_t n, double inlier_chi2, const Chi2& chi2) {
  ModelScore s;
  for (size_t i = 0; i < n; ++i) {
    bool inlier = true;
    for (double c : chi2(i)) {
      if (c < inlier_chi2)
        s.score += kChi2TwoDof - c;
      else
        inlier = false;
    }
    if (inlier) s.inliers.push_back(static_cast<int>(i));
  }
  return s;
}

ModelScore score_essential(const Eigen::Matrix3d& E, const std::vector<Eigen::Vector2d>& xy_a,
                           const std::vector<Eigen::Vector2d>& xy_b, double sigma) {
  return score_model(xy_a.size(), kChi2OneDof, [&](size_t i) {
    return std::array<double, 2>{line_chi2(E * homogeneous(xy_b[i]), xy_a[i], sigma),
                                 line_chi2(E.transpose() * homogeneous(xy_a[i]), xy_b[i], sigma)};
  });
}

ModelScore score_homography(const Eigen::Matrix3d& H, const std::vector<Eigen::Vector2d>& xy_a,
                            const std::vector<Eigen::Vector2d>& xy_b, double sigma) {
  const Eigen::Matrix3d H_inv = H.inverse();
  return score_model(xy_a.size(), kChi2TwoDof, [&](size_t i) {
    return std::array<double, 2>{transfer_chi2(H, xy_b[i], xy_a[i], sigma),
                                 transfer_chi2(H_inv, xy_a[i], xy_b[i], sigma)};
  });
}

struct Candidate {
  Eigen::Isometry3d T_a_b;
  std::vector<int> good;  // match indices triangulated in front of both, reprojecting well
  std::vector<Eigen::Vector3d> p_a;
  std::vector<double> parallax;
};

Candidate check_cheirality(const Eigen::Isometry3d& T_a_b, const std::vector<int>& inliers,
                           const std::vector<Eigen::Vector2d>& xy_a,
                           const std::vector<Eigen::Vector2d>& xy_b, double sigma) {
  Candidate c{T_a_b, {}, {}, {}};
  const Eigen::Isometry3d T_b_a = T_a_b.inverse();
  const double max_sq = 4.0 * kChi2TwoDof * sigma * sigma;  // reprojection, each view
  for (int i : inliers) {
    const std::optional<Eigen::Vector3d> p_a = triangulate_two_view(xy_a[i], xy_b[i], T_a_b);
    if (!p_a) continue;
    const Eigen::Vector3d p_b = T_b_a * *p_a;
    if (p_a->z() <= 0 || p_b.z() <= 0) continue;
    if ((p_a->hnormalized() - xy_a[i]).squaredNorm() > max_sq ||
        (p_b.hnormalized() - xy_b[i]).squaredNorm() > max_sq)
      continue;
    c.good.push_back(i);
    c.p_a.push_back(*p_a);
    c.parallax.push_back(parallax_angle(*p_a, T_a_b));
  }
  return c;
}

std::vector<Eigen::Isometry3d> decompose_homography(const Eigen::Matrix3d& H_a_b) {
  cv::Mat H;
  cv::eigen2cv(H_a_b, H);
  std::vector<cv::Mat> rotations, translations, normals;
  cv::decomposeHomographyMat(H, cv::Mat::eye(3, 3, CV_64F), rotations, translations, normals);
  std::vector<Eigen::Isometry3d> out;
  for (size_t k = 0; k < rotations.size(); ++k) {
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    cv::cv2eigen(rotations[k], R);
    cv::cv2eigen(translations[k], t);
    if (t.norm() < 1e-12) continue;  // pure rotation: no structure to start from
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = R;
    T.translation() = t.normalized();
    out.push_back(T);
  }
  return out;
}

}  // namespace

std::vector<Eigen::Isometry3d> decompose_essential(const Eigen::Matrix3d& E_a_b) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(E_a_b, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU();
  Eigen::Matrix3d V = svd.matrixV();
  // E is defined up to sign: proper rotations for both factors.
  if (U.determinant() < 0) U = -U;
  if (V.determinant() < 0) V = -V;
  Eigen::Matrix3d W;
  W << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  const Eigen::Vector3d t = U.col(2);
  std::vector<Eigen::Isometry3d> out;
  for (const Eigen::Matrix3d& R :
       {Eigen::Matrix3d(U * W * V.transpose()), Eigen::Matrix3d(U * W.transpose() * V.transpose())})
    for (double sign : {1.0, -1.0}) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.linear() = R;
      T.translation() = sign * t;
      out.push_back(T);
    }
  return out;
}

TwoViewResult reconstruct_two_view(const std::vector<Eigen::Vector2d>& xy_a,
                                   const std::vector<Eigen::Vector2d>& xy_b,
                                   const TwoViewOptions& options) {
  if (xy_a.size() != xy_b.size())
    throw std::invalid_argument("reconstruct_two_view: the two frames' match counts differ");
  TwoViewResult r;
  if (static_cast<int>(xy_a.size()) < std::max(options.min_matches, 8)) {
    r.reason = "too few matches (" + std::to_string(xy_a.size()) + ", need " +
               std::to_string(options.min_matches) + ")";
    return r;
  }
  const std::vector<cv::Point2d> a = to_cv(xy_a), b = to_cv(xy_b);
  // OpenCV's conventions: findEssentialMat(p1, p2) gives p2^T E p1 = 0, findHomography(src,
  // dst) dst ~ H src; frame b first gives x_a^T E x_b = 0 and x_a ~ H x_b.
  const cv::Mat E_cv = cv::findEssentialMat(b, a, 1.0, cv::Point2d(0, 0), cv::USAC_ACCURATE, 0.999,
                                            std::sqrt(kChi2OneDof) * options.sigma);
  const cv::Mat H_cv =
      cv::findHomography(b, a, cv::USAC_ACCURATE, std::sqrt(kChi2TwoDof) * options.sigma,
                         cv::noArray(), options.ransac_iterations);
  ModelScore e_score, h_score;
  Eigen::Matrix3d E = Eigen::Matrix3d::Zero(), H = Eigen::Matrix3d::Zero();
  // With several solutions OpenCV stacks them (3n x 3): each is scored, the best kept.
  for (int k = 0; k + 3 <= E_cv.rows; k += 3) {
    Eigen::Matrix3d E_k;
    cv::cv2eigen(E_cv.rowRange(k, k + 3), E_k);
    ModelScore s = score_essential(E_k, xy_a, xy_b, options.sigma);
    if (s.score > e_score.score) {
      e_score = std::move(s);
      E = E_k;
    }
  }
  if (!H_cv.empty()) {
    cv::cv2eigen(H_cv, H);
    h_score = score_homography(H, xy_a, xy_b, options.sigma);
  }
  if (e_score.score + h_score.score <= 0.0) {
    r.reason = "no model explains the matches";
    return r;
  }
  r.homography_score_share = h_score.score / (e_score.score + h_score.score);
  r.homography = r.homography_score_share > options.homography_score_ratio;
  r.inliers = r.homography ? h_score.inliers : e_score.inliers;
  const std::vector<Eigen::Isometry3d> motions =
      r.homography ? decompose_homography(H) : decompose_essential(E);

  std::vector<Candidate> candidates;
  for (const Eigen::Isometry3d& T : motions)
    candidates.push_back(check_cheirality(T, r.inliers, xy_a, xy_b, options.sigma));
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& x, const Candidate& y) { return x.good.size() > y.good.size(); });
  const std::string model = r.homography ? "homography" : "essential matrix";
  if (candidates.empty() || candidates[0].good.empty()) {
    r.reason = "no motion of the " + model + " puts the points in front of both cameras";
    return r;
  }
  Candidate& best = candidates[0];
  std::vector<double> parallax = best.parallax;
  std::nth_element(parallax.begin(), parallax.begin() + parallax.size() / 2, parallax.end());
  r.median_parallax_rad = parallax[parallax.size() / 2];
  const size_t n = best.good.size();
  if (r.median_parallax_rad < options.min_parallax_rad) {
    r.reason = "not enough parallax (median " +
               std::to_string(r.median_parallax_rad * 180.0 / M_PI) + " deg)";
    return r;
  }
  if (static_cast<int>(n) < options.min_triangulated ||
      n < options.min_triangulated_share * r.inliers.size()) {
    r.reason = "too few points triangulated (" + std::to_string(n) + " of " +
               std::to_string(r.inliers.size()) + " " + model + " inliers)";
    return r;
  }
  if (candidates.size() > 1 && candidates[1].good.size() > options.ambiguity_ratio * n) {
    r.reason = "ambiguous motion (" + std::to_string(n) + " vs " +
               std::to_string(candidates[1].good.size()) + " points in front)";
    return r;
  }
  r.ok = true;
  r.T_a_b = best.T_a_b;
  r.triangulated = std::move(best.good);
  r.p_a = std::move(best.p_a);
  return r;
}

}  // namespace hs
