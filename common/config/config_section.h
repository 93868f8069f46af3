#pragma once
// Strict, typed reading of one YAML mapping of a config file. A module's options loader reads
// the keys it knows (each read also declares the key as known), then calls finish(), which
// rejects any other key with file:line and the closest known key, so typos never pass silently:
//
//   ConfigSection top = ConfigSection::load(path);
//   top.section("tracker", [&](ConfigSection& s) { s.read("max_features", opt.max_features); });
//   top.finish();
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <set>
#include <string>
#include <vector>

namespace hs {

class ConfigSection {
 public:
  // `node` must be a mapping, or null (an empty section). `name` prefixes key names in errors.
  ConfigSection(std::string file, YAML::Node node, std::string name);
  // The top-level mapping of a YAML file (see load_yaml_file). An empty file is an empty section.
  static ConfigSection load(const std::string& path);

  // Optional key: assigns `value` if the key is present, leaves the default otherwise.
  // Returns whether it was present. Throws InputError (file:line, key) on a wrong type.
  template <class T>
  bool read(const std::string& key, T& value) {
    const YAML::Node node = lookup(key);
    if (!node) return false;
    convert(key, node, value);
    return true;
  }

  // Optional duration key given in seconds, stored as int64 nanoseconds.
  bool read_seconds(const std::string& key, int64_t& t_ns);
  // As read_seconds, for a period: fails (file:line) unless it is > 0.
  bool read_period(const std::string& key, int64_t& t_ns);
  // A value in degrees into radians.
  bool read_degrees(const std::string& key, double& rad);

  // Mandatory key.
  template <class T>
  T require(const std::string& key) {
    T value{};
    if (!read(key, value)) fail_missing(key);
    return value;
  }

  // Optional nested mapping: when present, `reader(ConfigSection&)` reads it and it is finished.
  template <class F>
  void section(const std::string& key, F&& reader) {
    const YAML::Node node = lookup(key);
    if (!node) return;
    ConfigSection child(file_, node, qualified(key));
    reader(child);
    child.finish();
  }

  // The mapping's keys in file order, each declared known: for sections whose keys are names
  // chosen by the user (e.g. one entry per process). Pair with section(key, ...).
  std::vector<std::string> keys();

  // Throws InputError naming the first unknown or duplicated key.
  void finish() const;

  // For checks a loader makes after reading (ranges, consistency): InputError at the key's line.
  [[noreturn]] void fail(const std::string& key, const std::string& what) const;

  const std::string& file() const { return file_; }

 private:
  YAML::Node lookup(const std::string& key);  // marks `key` known; null node when absent
  std::string qualified(const std::string& key) const;
  [[noreturn]] void fail_missing(const std::string& key) const;
  [[noreturn]] void type_error(const std::string& key, const YAML::Node& node,
                               const std::string& expected) const;
  template <class T>
  void convert_list(const std::string& key, const YAML::Node& node, std::vector<T>& out,
                    const std::string& expected) const;

  void convert(const std::string& key, const YAML::Node& node, bool& out) const;
  void convert(const std::string& key, const YAML::Node& node, int& out) const;
  void convert(const std::string& key, const YAML::Node& node, int64_t& out) const;
  void convert(const std::string& key, const YAML::Node& node, double& out) const;
  void convert(const std::string& key, const YAML::Node& node, std::string& out) const;
  void convert(const std::string& key, const YAML::Node& node, std::vector<double>& out) const;
  void convert(const std::string& key, const YAML::Node& node, std::vector<int>& out) const;
  void convert(const std::string& key, const YAML::Node& node, std::vector<std::string>& out) const;

  std::string file_;
  YAML::Node node_;
  std::string name_;
  std::set<std::string> known_;
};

// Edit distance, for "did you mean" suggestions.
size_t edit_distance(const std::string& a, const std::string& b);

}  // namespace hs
