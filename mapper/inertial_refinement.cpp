#include "mapper/inertial_refinement.h"

#include <set>

namespace hs {

LocalBaInput inertial_refinement_input(const KeyframeGraph& graph, int64_t newest,
                                       const Eigen::Vector3d& g_w,
                                       const InertialRefinementOptions& options,
                                       const WindowInputOptions& window, int* imu_skipped) {
  std::set<int64_t> chain{newest};
  for (auto id = graph.imu_predecessor(newest); id && chain.size() < options.max_keyframes;
       id = graph.imu_predecessor(*id))
    chain.insert(*id);
  LocalBaInput in;
  if (chain.size() < options.min_keyframes) return in;
  in.gravity = {g_w, options.gravity_prior_sigma_rad};
  for (int64_t id : chain) {
    BaKeyframe k{id, graph.keyframe(id)->state};
    k.pose_fixed = true;
    in.keyframes.push_back(k);
  }
  in.imu_factors = chain_imu_factors(graph, chain, {}, window, imu_skipped);
  return in;
}

}  // namespace hs
