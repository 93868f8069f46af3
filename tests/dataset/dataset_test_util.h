#pragma once
// Scratch copies of the bundled EuRoC sample for tests that alter it, and small file edits.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/core/error.h"
#include "tests/common/temp_dir.h"

namespace hs::test {

inline const std::string kSampleRoot = HS_SOURCE_DIR "/tests/data/euroc_v1_01_static_sample";
inline const std::string kSharedEuroc = HS_SOURCE_DIR "/../shared/data/euroc";

// A writable copy of the sample; mav0() is its mav0 folder.
class SampleCopy {
 public:
  SampleCopy() {
    std::filesystem::copy(kSampleRoot, dir_.path() + "/ds",
                          std::filesystem::copy_options::recursive);
  }
  std::string root() const { return dir_.path() + "/ds"; }
  std::string mav0() const { return root() + "/mav0"; }

 private:
  TempDir dir_;
};

inline std::vector<std::string> read_lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

inline void write_lines(const std::string& path, const std::vector<std::string>& lines) {
  std::ofstream out(path, std::ios::trunc);
  for (const std::string& l : lines) out << l << "\n";
}

// Replaces (1-based) line `n` of a file; an empty `text` with `erase` removes the line.
inline void edit_line(const std::string& path, size_t n, const std::string& text,
                      bool erase = false) {
  std::vector<std::string> lines = read_lines(path);
  ASSERT_LE(n, lines.size());
  if (erase)
    lines.erase(lines.begin() + static_cast<long>(n - 1));
  else
    lines[n - 1] = text;
  write_lines(path, lines);
}

template <class F>
std::string input_error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected hs::InputError";
  return "";
}

}  // namespace hs::test
