#include "common/config/config_section.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "common/config/yaml_file.h"
#include "common/core/error.h"
#include "common/core/types.h"

namespace hs {
namespace {

long line_of(const YAML::Node& node) {
  return node.Mark().line + 1;
}

std::string describe(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Scalar:
      return "'" + node.Scalar() + "'";
    case YAML::NodeType::Sequence:
      return "a sequence";
    case YAML::NodeType::Map:
      return "a mapping";
    default:
      return "nothing";
  }
}

// " (did you mean 'x'?)" for a near miss, else the list of known keys.
std::string suggestion(const std::string& key, const std::set<std::string>& known) {
  if (known.empty()) return " (this section takes no keys)";
  const std::string* best = nullptr;
  size_t best_distance = 0;
  std::string list;
  for (const std::string& candidate : known) {
    const size_t d = edit_distance(key, candidate);
    if (!best || d < best_distance) best = &candidate, best_distance = d;
    list += (list.empty() ? "" : ", ") + candidate;
  }
  if (best_distance <= std::max<size_t>(2, key.size() / 3))
    return " (did you mean '" + *best + "'?)";
  return " (known keys: " + list + ")";
}

// Converts a scalar with yaml-cpp's own parser; false when the node is not a valid T.
template <class T>
bool scalar(const YAML::Node& node, T& out) {
  return node.IsScalar() && YAML::convert<T>::decode(node, out);
}

}  // namespace

ConfigSection::ConfigSection(std::string file, YAML::Node node, std::string name)
    : file_(std::move(file)), node_(std::move(node)), name_(std::move(name)) {
  if (!node_.IsMap() && !node_.IsNull())
    throw InputError(file_, line_of(node_),
                     (name_.empty() ? std::string("file") : "'" + name_ + "'") +
                         ": expected a mapping of keys, got " + describe(node_));
}

ConfigSection ConfigSection::load(const std::string& path) {
  return ConfigSection(path, load_yaml_file(path), "");
}

YAML::Node ConfigSection::lookup(const std::string& key) {
  known_.insert(key);
  const YAML::Node& map = node_;  // const: operator[] must not insert the key
  return map.IsMap() ? map[key] : YAML::Node(YAML::NodeType::Undefined);
}

std::string ConfigSection::qualified(const std::string& key) const {
  return name_.empty() ? key : name_ + "." + key;
}

bool ConfigSection::read_seconds(const std::string& key, int64_t& t_ns) {
  double t_s = ns_to_s(t_ns);
  if (!read(key, t_s)) return false;
  t_ns = s_to_ns(t_s);
  return true;
}

bool ConfigSection::read_period(const std::string& key, int64_t& t_ns) {
  if (!read_seconds(key, t_ns)) return false;
  if (t_ns <= 0) fail(key, "must be > 0");
  return true;
}

bool ConfigSection::read_degrees(const std::string& key, double& rad) {
  double deg = rad * 180.0 / M_PI;
  if (!read(key, deg)) return false;
  rad = deg * M_PI / 180.0;
  return true;
}

std::vector<std::string> ConfigSection::keys() {
  std::vector<std::string> out;
  if (!node_.IsMap()) return out;
  for (const auto& entry : node_) {
    if (!entry.first.IsScalar())
      throw InputError(file_, line_of(entry.first),
                       "keys must be plain names, got " + describe(entry.first));
    out.push_back(entry.first.Scalar());
    known_.insert(out.back());
  }
  return out;
}

void ConfigSection::finish() const {
  if (!node_.IsMap()) return;
  std::map<std::string, long> first_line;
  for (const auto& entry : node_) {
    const YAML::Node& k = entry.first;
    if (!k.IsScalar())
      throw InputError(file_, line_of(k), "keys must be plain names, got " + describe(k));
    const std::string key = k.Scalar();
    const auto [it, fresh] = first_line.emplace(key, line_of(k));
    if (!fresh)
      throw InputError(file_, line_of(k),
                       "duplicate key '" + qualified(key) + "' (first at line " +
                           std::to_string(it->second) + ")");
    if (!known_.count(key))
      throw InputError(file_, line_of(k),
                       "unknown key '" + qualified(key) + "'" + suggestion(key, known_));
  }
}

void ConfigSection::fail(const std::string& key, const std::string& what) const {
  long line = line_of(node_);
  if (node_.IsMap())
    for (const auto& entry : node_)
      if (entry.first.IsScalar() && entry.first.Scalar() == key) line = line_of(entry.first);
  throw InputError(file_, line, "'" + qualified(key) + "': " + what);
}

void ConfigSection::fail_missing(const std::string& key) const {
  throw InputError(file_, line_of(node_), "missing key '" + qualified(key) + "'");
}

void ConfigSection::type_error(const std::string& key, const YAML::Node& node,
                               const std::string& expected) const {
  throw InputError(file_, line_of(node),
                   "'" + qualified(key) + "': expected " + expected + ", got " + describe(node));
}

void ConfigSection::convert(const std::string& key, const YAML::Node& node, bool& out) const {
  if (!scalar(node, out)) type_error(key, node, "true or false");
}

void ConfigSection::convert(const std::string& key, const YAML::Node& node, int& out) const {
  if (!scalar(node, out)) type_error(key, node, "an integer");
}

void ConfigSection::convert(const std::string& key, const YAML::Node& node, int64_t& out) const {
  long long v = 0;
  if (!scalar(node, v)) type_error(key, node, "an integer");
  out = static_cast<int64_t>(v);
}

void ConfigSection::convert(const std::string& key, const YAML::Node& node, double& out) const {
  if (!scalar(node, out) || !std::isfinite(out)) type_error(key, node, "a finite number");
}

void ConfigSection::convert(const std::string& key, const YAML::Node& node,
                            std::string& out) const {
  if (!scalar(node, out)) type_error(key, node, "a string");
}

template <class T>
void ConfigSection::convert_list(const std::string& key, const YAML::Node& node,
                                 std::vector<T>& out, const std::string& expected) const {
  if (!node.IsSequence()) type_error(key, node, expected);
  std::vector<T> values(node.size());
  for (size_t i = 0; i < node.size(); ++i)
    convert(key + "[" + std::to_string(i) + "]", node[i], values[i]);
  out = std::move(values);
}

void ConfigSection::convert(const std::string& key, const YAML::Node& node,
                            std::vector<double>& out) const {
  convert_list(key, node, out, "a sequence of numbers");
}

void ConfigSection::convert(const std::string& key, const YAML::Node& node,
                            std::vector<int>& out) const {
  convert_list(key, node, out, "a sequence of integers");
}

void ConfigSection::convert(const std::string& key, const YAML::Node& node,
                            std::vector<std::string>& out) const {
  convert_list(key, node, out, "a sequence of strings");
}

size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diag = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] != b[j - 1] ? 1 : 0)});
      diag = up;
    }
  }
  return row[b.size()];
}

}  // namespace hs
