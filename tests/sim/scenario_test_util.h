#pragma once
// Shared helpers of the scenario-side simulator tests.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "common/sim/scenario.h"

namespace hs::sim::testing {

inline std::string scenario_path(const std::string& name) {
  return std::string(HS_SOURCE_DIR) + "/config/sim/" + name + ".yaml";
}

// A fresh directory under the system temp dir, removed with the object.
class TempDir {
 public:
  explicit TempDir(const std::string& tag)
      : path_(std::filesystem::temp_directory_path() /
              ("hs_sim_" + tag + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  std::string file(const std::string& name, const std::string& content) const {
    const std::string p = (path_ / name).string();
    std::ofstream(p) << content;
    return p;
  }
  std::filesystem::path path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// A scenario from the repository with small textures, cheaper to render for tests.
inline Scenario test_scenario(const std::string& name) {
  Scenario sc = load_scenario(scenario_path(name));
  sc.camera.texture_size = 128;
  return sc;
}

// Cheaper still, for tests that do not depend on the world's content: little furniture.
inline Scenario sparse_scenario(const std::string& name) {
  Scenario sc = test_scenario(name);
  sc.world.furniture = 2;
  sc.camera.texture_size = 32;
  return sc;
}

}  // namespace hs::sim::testing
