#pragma once
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <string>

namespace hs::test {

// A temp directory removed with its contents at scope exit.
class TempDir {
 public:
  TempDir() {
    char name[] = "/tmp/hs_test_XXXXXX";
    path_ = ::mkdtemp(name) ? name : "";
    EXPECT_FALSE(path_.empty());
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace hs::test
