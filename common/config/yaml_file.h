#pragma once
// Reading YAML files, including the OpenCV/EuRoC flavour that starts with a `%YAML:1.0` line
// (not valid YAML, so yaml-cpp rejects it): that line is blanked, keeping line numbers intact.
#include <yaml-cpp/yaml.h>

#include <string>

namespace hs {

// Parses `path`. Throws InputError naming file:line on a missing file or a syntax error.
YAML::Node load_yaml_file(const std::string& path);

// Parses YAML text; `source` names it in errors.
YAML::Node parse_yaml(const std::string& text, const std::string& source);

}  // namespace hs
