// Scenario files: strict loading with file:line errors, and the properties each scenario
// promises (loop length, speeds, slip, rotation rates).
#include <gtest/gtest.h>

#include <filesystem>

#include "common/core/error.h"
#include "common/sim/dataset_gen.h"
#include "common/sim/scenario.h"
#include "scenario_test_util.h"

namespace hs::sim {
namespace {

using testing::scenario_path;
using testing::TempDir;

const char* const kScenarios[] = {"room_mav",          "vehicle_loop",  "textureless",
                                  "illumination_step", "fast_rotation", "blackout",
                                  "imu_gap",           "static",        "lookalike_street"};

TEST(ScenarioTest, AllShippedScenariosLoad) {
  for (const char* name : kScenarios) {
    SCOPED_TRACE(name);
    const Scenario sc = load_scenario(scenario_path(name));
    EXPECT_EQ(sc.name, name);
    EXPECT_GT(sc.duration_s, 0.0);
    EXPECT_EQ(sc.camera.rate_hz, 20.0);
    EXPECT_EQ(sc.camera.calib.cam0.intrinsics.width, 752);
    EXPECT_EQ(sc.imu.rate_hz, 200.0);
  }
  // Every file in config/sim is one of them.
  int files = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(HS_SOURCE_DIR) + "/config/sim"))
    files += entry.path().extension() == ".yaml";
  EXPECT_EQ(files, static_cast<int>(std::size(kScenarios)));
}

const char* const kValidRoom = R"(name: t
duration_s: 20
world:
  type: room
  room_size_m: [8, 7, 3]
  furniture: 3
trajectory:
  waypoints: [-2, -2, 1.5,
              2, -2, 1.5,
              2, 2, 1.5]
  speed_mps: 0.8
  yaw:
    mode: keyframes
    deg: [0, 90]
)";

