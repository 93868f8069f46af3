#pragma once
// IMU refinement after the start (issue 6): an inertial-only optimisation of gravity direction,
// velocities and biases over a long stretch of the keyframe chain, the poses held where the
// visual bundle adjustment put them (as ORB-SLAM3's inertial-only step). A world levelled at
// rest with a biased accelerometer is tilted (0.1 m/s^2 is 0.6 deg); gravity and accelerometer
// bias only separate as the body turns, over seconds, not within a local BA window. The mapper
// centres the gravity prior on the world's -z, not on the previous estimate: a chain of relative
// priors is a random walk (one vehicle run wandered to 6 deg over a straight stretch), an absolute
// one bounds the tilt by what the levelling can have got wrong. It converges when the motion
// allows and never waits or loops.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>

#include "mapper/keyframe_graph.h"
#include "mapper/local_ba.h"
#include "mapper/window_input.h"

namespace hs {

struct InertialRefinementOptions {
  // Run after every n-th keyframe (0: never, gravity held at -z). Its velocities and biases
  // reach the window and, by MAP_UPDATE, the tracker. vehicle_loop 50 s seeds 1-8, online ATE
  // against the tracker alone: every 10th 0.99x, 5th 0.84x, 2nd 0.74x, 1st 0.91x (2-6 ms each).
  // Not every 2nd: there the atlas placed blackout.yaml's lost frame 4.8 cm off instead of 1.8
  // (loop_detection_test.cpp).
  int every_keyframes = 5;
  size_t max_keyframes = 150;                           // the newest keyframes of the chain
  size_t min_keyframes = 10;                            // fewer linked keyframes: not run
  double gravity_prior_sigma_rad = 1.0 * M_PI / 180.0;  // around the prior's g_w
  // A result is adopted only with gravity within this of the world's -z: no accelerometer bias
  // tilts the levelling by more (0.5 m/s^2 is 2.9 deg). A refinement goes beyond it when the
  // chain's poses and IMU disagree; adopting it would spread that into every velocity and bias
  // and tilt the tracker's world.
  double max_tilt_rad = 3.0 * M_PI / 180.0;
};

// The newest keyframes of `newest`'s IMU chain (up to max_keyframes, walking back by
// imu_predecessor), all with poses held, and the IMU factors between them; empty keyframes when
// fewer than min_keyframes are linked.
LocalBaInput inertial_refinement_input(const KeyframeGraph& graph, int64_t newest,
                                       const Eigen::Vector3d& g_w,
                                       const InertialRefinementOptions& options,
                                       const WindowInputOptions& window, int* imu_skipped);

}  // namespace hs
