#include "common/config/config_section.h"

#include <gtest/gtest.h>

#include "common/config/yaml_file.h"
#include "tests/config/config_test_util.h"

namespace hs {
namespace {

using test::expect_input_error;
using test::TempYaml;

struct DemoOptions {
  int max_features = 100;
  double threshold = 0.5;
  bool enabled = false;
  std::string name = "default";
  std::vector<double> gains = {1.0};
  int64_t window_ns = 0;
  int64_t timeout_ns = 2'000'000'000;
  int64_t period_ns = 1'000'000'000;
};

DemoOptions load_demo(const std::string& path) {
  DemoOptions o;
  ConfigSection top = ConfigSection::load(path);
  top.section("demo", [&](ConfigSection& s) {
    s.read("max_features", o.max_features);
    s.read("threshold", o.threshold);
    s.read("enabled", o.enabled);
    s.read("name", o.name);
    s.read("gains", o.gains);
    s.read("window_ns", o.window_ns);
    s.read_seconds("timeout_s", o.timeout_ns);
    s.read_period("period_s", o.period_ns);
  });
  top.finish();
  return o;
}

TEST(ConfigSection, ReadsTypedKeysAndKeepsDefaults) {
  TempYaml f(
      "demo:\n  max_features: 250\n  enabled: true\n  gains: [0.5, 2]\n"
      "  window_ns: 5000000000\n");
  const DemoOptions o = load_demo(f.path());
  EXPECT_EQ(o.max_features, 250);
  EXPECT_TRUE(o.enabled);
  ASSERT_EQ(o.gains.size(), 2u);
  EXPECT_DOUBLE_EQ(o.gains[1], 2.0);
  EXPECT_EQ(o.window_ns, 5000000000LL);
  EXPECT_DOUBLE_EQ(o.threshold, DemoOptions().threshold);
  EXPECT_EQ(o.name, DemoOptions().name);
}

TEST(ConfigSection, APeriodMustBePositive) {
  TempYaml f("demo:\n  period_s: 0.25\n");
  EXPECT_EQ(load_demo(f.path()).period_ns, 250'000'000);
  TempYaml zero("demo:\n  max_features: 1\n  period_s: 0\n");
  expect_input_error([&] { load_demo(zero.path()); }, {zero.path() + ":3", "period_s", "> 0"});
}

TEST(ConfigSection, SecondsKeyBecomesNanoseconds) {
  TempYaml f("demo:\n  timeout_s: 0.0015\n");
  EXPECT_EQ(load_demo(f.path()).timeout_ns, 1'500'000);
  TempYaml none("demo:\n  max_features: 1\n");
  EXPECT_EQ(load_demo(none.path()).timeout_ns, DemoOptions().timeout_ns);
  TempYaml bad("demo:\n  timeout_s: soon\n");
  expect_input_error([&] { load_demo(bad.path()); }, {bad.path() + ":2:", "timeout_s"});
}

TEST(ConfigSection, EmptyFileGivesDefaults) {
  TempYaml f("# nothing\n");
  EXPECT_EQ(load_demo(f.path()).max_features, DemoOptions().max_features);
}

TEST(ConfigSection, UnknownKeyNamesFileLineAndClosestKey) {
  TempYaml f("demo:\n  max_features: 3\n  treshold: 0.1\n");
  expect_input_error([&] { load_demo(f.path()); },
                     {f.path() + ":3:", "unknown key 'demo.treshold'", "did you mean 'threshold'"});
}

TEST(ConfigSection, UnknownKeyFarFromAnyListsKnownKeys) {
  TempYaml f("demo:\n  zzzzzzzzzzzz: 1\n");
  expect_input_error([&] { load_demo(f.path()); },
                     {f.path() + ":2:", "known keys:", "max_features"});
}

TEST(ConfigSection, UnknownTopLevelSection) {
  TempYaml f("demo:\n  enabled: true\ndemoo:\n  enabled: false\n");
  expect_input_error([&] { load_demo(f.path()); }, {f.path() + ":3:", "did you mean 'demo'"});
}

TEST(ConfigSection, WrongTypesAreRejectedWithLine) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"demo:\n  max_features: 2.5\n", "expected an integer, got '2.5'"},
      {"demo:\n  max_features: many\n", "expected an integer"},
      {"demo:\n  threshold: abc\n", "expected a finite number, got 'abc'"},
      {"demo:\n  threshold: .nan\n", "expected a finite number"},
      {"demo:\n  enabled: 7\n", "expected true or false"},
      {"demo:\n  name: [a, b]\n", "expected a string, got a sequence"},
      {"demo:\n  gains: 3\n", "expected a sequence of numbers"},
      {"demo:\n  gains: [1, x]\n", "'demo.gains[1]': expected a finite number, got 'x'"},
  };
  for (const auto& [text, part] : cases) {
    TempYaml f(text);
    expect_input_error([&] { load_demo(f.path()); }, {f.path() + ":2:", part});
  }
}

