#pragma once
// Uniform quintic B-splines: C4-smooth curves with exact derivatives up to third order, so the
// simulated IMU (which needs acceleration, and jerk for acceleration-dependent tilt) is exact.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace hs::sim {

template <int Dim>
struct SplinePoint {
  using Vec = Eigen::Matrix<double, Dim, 1>;
  Vec value = Vec::Zero();
  Vec d1 = Vec::Zero();  // first derivative w.r.t. the spline parameter
  Vec d2 = Vec::Zero();
  Vec d3 = Vec::Zero();
};

// Quintic B-spline over uniformly spaced knots (spacing `knot`). Closed splines wrap their control
// points (period = n * knot). Open splines repeat the end points so the curve starts and ends at
// rest exactly at the first and last control point, and is clamped to them outside its range.
template <int Dim>
class QuinticSpline {
 public:
  using Vec = Eigen::Matrix<double, Dim, 1>;

  QuinticSpline(std::vector<Vec> control, double knot, bool closed) : knot_(knot), closed_(closed) {
    if (control.empty() || !(knot > 0.0)) throw std::invalid_argument("QuinticSpline: bad input");
    if (closed) {
      if (control.size() < 6)
        throw std::invalid_argument("QuinticSpline: closed needs >= 6 points");
      control_ = std::move(control);
      segments_ = control_.size();
    } else {
      control_.assign(kPad, control.front());
      control_.insert(control_.end(), control.begin(), control.end());
      control_.insert(control_.end(), kPad, control.back());
      segments_ = control_.size() - 5;
    }
  }

  // Parameter range: [0, length()] (one period for closed splines).
  double length() const { return static_cast<double>(segments_) * knot_; }

  SplinePoint<Dim> at(double s) const {
    double x = s / knot_;
    if (closed_) {
      x = std::fmod(x, static_cast<double>(segments_));
      if (x < 0.0) x += static_cast<double>(segments_);
    } else {
      x = std::clamp(x, 0.0, static_cast<double>(segments_));
    }
    size_t seg = std::min(static_cast<size_t>(x), segments_ - 1);
    const double u = x - static_cast<double>(seg);
    // Powers of u and their derivatives: row k of `pow` holds d^k/du^k [1 u u^2 u^3 u^4 u^5].
    const double u2 = u * u, u3 = u2 * u, u4 = u3 * u, u5 = u4 * u;
    Eigen::Matrix<double, 4, 6> pow;
    pow << 1, u, u2, u3, u4, u5,              //
        0, 1, 2 * u, 3 * u2, 4 * u3, 5 * u4,  //
        0, 0, 2, 6 * u, 12 * u2, 20 * u3,     //
        0, 0, 0, 6, 24 * u, 60 * u2;
    const Eigen::Matrix<double, 4, 6> w = pow * basis();
    SplinePoint<Dim> out;
    for (int k = 0; k < 6; ++k) {
      const Vec& c = control_[(seg + static_cast<size_t>(k)) % control_.size()];
      out.value += w(0, k) * c;
      out.d1 += w(1, k) * c;
      out.d2 += w(2, k) * c;
      out.d3 += w(3, k) * c;
    }
    const double inv = 1.0 / knot_;
    out.d1 *= inv;
    out.d2 *= inv * inv;
    out.d3 *= inv * inv * inv;
    return out;
  }

 private:
  static constexpr size_t kPad = 4;  // degree - 1 repeats: zero derivatives up to 4th order

  // Power-basis matrix of the uniform quintic B-spline: curve(u) = [1 u .. u^5] * M * P.
  static const Eigen::Matrix<double, 6, 6>& basis() {
    static const Eigen::Matrix<double, 6, 6> m = [] {
      Eigen::Matrix<double, 6, 6> b;
      b << 1, 26, 66, 26, 1, 0,    //
          -5, -50, 0, 50, 5, 0,    //
          10, 20, -60, 20, 10, 0,  //
          -10, 20, 0, -20, 10, 0,  //
          5, -20, 30, -20, 5, 0,   //
          -1, 5, -10, 10, -5, 1;
      return Eigen::Matrix<double, 6, 6>(b / 120.0);
    }();
    return m;
  }

  double knot_;
  bool closed_;
  std::vector<Vec> control_;
  size_t segments_ = 0;
};

}  // namespace hs::sim
