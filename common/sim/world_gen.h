#pragma once
// Procedural worlds for the scenarios: a furnished room (MAV) or a street block with buildings,
// poles and parked objects (vehicle). Generated objects are placed clear of the trajectory, so
// any seed gives a valid scenario; explicit boxes are checked by the scenario instead.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "common/sim/world.h"

namespace hs::sim {

enum class WorldType { kRoom, kStreet };

// An explicit box standing at `center` (world), `size` along its axes, turned by yaw about z.
struct BoxSpec {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d size = Eigen::Vector3d::Ones();
  double yaw_deg = 0.0;
};

struct WorldSpec {
  WorldType type = WorldType::kRoom;
  // Room: x, y in [-size/2, size/2], z in [0, size.z].
  Eigen::Vector3d room_size_m{8.0, 7.0, 3.0};
  int furniture = 10;  // tables, shelves, cabinets, crates
  // Street: ground extent (x, y); the vehicle path runs inside it.
  Eigen::Vector2d street_min_m{-50.0, -40.0};
  Eigen::Vector2d street_max_m{50.0, 40.0};
  double building_setback_m = 6.0;  // from the path to the facades
  double pole_spacing_m = 12.0;     // along the path, on alternating-ish sides
  double parked_spacing_m = 18.0;
  // Both: the smallest distance between the path and any solid.
  double clearance_m = 0.4;
  // Street: the content repeats along x with this period (0: never), every copy alike to the
  // texel: a look-alike street where a place recogniser must not close a loop.
  double repeat_x_m = 0.0;
  std::vector<BoxSpec> boxes;
  // Surfaces whose centre lies in one of these are drawn textureless (kPlain).
  std::vector<Eigen::AlignedBox3d> textureless_regions;
};

// `path_w`: samples of the body path (dense enough that objects cannot slip between them).
World generate_world(const WorldSpec& spec, const std::vector<Eigen::Vector3d>& path_w,
                     uint64_t seed);

// The region the path must stay in: the room interior, or the street extent up to 50 m.
Eigen::AlignedBox3d world_bounds(const WorldSpec& spec);

SolidBox box_solid(const BoxSpec& box);

// Euclidean distance from p_w to the box volume (0 inside).
double distance_to_box(const SolidBox& box, const Eigen::Vector3d& p_w);

}  // namespace hs::sim