std::string error_of(const std::string& path) {
  try {
    load_scenario(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ScenarioTest, ValidMinimalFileLoads) {
  TempDir dir("scenario_ok");
  const Scenario sc = load_scenario(dir.file("ok.yaml", kValidRoom));
  EXPECT_EQ(sc.trajectory.waypoints.size(), 3u);
  EXPECT_EQ(sc.world.furniture, 3);
}

TEST(ScenarioTest, UnknownKeyNamesFileLineAndKey) {
  TempDir dir("scenario_unknown");
  std::string text = kValidRoom;
  text.replace(text.find("  speed_mps"), 11, "  sped_mps");
  const std::string path = dir.file("typo.yaml", text);
  const std::string err = error_of(path);
  EXPECT_NE(err.find(path + ":11:"), std::string::npos) << err;
  EXPECT_NE(err.find("trajectory.sped_mps"), std::string::npos) << err;
  EXPECT_NE(err.find("speed_mps"), std::string::npos) << err;  // the suggestion
}

TEST(ScenarioTest, BadTypeNamesTheKey) {
  TempDir dir("scenario_type");
  std::string text = kValidRoom;
  text.replace(text.find("furniture: 3"), 12, "furniture: many");
  const std::string path = dir.file("type.yaml", text);
  const std::string err = error_of(path);
  EXPECT_NE(err.find(path + ":6:"), std::string::npos) << err;
  EXPECT_NE(err.find("world.furniture"), std::string::npos) << err;
}

TEST(ScenarioTest, ZeroOrNegativeDurationIsRejected) {
  TempDir dir("scenario_duration");
  for (const char* bad : {"duration_s: 0", "duration_s: -3"}) {
    std::string text = kValidRoom;
    text.replace(text.find("duration_s: 20"), 14, bad);
    const std::string path = dir.file("duration.yaml", text);
    const std::string err = error_of(path);
    EXPECT_NE(err.find(path + ":2:"), std::string::npos) << err;
    EXPECT_NE(err.find("duration_s"), std::string::npos) << err;
  }
}

TEST(ScenarioTest, PathThroughAnExplicitBoxIsRejected) {
  TempDir dir("scenario_box");
  std::string text = kValidRoom;
  text.replace(text.find("  furniture: 3"), 14,
               "  furniture: 3\n  boxes: [0, -2, 0.75, 1, 1, 1.5, 0]");
  const std::string path = dir.file("box.yaml", text);
  const std::string err = error_of(path);
  EXPECT_NE(err.find(path + ":9:"), std::string::npos) << err;  // the waypoints key
  EXPECT_NE(err.find("trajectory.waypoints"), std::string::npos) << err;
  EXPECT_NE(err.find("world.boxes[0]"), std::string::npos) << err;
}

TEST(ScenarioTest, PathLeavingTheWorldIsRejected) {
  TempDir dir("scenario_bounds");
  std::string text = kValidRoom;
  text.replace(text.find("2, 2, 1.5]"), 10, "5, 2, 1.5]");
  const std::string path = dir.file("bounds.yaml", text);
  const std::string err = error_of(path);
  EXPECT_NE(err.find(path + ":8:"), std::string::npos) << err;
  EXPECT_NE(err.find("leaves the world"), std::string::npos) << err;
  EXPECT_NE(err.find("waypoint 2"), std::string::npos) << err;
}

TEST(ScenarioTest, BadValuesAreRejectedAtTheirLine) {
  TempDir dir("scenario_values");
  const std::pair<const char*, const char*> cases[] = {
      {"    mode: keyframes", "    mode: sideways"},
      {"  speed_mps: 0.8", "  speed_mps: 0"},
      {"              2, 2, 1.5]", "              2, 2]"},
      {"  type: room", "  type: moon"},
  };
  for (const auto& [from, to] : cases) {
    std::string text = kValidRoom;
    text.replace(text.find(from), std::string(from).size(), to);
    const std::string path = dir.file("values.yaml", text);
    EXPECT_NE(error_of(path).find(path + ":"), std::string::npos) << to;
  }
}

TEST(ScenarioTest, VehicleLoopIsClosedAndDrivenTwice) {
  const Scenario sc = load_scenario(scenario_path("vehicle_loop"));
  ASSERT_TRUE(sc.trajectory.closed);
  const Trajectory tr(sc.trajectory);
  const double dt = 0.01;
  // During the cruise path time runs at 1 s/s, so path_length_s() of it is one full lap.
  double loop_length = 0.0;
  double travelled = 0.0, min_speed = 1e9, max_speed = 0.0, max_lateral = 0.0, max_tilt = 0.0;
  double min_z = 1e9, max_z = -1e9;
  const double cruise_from = sc.trajectory.start_hold_s + sc.trajectory.ramp_s;
  const double cruise_to = tr.motion_end_s() - sc.trajectory.ramp_s;
  Eigen::Vector3d prev = tr.at(0).p_w_b;
  for (double t = dt; t <= sc.duration_s; t += dt) {
    const BodyKinematics k = tr.at(t);
    travelled += (k.p_w_b - prev).norm();
    prev = k.p_w_b;
    if (t >= cruise_from && t <= cruise_from + tr.path_length_s()) loop_length += k.v_w.norm() * dt;
    if (t > cruise_from && t < cruise_to) {
      min_speed = std::min(min_speed, k.v_w.norm());
      max_speed = std::max(max_speed, k.v_w.norm());
    }
    // Body y is the rig's right axis: no sideways velocity.
    max_lateral = std::max(max_lateral, std::abs((k.q_w_b.conjugate() * k.v_w).y()));
    max_tilt = std::max(max_tilt, std::acos((k.q_w_b * Eigen::Vector3d::UnitX()).z()));
    min_z = std::min(min_z, k.p_w_b.z());
    max_z = std::max(max_z, k.p_w_b.z());
  }
  EXPECT_GE(loop_length, 150.0);
  EXPECT_GE(travelled, 2.0 * loop_length - 1.0);
  EXPECT_LE(travelled, 2.0 * loop_length + 1.0);
  EXPECT_LT((tr.at(sc.duration_s).p_w_b - tr.at(0).p_w_b).norm(), 0.01) << "back at the start";
  EXPECT_GE(min_speed, 2.0);
  EXPECT_LE(max_speed, 5.0);
  EXPECT_LT(max_lateral, 0.01);
  EXPECT_LT(max_tilt * 180.0 / M_PI, 3.0);
  EXPECT_LT(max_z - min_z, 1e-9) << "planar";
  EXPECT_NEAR(min_z, 1.5, 1e-9) << "camera rig height";
}

// Every surface of the look-alike street has a twin 20 m further along x, the same to the texel,
// as far as the street goes.
TEST(ScenarioTest, LookalikeStreetRepeatsEvery20m) {
  const Scenario sc = load_scenario(scenario_path("lookalike_street"));
  ASSERT_EQ(sc.world.repeat_x_m, 20.0);
  const DatasetGenerator gen(sc);
  const std::vector<TexturedQuad>& quads = gen.world().quads;
  const auto twin = [&](const TexturedQuad& q) {
    for (const TexturedQuad& o : quads)
      if ((o.p0_w - q.p0_w - Eigen::Vector3d(20, 0, 0)).norm() < 1e-9 && o.edge_u_w == q.edge_u_w &&
          o.edge_v_w == q.edge_v_w && o.texture == q.texture && o.texture_seed == q.texture_seed &&
          o.texture_offset == q.texture_offset && o.brightness == q.brightness)
        return true;
    return false;
  };
  int checked = 0;
  for (const TexturedQuad& q : quads) {
    if (q.p0_w.x() + 20.0 > sc.world.street_max_m.x() - 30.0) continue;  // the last copies
    EXPECT_TRUE(twin(q)) << "quad at " << q.p0_w.transpose();
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

double max_rate_deg(const Trajectory& tr, double duration_s) {
  double w = 0;
  for (double t = 0; t <= duration_s; t += 0.005) w = std::max(w, tr.at(t).omega_b.norm());
  return w * 180.0 / M_PI;
}

TEST(ScenarioTest, FastRotationExceeds200DegPerSecond) {
  const Scenario sc = load_scenario(scenario_path("fast_rotation"));
  EXPECT_GT(max_rate_deg(Trajectory(sc.trajectory), sc.duration_s), 200.0);
}

TEST(ScenarioTest, RoomMavIsAGentleEurocLikeFlight) {
  const Scenario sc = load_scenario(scenario_path("room_mav"));
  EXPECT_GE(sc.duration_s, 30.0);
  EXPECT_LE(sc.duration_s, 60.0);
  const Trajectory tr(sc.trajectory);
  double max_speed = 0;
  for (double t = 0; t <= sc.duration_s; t += 0.01)
    max_speed = std::max(max_speed, tr.at(t).v_w.norm());
  EXPECT_GT(max_speed, 0.5);
  EXPECT_LE(max_speed, 1.05);
  const double rate = max_rate_deg(tr, sc.duration_s);
  EXPECT_GT(rate, 30.0);
  EXPECT_LE(rate, 65.0);
}

TEST(ScenarioTest, StaticScenarioNeverMoves) {
  const Scenario sc = load_scenario(scenario_path("static"));
  EXPECT_EQ(sc.duration_s, 10.0);
  const Trajectory tr(sc.trajectory);
  const BodyKinematics first = tr.at(0);
  for (double t = 0; t <= sc.duration_s; t += 0.1) {
    const BodyKinematics k = tr.at(t);
    EXPECT_LT((k.p_w_b - first.p_w_b).norm(), 1e-12);
    EXPECT_LT(k.q_w_b.angularDistance(first.q_w_b), 1e-12);
    EXPECT_LT(k.v_w.norm() + k.a_w.norm() + k.omega_b.norm(), 1e-12);
  }
}

}  // namespace
}  // namespace hs::sim
