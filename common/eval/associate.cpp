#include "common/eval/associate.h"

#include <algorithm>
#include <cstdlib>

#include "common/core/error.h"

namespace hs {
namespace {

// Index of the pose in `poses` (strictly increasing stamps, shifted by `shift_ns`) nearest to
// t_ns, the earlier one on ties as numpy.argmin does.
size_t nearest(const std::vector<StampedPose>& poses, int64_t shift_ns, int64_t t_ns) {
  const auto it = std::lower_bound(
      poses.begin(), poses.end(), t_ns,
      [shift_ns](const StampedPose& p, int64_t t) { return p.t_ns + shift_ns < t; });
  const size_t i = static_cast<size_t>(it - poses.begin());
  if (i == poses.size()) return i - 1;
  if (i == 0) return 0;
  const int64_t before = t_ns - (poses[i - 1].t_ns + shift_ns);
  const int64_t after = poses[i].t_ns + shift_ns - t_ns;
  return before <= after ? i - 1 : i;
}

}  // namespace

Association associate(const Trajectory& gt, const Trajectory& est, int64_t t_max_diff_ns,
                      int64_t t_offset_ns) {
  // Iterate over the shorter one; express every stamp in the ground-truth clock.
  const bool iterate_gt = gt.poses.size() < est.poses.size();
  const std::vector<StampedPose>& outer = iterate_gt ? gt.poses : est.poses;
  const std::vector<StampedPose>& inner = iterate_gt ? est.poses : gt.poses;
  const int64_t outer_shift = iterate_gt ? 0 : t_offset_ns;
  const int64_t inner_shift = iterate_gt ? t_offset_ns : 0;
  Association a;
  for (const StampedPose& o : outer) {
    if (inner.empty()) break;
    const int64_t t_ns = o.t_ns + outer_shift;
    const StampedPose& in = inner[nearest(inner, inner_shift, t_ns)];
    if (std::llabs(in.t_ns + inner_shift - t_ns) > t_max_diff_ns) continue;
    a.gt.poses.push_back(iterate_gt ? o : in);
    a.est.poses.push_back(iterate_gt ? in : o);
  }
  if (a.est.poses.empty())
    throw InputError("no matching timestamps between ground truth and estimate (max diff " +
                     std::to_string(t_max_diff_ns * 1e-9) + " s, offset " +
                     std::to_string(t_offset_ns * 1e-9) + " s)");
  return a;
}

}  // namespace hs
