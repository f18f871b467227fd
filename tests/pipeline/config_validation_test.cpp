// Every config value is type- and range-checked where it enters (JSON files, --set,
// Python dicts, configs built in C++), with messages that name the source and the key path.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "zeroreg/error.hpp"
#include "zeroreg/json.hpp"
#include "zeroreg/register.hpp"

namespace zeroreg {
namespace {

std::string MessageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

TEST(ConfigValidation, DefaultsAreAccepted) {
  EXPECT_NO_THROW(ValidateConfig(PipelineConfig(), "defaults"));
  PipelineConfig round_trip;
  EXPECT_NO_THROW(ApplyConfigJson(ConfigToJson(PipelineConfig()), "defaults", &round_trip));
  EXPECT_EQ(ConfigToJson(round_trip), ConfigToJson(PipelineConfig()));
}

TEST(ConfigValidation, NanAndInfinityAreRefused) {
  // A Python dict can hold NaN; it used to switch the verdict's thresholds off.
  for (double bad : {std::nan(""), std::numeric_limits<double>::infinity()}) {
    PipelineConfig c;
    const nlohmann::json j = {{"ransac", {{"min_inlier_spread_m", bad}}}};
    const std::string m = MessageOf([&] { ApplyConfigJson(j, "config", &c); });
    EXPECT_NE(m.find("config: ransac.min_inlier_spread_m is"), std::string::npos) << m;
  }
}

TEST(ConfigValidation, ConfigsBuiltInCodeAreCheckedByThePipeline) {
  PipelineConfig c;
  c.ransac.min_inlier_ratio = std::nan("");
  const std::string m = MessageOf([&] { Pipeline p(c); });
  EXPECT_NE(m.find("ransac.min_inlier_ratio"), std::string::npos) << m;
  c = PipelineConfig();
  c.match.sinkhorn.temperature = 0;
  const std::string t = MessageOf([&] { Pipeline p(c); });
  EXPECT_NE(t.find("match.sinkhorn.temperature is 0"), std::string::npos) << t;
}

TEST(ConfigValidation, ObjectAppearanceKindIsChecked) {
  PipelineConfig c;
  const std::string unknown = MessageOf([&] {
    ApplyConfigJson({{"objects", {{"appearance", "clip"}}}}, "f.json", &c);
  });
  EXPECT_NE(unknown.find("f.json: objects.appearance is \"clip\"; expected \"auto\", \"colour\" or "
                         "\"sam-embedding\""),
            std::string::npos)
      << unknown;
  // The SAM embedding exists only when SAM segments.
  const std::string without_sam = MessageOf([&] {
    ApplyConfigJson({{"objects", {{"appearance", "sam-embedding"}}}}, "f.json", &c);
  });
  EXPECT_NE(without_sam.find("needs segmenter.backend \"sam\""), std::string::npos) << without_sam;
  EXPECT_NE(without_sam.find("\"depth-grabcut\""), std::string::npos) << without_sam;
  PipelineConfig ok;
  EXPECT_NO_THROW(ApplyConfigJson(
      {{"segmenter", {{"backend", "sam"}}}, {"objects", {{"appearance", "sam-embedding"}}}},
      "f.json", &ok));
  EXPECT_EQ(ok.objects.appearance, "sam-embedding");
  EXPECT_EQ(PipelineConfig().objects.appearance, "auto");
}

TEST(ConfigValidation, IntegersAreExact) {
  PipelineConfig c;
  for (const char* text : {"4294967297", "true", "2.7", "-1", "\"5\""}) {
    const nlohmann::json j = {{"ransac", {{"max_iterations", nlohmann::json::parse(text)}}}};
    const std::string m = MessageOf([&] { ApplyConfigJson(j, "f.json", &c); });
    EXPECT_NE(m.find("f.json: ransac.max_iterations is"), std::string::npos) << text << ": " << m;
  }
  EXPECT_EQ(c.ransac.max_iterations, PipelineConfig().ransac.max_iterations);
  const std::string seed = MessageOf([&] { ApplyConfigOverride("seed=-3", &c); });
  EXPECT_NE(seed.find("--set seed=-3: seed is -3"), std::string::npos) << seed;
  ApplyConfigOverride("seed=18446744073709551615", &c);
  EXPECT_EQ(c.seed, 18446744073709551615ull);
}

}  // namespace
}  // namespace zeroreg

namespace zeroreg {
namespace {

// A removed setting in a config file is refused with what took its place, not merely as an
// unknown key; the one seed is accepted wherever a config enters.
TEST(ConfigValidation, RemovedSettingsNameWhatReplacedThem) {
  const std::vector<std::pair<std::string, std::string>> removed = {
      {"features.xfeat_keep_aspect", "aspect ratio"},
      {"features.xfeat_square_input", "own size"},
      {"features.xfeat_square_contrast", "contrast"},
      {"lift.holes_are_edges", "never a keypoint's depth edge"},
      {"refine.anchor_inverse_variance", "refine.anchor_weight_coarse"},
      {"object_match.seed", "top-level \"seed\""},
      {"segmenter.seed", "top-level \"seed\""},
  };
  for (const auto& [key, replacement] : removed) {
    PipelineConfig c;
    const std::string m = MessageOf([&, key = key] { ApplyConfigOverride(key + "=1", &c); });
    EXPECT_NE(m.find(key + " was removed"), std::string::npos) << m;
    EXPECT_NE(m.find(replacement), std::string::npos) << m;
    EXPECT_EQ(m.find("known keys"), std::string::npos) << m;
    const std::string section = key.substr(0, key.find('.'));
    EXPECT_FALSE(
        ConfigToJson(PipelineConfig()).at(section).contains(key.substr(section.size() + 1)))
        << key;
  }
  // The per-stage copies of the depth model point to the one `depth` key.
  const std::vector<std::pair<std::string, std::string>> moved = {
      {"lift.min_depth_m", "depth.min_m"},
      {"verify.max_depth_m", "depth.max_m"},
      {"lift.depth_edge_relative", "depth.edge_relative"},
      {"segmenter.depth_edge_relative", "depth.edge_relative"},
      {"verify.depth_edge_relative", "depth.edge_relative"},
      {"verify.depth_noise_at_1m_m", "depth.noise_at_1m_m"},
      {"refine.depth_noise_exponent", "depth.noise_exponent"},
  };
  for (const auto& [key, replacement] : moved) {
    PipelineConfig c;
    const std::string m = MessageOf([&, key = key] { ApplyConfigOverride(key + "=1", &c); });
    EXPECT_NE(m.find(key + " moved"), std::string::npos) << m;
    EXPECT_NE(m.find(replacement), std::string::npos) << m;
    EXPECT_EQ(m.find("known keys"), std::string::npos) << m;
  }
  PipelineConfig c;
  ApplyConfigOverride("seed=7", &c);
  EXPECT_EQ(c.seed, 7u);
  ApplyConfigJson(nlohmann::json{{"seed", 11}}, "config", &c);
  EXPECT_EQ(c.seed, 11u);
  // A misspelt key still gets the list of known keys.
  const std::string typo = MessageOf([&] { ApplyConfigOverride("lift.holes_are_edge=1", &c); });
  EXPECT_NE(typo.find("unknown key 'lift.holes_are_edge'; known keys"), std::string::npos) << typo;
}

}  // namespace
}  // namespace zeroreg
