// The catalogue of options (gdm/option_catalogue.h): one name, range and
// default per option, the range check validate() runs.
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>
#include <limits>
#include <set>

#include "gdm/deformer.h"
#include "gdm/errors.h"
#include "gdm/option_catalogue.h"
#include "gdm/pipeline.h"

namespace {

using namespace gdm;

// A value just outside the option's range, or NaN when it has no outside.
double outside_value(const OptionInfo& o) {
  if (o.type == OptionType::boolean) return std::numeric_limits<double>::quiet_NaN();
  if (o.type == OptionType::choice) return o.hi + 1.0;
  if (std::isfinite(o.hi)) return o.hi_open ? o.hi : o.hi + 1.0;
  return o.lo_open ? o.lo : o.lo - 1.0;
}

Volume step_volume() {
  std::vector<float> values(8 * 8 * 8);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = (i % 8) < 4 ? 0.0f : 100.0f;
  return Volume({8, 8, 8}, values);
}

TEST(OptionCatalogue, names_are_unique_snake_case_with_help) {
  std::set<std::string> names;
  for (const auto& o : pipeline_option_catalogue()) {
    EXPECT_TRUE(names.insert(o.name).second) << o.name;
    if (!o.alias.empty()) EXPECT_TRUE(names.insert(o.alias).second) << o.alias;
    for (const char c : o.name) EXPECT_TRUE(std::islower(static_cast<unsigned char>(c)) || std::isdigit(c) || c == '_') << o.name;
    EXPECT_FALSE(o.help.empty()) << o.name;
    EXPECT_FALSE(o.group.empty()) << o.name;
  }
}

TEST(OptionCatalogue, every_default_is_accepted_and_round_trips) {
  const DeformOptions defaults;
  for (const auto& o : deform_option_catalogue()) {
    const double v = o.get(defaults);
    EXPECT_TRUE(accepts(o, v)) << o.name << " = " << v << " is not " << range_text(o);
    DeformOptions copy;
    o.set(copy, v);
    EXPECT_EQ(o.get(copy), v) << o.name;
  }
}

TEST(OptionCatalogue, validate_names_the_option_out_of_range) {
  const Volume volume = step_volume();
  for (const auto& o : deform_option_catalogue()) {
    const double bad = outside_value(o);
    if (std::isnan(bad)) continue;
    DeformOptions options;
    options.threshold = 50.0;
    ASSERT_NO_THROW(validate(options, volume));
    try {
      // An integer or choice field refuses at once a value it cannot hold
      // (a choice past the last, 2^31 for an int); the others validate() names.
      o.set(options, bad);
      validate(options, volume);
      ADD_FAILURE() << o.name << " = " << bad << " was accepted";
    } catch (const InvalidOption& e) {
      EXPECT_EQ(e.option(), o.name);
      EXPECT_NE(std::string(e.what()).find(o.name + " must be"), std::string::npos) << e.what();
    }
  }
}

TEST(OptionCatalogue, special_values_and_nan) {
  const auto& all = deform_option_catalogue();
  const auto find = [&](const std::string& name) -> const OptionInfo& {
    for (const auto& o : all)
      if (o.name == name) return o;
    throw std::runtime_error("no option " + name);
  };
  const OptionInfo& tolerance = find("lod_tolerance");
  EXPECT_TRUE(accepts(tolerance, 0.0));
  EXPECT_FALSE(accepts(tolerance, 0.001));
  EXPECT_TRUE(accepts(tolerance, 0.01));
  EXPECT_EQ(range_text(tolerance), "0 (off) or in [0.01, 10]");
  const OptionInfo& ratio = find("max_topology_ratio");
  EXPECT_TRUE(accepts(ratio, std::numeric_limits<double>::infinity()));
  EXPECT_FALSE(accepts(ratio, 0.0));
  EXPECT_EQ(range_text(ratio), "> 0 (inf = off)");
  const OptionInfo& a0 = find("a0");
  EXPECT_FALSE(accepts(a0, std::numeric_limits<double>::infinity()));  // a no-op run otherwise
  EXPECT_FALSE(accepts(a0, std::numeric_limits<double>::quiet_NaN()));
  const OptionInfo& passes = find("fit_passes");
  EXPECT_FALSE(accepts(passes, 2.5));
  EXPECT_EQ(range_text(find("mode")), "grow or shrink");
}

TEST(OptionCatalogue, pipeline_catalogue_reaches_the_deform_options) {
  PipelineOptions options;
  for (const auto& o : pipeline_option_catalogue())
    if (o.name == "lod_face_area") o.set(options, 25.0);
  EXPECT_EQ(options.deform.lod_face_area, 25.0);
  options.seed.level = 5;
  try {
    validate(options);
    ADD_FAILURE() << "seed level 5 accepted";
  } catch (const InvalidOption& e) {
    EXPECT_EQ(e.option(), "seed_level");
  }
}

TEST(OptionCatalogue, docs_options_md_is_generated_from_the_catalogue) {
  std::ifstream in(GDM_SOURCE_DIR "/docs/options.md");
  ASSERT_TRUE(in) << "docs/options.md is missing";
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), options_markdown())
      << "docs/options.md is stale: run build/common/gdm_options_markdown > docs/options.md";
}

}  // namespace
