#pragma once
// Options of the direct (photometric) tracking module: sparse image alignment of the relative
// pose (paper Eq. 16-18) and per-point patch alignment / optical flow (the correspondences of
// Eq. 17). Intensities are grey levels (0-255); pixel distances are in level-0 pixels unless
// named otherwise.

namespace hs {

struct SparseAlignOptions {
  int coarsest_level = 3;   // first (top) pyramid level aligned; clamped to the pyramid
  int finest_level = 0;     // last level aligned
  int max_iterations = 12;  // Gauss-Newton/LM iterations per level
  // The finest level is done when an update moves the points by less than this (its pixels);
  // each coarser level allows twice as much.
  double convergence_px = 0.005;
  bool estimate_affine = true;  // estimate I_cur = exp(a) * I_ref + b; else keep a, b fixed
  // Robust weights: Huber threshold in units of the level's residual scale, which is the median
  // per-patch RMS residual at the start of the level, floored at min_residual_scale.
  double huber_k = 1.345;
  double min_residual_scale = 2.0;
  // A patch whose RMS residual exceeds outlier_factor * scale is an outlier: it gets no weight
  // and is not counted as an inlier.
  double outlier_factor = 3.0;
  int min_points = 20;  // fewer valid patches: a coarse level is skipped, the finest one fails
  double min_inlier_ratio = 0.3;  // fewer inliers / valid patches at the finest level: failure
};

struct PatchAlignOptions {
  int max_iterations = 15;       // per level
  double convergence_px = 0.01;  // step size at level 0; level k allows 2^k times as much
  // Pyramid level where the search starts: the lowest level at which the search radius is at
  // most this many pixels (the capture range of an 8x8 patch).
  double capture_radius_px = 2.0;
  double max_rms_residual = 20.0;  // grey levels, after the affine brightness fit
  double min_gain = 0.5, max_gain = 2.0;
  // Reject a result that moved further than this from the initial guess (level-0 pixels), on top
  // of the search radius given per call.
  double max_extra_displacement_px = 2.0;
};

struct DirectOptions {
  SparseAlignOptions sparse;
  PatchAlignOptions patch;
};

}  // namespace hs
