#include "common/core/atomic_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "common/core/error.h"

namespace hs {
namespace {

std::string read_all(const std::string& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(AtomicFile, NothingAppearsUntilCommit) {
  const std::string p = "/tmp/hs_atomic_" + std::to_string(::getpid());
  std::remove(p.c_str());
  {
    AtomicFile f(p);
    f.stream() << "partial";
    EXPECT_NE(::access(f.temp_path().c_str(), F_OK), -1);
    EXPECT_EQ(::access(p.c_str(), F_OK), -1);
  }  // abandoned: neither file remains
  EXPECT_EQ(::access(p.c_str(), F_OK), -1);
  write_file_atomically(p, "done");
  EXPECT_EQ(read_all(p), "done");
  std::remove(p.c_str());
}

TEST(AtomicFile, UnwritableDirectoryIsAnInputError) {
  EXPECT_THROW(write_file_atomically("/nonexistent_dir/out.txt", "x"), InputError);
}

}  // namespace
}  // namespace hs
