#include "common/config/yaml_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "common/core/error.h"

namespace hs {

YAML::Node parse_yaml(const std::string& text, const std::string& source) {
  std::string body = text;
  if (body.rfind("%YAML:", 0) == 0) body[0] = '#';  // OpenCV header -> comment, same line count
  try {
    return YAML::Load(body);
  } catch (const YAML::Exception& e) {
    throw InputError(source, e.mark.line + 1, "YAML syntax error: " + e.msg);
  }
}

YAML::Node load_yaml_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open file: " + std::string(std::strerror(errno)));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(path, "read error");
  return parse_yaml(text.str(), path);
}

}  // namespace hs
