#pragma once
// A simulated room_mav flight as an EuRoC folder DIR/sim and its LCM log DIR/sim.lcmlog, for
// tests that replay it through processes. Pass the hs-sim and hs-euroc2lcm program paths.
#include <gtest/gtest.h>

#include <string>

#include "tests/common/child_process.h"

namespace hs::test {

// False (with the programs' output as failures) when either step fails.
inline bool make_sim_log(const std::string& hs_sim, const std::string& hs_euroc2lcm,
                         const std::string& dir, int duration_s) {
  ChildProcess gen({hs_sim, "--scenario", HS_SOURCE_DIR "/config/sim/room_mav.yaml", "--out",
                    dir + "/sim", "--duration", std::to_string(duration_s), "--quiet"},
                   dir + "/sim.txt");
  EXPECT_EQ(gen.wait(), 0) << gen.output();
  ChildProcess conv({hs_euroc2lcm, "--dataset", dir + "/sim", "--out", dir + "/sim.lcmlog"},
                    dir + "/euroc2lcm.txt");
  EXPECT_EQ(conv.wait(), 0) << conv.output();
  return !::testing::Test::HasFailure();
}

}  // namespace hs::test
