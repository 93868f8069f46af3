// The shipped systemd units (as configured into build/systemd/) pass `systemd-analyze verify`
// with their programs pointed at this build, and carry the deployment policy: restart, the
// environment file, and CPU affinity and priority for the tracker.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "tests/dataset/dataset_test_util.h"

namespace hs {
namespace {

namespace fs = std::filesystem;

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Output (stdout + stderr) and exit status of a shell command.
std::pair<std::string, int> run(const std::string& command) {
  std::string out;
  FILE* p = ::popen((command + " 2>&1").c_str(), "r");
  if (!p) return {"popen failed", -1};
  std::array<char, 512> buf{};
  while (std::fgets(buf.data(), buf.size(), p)) out += buf.data();
  const int status = ::pclose(p);
  return {out, WIFEXITED(status) ? WEXITSTATUS(status) : -1};
}

std::map<std::string, std::string> configured_units() {
  std::map<std::string, std::string> units;
  for (const auto& e : fs::directory_iterator(HS_BINARY_DIR "/systemd"))
    units[e.path().filename().string()] = read_file(e.path().string());
  return units;
}

TEST(SystemdUnits, EveryProcessHasAUnitWithRestartAndTheEnvironmentFile) {
  const auto units = configured_units();
  for (const char* name : {"hs-camera.service", "hs-trigger.service", "hs-imu.service",
                           "hs-tracker.service", "hs-mapper.service", "hs-logger.service"}) {
    ASSERT_TRUE(units.count(name)) << name;
    const std::string& u = units.at(name);
    EXPECT_NE(u.find("\nRestart="), std::string::npos) << name;
    EXPECT_NE(u.find("EnvironmentFile=/etc/hs-slam/hs-slam.env"), std::string::npos) << name;
    EXPECT_NE(u.find("PartOf=hs-slam.target"), std::string::npos) << name;
    EXPECT_EQ(u.find('@'), std::string::npos) << name << ": unconfigured placeholder";
  }
  const std::string& tracker = units.at("hs-tracker.service");
  EXPECT_NE(tracker.find("\nCPUAffinity="), std::string::npos);
  EXPECT_NE(tracker.find("\nNice=-"), std::string::npos);
  // The environment file sets what the units use.
  const std::string env = read_file(HS_SOURCE_DIR "/config/systemd/hs-slam.env");
  for (const char* var : {"LCM_DEFAULT_URL=", "HS_CAMERA_CONFIG=", "HS_TRIGGER_CONFIG=",
                          "HS_IMU_CONFIG=", "HS_TRACKER_CONFIG=", "HS_MAPPER_CONFIG=",
                          "HS_LOGGER_CONFIG=", "HS_CALIB_DIR=", "HS_MULTICAST_DEV="})
    EXPECT_NE(env.find(std::string("\n") + var), std::string::npos) << var;
}

TEST(SystemdUnits, PassSystemdAnalyzeVerify) {
  if (run("command -v systemd-analyze").second != 0)
    GTEST_SKIP() << "systemd-analyze not installed (Debian package systemd): units not verified";
  test::TempDir dir;
  std::string files;
  for (const auto& [name, text] : configured_units()) {
    std::string unit = text;
    // The installed programs' directory, as configured, becomes this build's bin/.
    const std::string installed = HS_INSTALL_BINDIR;
    for (size_t at; (at = unit.find(installed)) != std::string::npos;)
      unit.replace(at, installed.size(), HS_BINARY_DIR "/bin/");
    std::ofstream(dir.path() + "/" + name) << unit;
    files += " " + dir.path() + "/" + name;
  }
  const auto [out, status] = run("systemd-analyze verify" + files);
  EXPECT_EQ(status, 0) << out;
  EXPECT_EQ(out, "") << "warnings about the units";
  // It does catch mistakes: a misspelt key.
  std::ofstream(dir.path() + "/hs-broken.service")
      << "[Unit]\nDescription=x\n[Service]\nExecStart=/bin/true\nRestat=always\n";
  EXPECT_NE(
      run("systemd-analyze verify " + dir.path() + "/hs-broken.service").first.find("Unknown key"),
      std::string::npos);
}

}  // namespace
}  // namespace hs
