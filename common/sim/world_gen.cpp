#include "common/sim/world_gen.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "common/sim/scenario_random.h"
#include "common/sim/world_build.h"

namespace hs::sim {
namespace {

constexpr int kPlacementTries = 40;
constexpr double kObjectGap = 0.1;  // between generated objects

SolidBox standing_box(const Eigen::Vector2d& center_xy, double yaw, const Eigen::Vector3d& size) {
  BoxSpec spec;
  spec.center = Eigen::Vector3d(center_xy.x(), center_xy.y(), 0.5 * size.z());
  spec.size = size;
  spec.yaw_deg = yaw * 180.0 / M_PI;
  return box_solid(spec);
}

// Separating-axis test of the boxes' footprints (yaw-only boxes), grown by `margin`.
bool footprints_overlap(const SolidBox& a, const SolidBox& b, double margin) {
  const std::array<const SolidBox*, 2> boxes{&a, &b};
  const Eigen::Vector2d d = (b.T_w_box.translation() - a.T_w_box.translation()).head<2>();
  for (const SolidBox* axis_box : boxes) {
    for (int i = 0; i < 2; ++i) {
      const Eigen::Vector2d axis = axis_box->T_w_box.linear().col(i).head<2>().normalized();
      double reach = margin;
      for (const SolidBox* box : boxes)
        for (int j = 0; j < 2; ++j)
          reach += box->half_size[j] * std::abs(axis.dot(box->T_w_box.linear().col(j).head<2>()));
      if (std::abs(axis.dot(d)) > reach) return false;
    }
  }
  return true;
}

class Placer {
 public:
  Placer(const std::vector<Eigen::Vector3d>& path_w, const Eigen::AlignedBox3d& bounds)
      : path_w_(path_w), bounds_(bounds) {}

  // Keeps `box` if it is inside the bounds, `clearance` away from the path and apart from the
  // objects placed so far.
  bool try_place(const SolidBox& box, double clearance) {
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d corner(c & 1 ? 1 : -1, c & 2 ? 1 : -1, c & 4 ? 1 : -1);
      if (!bounds_.contains(box.T_w_box * corner.cwiseProduct(box.half_size))) return false;
    }
    for (const SolidBox& other : placed_)
      if (footprints_overlap(box, other, kObjectGap)) return false;
    for (const Eigen::Vector3d& p : path_w_)
      if (distance_to_box(box, p) < clearance) return false;
    placed_.push_back(box);
    return true;
  }
  // An object placed by the user: kept as it is, generated ones keep clear of it.
  void add_fixed(const SolidBox& box) { placed_.push_back(box); }

