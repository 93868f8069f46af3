#include "common/geometry/pnp.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <stdexcept>

namespace hs {

PnpResult solve_pnp_ransac(const std::vector<Eigen::Vector3d>& p_a,
                           const std::vector<Eigen::Vector2d>& xy_c, const PnpOptions& options) {
  if (p_a.size() != xy_c.size())
    throw std::invalid_argument("solve_pnp_ransac: point and pixel counts differ");
  PnpResult r;
  if (p_a.size() < 4) return r;
  std::vector<cv::Point3f> obj;
  std::vector<cv::Point2f> img;
  for (size_t i = 0; i < p_a.size(); ++i) {
    obj.emplace_back(static_cast<float>(p_a[i].x()), static_cast<float>(p_a[i].y()),
                     static_cast<float>(p_a[i].z()));
    img.emplace_back(static_cast<float>(xy_c[i].x()), static_cast<float>(xy_c[i].y()));
  }
  cv::Mat rvec, tvec;
  if (!cv::solvePnPRansac(obj, img, cv::Mat::eye(3, 3, CV_64F), cv::Mat(), rvec, tvec, false,
                          options.iterations, static_cast<float>(options.threshold),
                          options.confidence, r.inliers, cv::SOLVEPNP_EPNP))
    return r;
  cv::Mat R_cv;
  cv::Rodrigues(rvec, R_cv);
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  cv::cv2eigen(R_cv, R);
  cv::cv2eigen(tvec, t);
  r.T_c_a.linear() = R;
  r.T_c_a.translation() = t;
  r.ok = true;
  return r;
}

}  // namespace hs
