#pragma once
// Temp YAML files and error-message checks shared by the config tests.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "common/core/error.h"

namespace hs::test {

class TempYaml {
 public:
  explicit TempYaml(const std::string& content) {
    char name[] = "/tmp/hs_config_XXXXXX.yaml";
    const int fd = mkstemps(name, 5);
    EXPECT_GE(fd, 0);
    ::close(fd);
    path_ = name;
    std::ofstream(path_) << content;
  }
  ~TempYaml() { std::remove(path_.c_str()); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// Runs `f`, expecting an InputError whose message contains every one of `parts`.
template <class F>
void expect_input_error(F&& f, const std::vector<std::string>& parts) {
  try {
    f();
    ADD_FAILURE() << "expected hs::InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const std::string& part : parts)
      EXPECT_NE(msg.find(part), std::string::npos) << "'" << part << "' not in: " << msg;
  }
}

}  // namespace hs::test