 private:
  const std::vector<Eigen::Vector3d>& path_w_;
  Eigen::AlignedBox3d bounds_;
  std::vector<SolidBox> placed_;
};

SurfaceStyle style(TextureKind kind, ScenarioRng& rng, double metres_per_tile) {
  SurfaceStyle s;
  s.texture = kind;
  s.seed = static_cast<uint32_t>(rng.uniform() * 4294967295.0);
  s.metres_per_tile = metres_per_tile;
  s.brightness = static_cast<float>(rng.uniform(0.75, 1.1));
  return s;
}

TextureKind object_texture(ScenarioRng& rng) {
  static constexpr std::array<TextureKind, 3> kinds{TextureKind::kMixed, TextureKind::kBlobs,
                                                    TextureKind::kBrick};
  return kinds[static_cast<size_t>(rng.uniform() * kinds.size()) % kinds.size()];
}

void add_solid_box(World* world, const SolidBox& box, const SurfaceStyle& s) {
  add_box(world, box.T_w_box, box.half_size, s);
}

void furnish_room(const WorldSpec& spec, Placer& placer, ScenarioRng& rng, World* world) {
  const Eigen::Vector3d half = 0.5 * spec.room_size_m;
  for (int item = 0; item < spec.furniture; ++item) {
    for (int attempt = 0; attempt < kPlacementTries; ++attempt) {
      const int type = static_cast<int>(rng.uniform() * 4.0);
      Eigen::Vector3d size;
      Eigen::Vector2d center(rng.uniform(-half.x(), half.x()), rng.uniform(-half.y(), half.y()));
      double yaw = rng.uniform(0.0, M_PI);
      if (type == 0) {  // table
        size = {rng.uniform(1.0, 1.8), rng.uniform(0.6, 1.0), rng.uniform(0.7, 0.8)};
      } else if (type == 1) {  // shelf against a wall
        size = {rng.uniform(1.0, 2.0), 0.4, rng.uniform(1.6, 2.2)};
        const int wall = static_cast<int>(rng.uniform() * 4.0);
        const double along = rng.uniform(-1.0, 1.0);
        const double inset = 0.2 + 0.02;
        yaw = (wall < 2) ? 0.0 : 0.5 * M_PI;
        const double sign = (wall % 2 == 0) ? 1.0 : -1.0;
        center = (wall < 2) ? Eigen::Vector2d(along * (half.x() - 1.0), sign * (half.y() - inset))
                            : Eigen::Vector2d(sign * (half.x() - inset), along * (half.y() - 1.0));
      } else if (type == 2) {  // cabinet
        size = {rng.uniform(0.6, 1.2), rng.uniform(0.5, 0.7), rng.uniform(0.9, 1.4)};
      } else {  // crate
        const double edge = rng.uniform(0.4, 0.8);
        size = {edge, edge, edge};
      }
      const SolidBox box = standing_box(center, yaw, size);
      if (placer.try_place(box, spec.clearance_m)) {
        add_solid_box(world, box, style(object_texture(rng), rng, 1.0));
        break;
      }
    }
  }
}

void build_room(const WorldSpec& spec, Placer& placer, ScenarioRng& rng, World* world) {
  const Eigen::Vector3d half = 0.5 * spec.room_size_m;
  add_room(world, Eigen::Vector3d(-half.x(), -half.y(), 0.0),
           Eigen::Vector3d(half.x(), half.y(), spec.room_size_m.z()),
           style(TextureKind::kMixed, rng, 2.0), style(TextureKind::kGravel, rng, 1.5),
           style(TextureKind::kBlobs, rng, 2.0));
  furnish_room(spec, placer, rng, world);
}

// A point of the path and its unit tangent, in the ground plane.
struct PathFrame {
  Eigen::Vector2d p, tangent;
};

std::vector<PathFrame> path_frames_every(const std::vector<Eigen::Vector3d>& path_w, double step,
                                         ScenarioRng& rng) {
  std::vector<PathFrame> frames;
  double next = rng.uniform(0.0, step), travelled = 0.0;
  for (size_t i = 1; i < path_w.size(); ++i) {
    const Eigen::Vector2d d = (path_w[i] - path_w[i - 1]).head<2>();
    travelled += d.norm();
    if (travelled < next || d.norm() < 1e-9) continue;
    frames.push_back({path_w[i].head<2>(), d.normalized()});
    next = travelled + step * rng.uniform(0.8, 1.25);
  }
  return frames;
}

void build_street(const WorldSpec& spec, const std::vector<Eigen::Vector3d>& path_w, Placer& placer,
                  ScenarioRng& rng, World* world) {
  // Ground in 10 m tiles so the texture does not visibly repeat.
  constexpr double kTile = 10.0;
  for (double x = spec.street_min_m.x(); x < spec.street_max_m.x() - 1e-9; x += kTile) {
    for (double y = spec.street_min_m.y(); y < spec.street_max_m.y() - 1e-9; y += kTile) {
      const double w = std::min(kTile, spec.street_max_m.x() - x);
      const double h = std::min(kTile, spec.street_max_m.y() - y);
      add_quad(world, Eigen::Vector3d(x, y, 0.0), Eigen::Vector3d(w, 0, 0),
               Eigen::Vector3d(0, h, 0), style(TextureKind::kGravel, rng, 2.0));
    }
  }
  const auto place_beside = [&](const PathFrame& f, double side, double offset,
                                const Eigen::Vector3d& size, double clearance, TextureKind kind,
                                double metres_per_tile) {
    const Eigen::Vector2d left(-f.tangent.y(), f.tangent.x());
    const SolidBox box = standing_box(f.p + side * (offset + 0.5 * size.y()) * left,
                                      std::atan2(f.tangent.y(), f.tangent.x()), size);
    if (placer.try_place(box, clearance))
      add_solid_box(world, box, style(kind, rng, metres_per_tile));
  };
  const auto random_side = [&rng] { return rng.uniform() < 0.5 ? 1.0 : -1.0; };
  // Small objects first so the buildings fill the space behind them.
  for (const PathFrame& f : path_frames_every(path_w, spec.pole_spacing_m, rng))
    place_beside(f, random_side(), 2.8, Eigen::Vector3d(0.2, 0.2, 4.5), spec.clearance_m,
                 TextureKind::kMixed, 1.0);
  for (const PathFrame& f : path_frames_every(path_w, spec.parked_spacing_m, rng))
    place_beside(f, random_side(), 2.6, Eigen::Vector3d(4.2, 1.8, 1.5), spec.clearance_m,
                 TextureKind::kBlobs, 1.5);
  for (const PathFrame& f : path_frames_every(path_w, 7.0, rng)) {
    for (const double side : {1.0, -1.0}) {
      const Eigen::Vector3d size(rng.uniform(7.0, 14.0), rng.uniform(6.0, 12.0),
                                 rng.uniform(5.0, 14.0));
      place_beside(f, side, spec.building_setback_m, size, spec.building_setback_m - 0.5,
                   rng.uniform() < 0.5 ? TextureKind::kBrick : TextureKind::kMixed, 3.0);
    }
  }
}

// Keeps what lies (by centre) in the first period of x and copies it along the whole street.
void repeat_along_x(const WorldSpec& spec, World* world) {
  const double x0 = spec.street_min_m.x(), period = spec.repeat_x_m;
  const auto in_first = [&](const Eigen::Vector3d& c) { return c.x() < x0 + period; };
  World first;
  for (const TexturedQuad& q : world->quads)
    if (in_first(q.p0_w + 0.5 * (q.edge_u_w + q.edge_v_w))) first.quads.push_back(q);
  for (const SolidBox& b : world->solids)
    if (in_first(b.T_w_box.translation())) first.solids.push_back(b);
  *world = first;
  for (double shift = period; x0 + shift < spec.street_max_m.x(); shift += period) {
    for (TexturedQuad q : first.quads) {
      q.p0_w.x() += shift;
      world->quads.push_back(q);
    }
    for (SolidBox b : first.solids) {
      b.T_w_box.translation().x() += shift;
      world->solids.push_back(b);
    }
  }
}

bool in_any(const std::vector<Eigen::AlignedBox3d>& regions, const Eigen::Vector3d& p) {
  for (const Eigen::AlignedBox3d& r : regions)
    if (r.contains(p)) return true;
  return false;
}

}  // namespace

