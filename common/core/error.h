#pragma once
// Errors for bad input: every message names the file (and line when known) it came from.
#include <stdexcept>
#include <string>

namespace hs {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& what) : std::runtime_error(what) {}
  InputError(const std::string& file, const std::string& what)
      : std::runtime_error(file + ": " + what) {}
  InputError(const std::string& file, long line, const std::string& what)
      : std::runtime_error(file + ":" + std::to_string(line) + ": " + what) {}
};

}  // namespace hs
