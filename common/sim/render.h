#pragma once
// Renders the simulated world (textured quads) into 8-bit mono images through a PinholeRadtan
// camera, with exact geometry: pixel (u, v) (column, row) covers [u - 0.5, u + 0.5] x
// [v - 0.5, v + 0.5] and its centre shows the surface point that PinholeRadtan::project maps
// to (u, v) (see pinhole_radtan.h).
//
// Method (a per-pixel-ray rasteriser): every output pixel corner and centre has a precomputed
// undistorted ray, so distortion costs nothing per frame and needs no resampling. Per 16x16
// tile, the quads whose projection (clipped at the near plane) overlaps the tile are tested at
// the pixel corners with the perspective-correct affine forms of 1/z, u/z and v/z in
// normalised coordinates (4-wide vectors), giving a z-buffered visibility. Runs of pixels
// whose corners all see one quad are shaded at their centres (trilinear mipmapped texture,
// vectorised); pixels on polygon edges get 16 coverage samples. Tiles that move more than
// blur_step_px during the exposure are re-rendered at sub-exposure poses and averaged
// (adaptive motion blur). Then gain, vignetting, noise and quantisation in one pass.
#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "common/calib/pinhole_radtan.h"
#include "common/sim/photometric.h"
#include "common/sim/world.h"

namespace hs::sim {

// Fixed per renderer (per camera).
struct RenderOptions {
  PhotometricOptions photometric;
  float background = 0.0f;  // radiance (0..255 scale) where no quad is seen
  double near_m = 0.05;     // near clipping distance along the optical axis
  // Motion blur: a tile whose image motion during the exposure exceeds blur_step_px is
  // rendered at n = ceil(motion / blur_step_px) sub-exposure poses, rounded up to odd (the
  // middle one is the frame pose, rendered anyway), at most max_blur_samples, and averaged.
  // Needs FrameParams::T_w_c_at.
  bool motion_blur = true;
  double blur_step_px = 1.5;
  int max_blur_samples = 5;
  int texture_size = 1024;  // texels per tile side (power of two)
};

// Per image.
struct FrameParams {
  double gain = 1.0;        // exposure x gain multiplier (1.4 = 40% brighter)
  bool blackout = false;    // all-black image (lens covered / lights off)
  uint64_t noise_seed = 0;  // same seed -> byte-identical image; use e.g. 2*frame + camera
  // Optional camera pose over the exposure, fraction 0 = exposure start, 1 = end (0.5 should
  // equal the pose passed to render()). Empty -> no motion blur.
  std::function<Eigen::Isometry3d(double fraction)> T_w_c_at;
};

// Work per stage, accumulated over render() and render_radiance() calls (thread CPU time).
struct RenderStats {
  int64_t images = 0;
  int64_t setup_ns = 0;        // quad transforms, clipping, tile binning
  int64_t visibility_ns = 0;   // per-corner depth test (the rasteriser)
  int64_t shading_ns = 0;      // texture sampling incl. edge anti-aliasing
  int64_t blur_ns = 0;         // motion estimate + sub-exposure re-renders of moving tiles
  int64_t photometric_ns = 0;  // gain, vignetting, noise, quantisation
  int64_t edge_pixels = 0;     // pixels that got coverage anti-aliasing (frame pose only)
  int64_t blurred_tiles = 0;   // tiles re-rendered for motion blur
};

class Renderer {
 public:
  // Generates (and mipmaps) the textures of `world` once. Copies the world. Throws
  // std::invalid_argument for an unusable camera, options or quad.
  Renderer(const World& world, const PinholeRadtan& camera, const RenderOptions& options = {});
  // Shares another renderer's world and textures (e.g. for the second camera of a pair; the
  // texture size is the other renderer's). Renderers sharing a scene may run in parallel.
  Renderer(const Renderer& shares_scene_with, const PinholeRadtan& camera,
           const RenderOptions& options);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Renders the image seen from camera pose T_w_c (camera -> world; camera frame x right,
  // y down, z forward). Returns a CV_8UC1 image of camera.width x camera.height.
  cv::Mat render(const Eigen::Isometry3d& T_w_c, const FrameParams& frame = {});
  // The noiseless radiance image before gain/vignetting/noise (CV_32FC1, 0..255 scale).
  cv::Mat render_radiance(const Eigen::Isometry3d& T_w_c, const FrameParams& frame = {});

  const PinholeRadtan& camera() const;
  const RenderOptions& options() const;
  const RenderStats& stats() const;
  void reset_stats();

 private:
  struct Scene;  // world + textures, shared between the cameras of a rig
  class Impl;    // per-camera ray maps, scratch buffers, stats
  std::shared_ptr<const Scene> scene_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hs::sim