SolidBox box_solid(const BoxSpec& box) {
  SolidBox solid;
  solid.T_w_box = Eigen::Translation3d(box.center) *
                  Eigen::AngleAxisd(box.yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ());
  solid.half_size = 0.5 * box.size;
  return solid;
}

double distance_to_box(const SolidBox& box, const Eigen::Vector3d& p_w) {
  const Eigen::Vector3d p_box = box.T_w_box.inverse() * p_w;
  return (p_box.cwiseAbs() - box.half_size).cwiseMax(0.0).norm();
}

Eigen::AlignedBox3d world_bounds(const WorldSpec& spec) {
  if (spec.type == WorldType::kRoom) {
    const Eigen::Vector3d half = 0.5 * spec.room_size_m;
    return {Eigen::Vector3d(-half.x(), -half.y(), 0.0),
            Eigen::Vector3d(half.x(), half.y(), spec.room_size_m.z())};
  }
  return {Eigen::Vector3d(spec.street_min_m.x(), spec.street_min_m.y(), 0.0),
          Eigen::Vector3d(spec.street_max_m.x(), spec.street_max_m.y(), 50.0)};
}

World generate_world(const WorldSpec& spec, const std::vector<Eigen::Vector3d>& path_w,
                     uint64_t seed) {
  ScenarioRng rng(seed);
  World world;
  Placer placer(path_w, world_bounds(spec));
  for (const BoxSpec& spec_box : spec.boxes) {
    const SolidBox box = box_solid(spec_box);
    placer.add_fixed(box);
    add_solid_box(&world, box, style(object_texture(rng), rng, 1.0));
  }
  if (spec.type == WorldType::kRoom) {
    build_room(spec, placer, rng, &world);
  } else {
    build_street(spec, path_w, placer, rng, &world);
    if (spec.repeat_x_m > 0) repeat_along_x(spec, &world);
  }
  for (TexturedQuad& q : world.quads)
    if (in_any(spec.textureless_regions, q.p0_w + 0.5 * (q.edge_u_w + q.edge_v_w)))
      q.texture = TextureKind::kPlain;
  return world;
}

}  // namespace hs::sim
