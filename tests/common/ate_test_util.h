#pragma once
// ATE RMSE (SE(3)-aligned, as evo_ape --align) of a trajectory file, through the hs-eval program.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/common/child_process.h"

namespace hs::test {

inline double ate_rmse(const std::string& hs_eval, const std::string& gt,
                       const std::string& estimate, const std::string& json) {
  ChildProcess eval({hs_eval, gt, estimate, "--align", "--json", json}, json + ".txt");
  EXPECT_EQ(eval.wait(), 0) << eval.output();
  return nlohmann::json::parse(std::ifstream(json))["ape"]["rmse"].get<double>();
}

}  // namespace hs::test