TEST(ConfigSection, SectionMustBeAMapping) {
  TempYaml f("demo: 5\n");
  expect_input_error([&] { load_demo(f.path()); }, {f.path() + ":1:", "expected a mapping"});
}

TEST(ConfigSection, DuplicateKeyIsRejected) {
  TempYaml f("demo:\n  enabled: true\n  enabled: false\n");
  expect_input_error([&] { load_demo(f.path()); },
                     {f.path() + ":3:", "duplicate key 'demo.enabled'", "first at line 2"});
}

TEST(ConfigSection, MissingRequiredKey) {
  TempYaml f("other: 1\n");
  ConfigSection top = ConfigSection::load(f.path());
  expect_input_error([&] { top.require<int>("count"); }, {f.path(), "missing key 'count'"});
}

TEST(ConfigSection, FailPointsAtTheKeyLine) {
  TempYaml f("a: 1\nrate_hz: -3\n");
  ConfigSection top = ConfigSection::load(f.path());
  const double rate = top.require<double>("rate_hz");
  EXPECT_DOUBLE_EQ(rate, -3.0);
  expect_input_error([&] { top.fail("rate_hz", "must be positive"); },
                     {f.path() + ":2:", "'rate_hz': must be positive"});
}

TEST(YamlFile, MissingFileIsAnInputError) {
  expect_input_error([] { load_yaml_file("/nonexistent/hs/config.yaml"); },
                     {"/nonexistent/hs/config.yaml", "cannot open file"});
}

TEST(YamlFile, SyntaxErrorNamesTheLine) {
  TempYaml f("a: 1\nb: [1, 2\nc: 3\n");
  expect_input_error([&] { load_yaml_file(f.path()); }, {f.path() + ":", "YAML syntax error"});
}

TEST(YamlFile, OpenCvHeaderIsStrippedAndLinesKept) {
  TempYaml f("%YAML:1.0\nrate_hz: 20\nbogus: 1\n");
  ConfigSection top = ConfigSection::load(f.path());
  EXPECT_EQ(top.require<int>("rate_hz"), 20);
  expect_input_error([&] { top.finish(); }, {f.path() + ":3:", "unknown key 'bogus'"});
}

TEST(YamlFile, ReadsARealEurocSensorFile) {
  const std::string path =
      HS_SOURCE_DIR "/tests/data/euroc_v1_01_static_sample/mav0/cam0/sensor.yaml";
  ConfigSection top = ConfigSection::load(path);
  std::vector<int> resolution;
  ASSERT_TRUE(top.read("resolution", resolution));
  ASSERT_EQ(resolution.size(), 2u);
  EXPECT_EQ(resolution[0], 752);
  EXPECT_EQ(resolution[1], 480);
  std::vector<double> data;
  top.section("T_BS", [&](ConfigSection& s) {
    EXPECT_EQ(s.require<int>("rows"), 4);
    EXPECT_EQ(s.require<int>("cols"), 4);
    data = s.require<std::vector<double>>("data");
  });
  EXPECT_EQ(data.size(), 16u);
  EXPECT_DOUBLE_EQ(data[15], 1.0);
}

TEST(EditDistance, Basics) {
  EXPECT_EQ(edit_distance("", "abc"), 3u);
  EXPECT_EQ(edit_distance("treshold", "threshold"), 1u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(edit_distance("same", "same"), 0u);
}

}  // namespace
}  // namespace hs
