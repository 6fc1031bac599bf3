// Tests core/fit/fit_options.*: FitOptionTable against FitOptions (every
// field with a valid default, the recorded ones of matching type, keys and
// flags unique), CheckFitOptions by the table's ranges, RecordFitOptions by
// its recorded entries, and docs/CLI.md documenting every flag.
#include "sdcb/core/fit/fit_options.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <variant>

namespace sdcb {
namespace {

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(FitOptionTableTest, KeysAndFlagsAreUniqueAndDefaultsValid) {
  std::set<std::string> keys, flags;
  for (const FitOptionDescriptor& d : FitOptionTable()) {
    EXPECT_TRUE(keys.insert(d.key).second) << d.key;
    if (d.flag != nullptr) {
      EXPECT_TRUE(flags.insert(d.flag).second) << d.flag;
      EXPECT_FALSE(std::string(d.help).empty()) << d.key;
    }
    // A recorded field has the option's type (int, double, bool).
    if (!std::holds_alternative<std::monostate>(d.recorded)) {
      EXPECT_EQ(d.recorded.index(), d.field.index() + 1) << d.key;
    }
    if (d.required_in_record) {
      EXPECT_FALSE(std::holds_alternative<std::monostate>(d.recorded));
    }
    // The flag's range lies within the option's (a switch has none).
    if (d.flag != nullptr && d.value_name != nullptr) {
      EXPECT_TRUE(d.range.Contains(d.flag_hi)) << d.key;
      EXPECT_TRUE(d.range.Contains(d.flag_lo) || d.range.zero_too) << d.key;
    }
  }
  // Every field of FitOptions but the progress callback.
  EXPECT_EQ(FitOptionTable().size(), 28u);
  EXPECT_TRUE(CheckFitOptions(FitOptions()).ok());
}

// Each option just outside its range is refused, naming the option.
TEST(FitOptionTableTest, CheckFitOptionsRefusesEachOptionOutOfRange) {
  for (const FitOptionDescriptor& d : FitOptionTable()) {
    FitOptions o;
    const double bad = std::isinf(d.range.lo) ? std::nan("") : d.range.lo - 1;
    if (const auto* f = std::get_if<int FitOptions::*>(&d.field)) {
      int& value = o.**f;
      value = static_cast<int>(bad == 0 ? -1 : bad);
    } else if (const auto* g = std::get_if<double FitOptions::*>(&d.field)) {
      double& value = o.**g;
      value = d.range.lo_open ? d.range.lo : bad;
    } else if (const auto* l =
                   std::get_if<std::vector<double> FitOptions::*>(&d.field)) {
      std::vector<double>& value = o.**l;
      value = {1.0, d.range.lo};
    } else if (const auto* e = std::get_if<BasisForm FitOptions::*>(&d.field)) {
      BasisForm& value = o.**e;
      value = static_cast<BasisForm>(7);
    } else {
      continue;  // bools have no range
    }
    const Status s = CheckFitOptions(o);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << d.key;
    EXPECT_NE(s.message().find(d.key), std::string::npos) << s.message();
  }
}

// Each recorded option reaches its field of the record.
TEST(FitOptionTableTest, RecordFitOptionsHoldsEveryRecordedOption) {
  int recorded = 0;
  for (const FitOptionDescriptor& d : FitOptionTable()) {
    if (std::holds_alternative<std::monostate>(d.recorded)) continue;
    ++recorded;
    FitOptions o;
    if (const auto* f = std::get_if<int FitOptions::*>(&d.field)) {
      int& value = o.**f;
      value += 1;
      EXPECT_EQ(
          RecordFitOptions(o).*std::get<int RecordedFitOptions::*>(d.recorded),
          o.**f)
          << d.key;
    } else if (const auto* g = std::get_if<double FitOptions::*>(&d.field)) {
      double& value = o.**g;
      value = value * 0.5 + 0.125;
      EXPECT_EQ(RecordFitOptions(o).*
                    std::get<double RecordedFitOptions::*>(d.recorded),
                o.**g)
          << d.key;
    } else {
      bool FitOptions::*b = std::get<bool FitOptions::*>(d.field);
      o.*b = !(o.*b);
      EXPECT_EQ(
          RecordFitOptions(o).*std::get<bool RecordedFitOptions::*>(d.recorded),
          o.*b)
          << d.key;
    }
  }
  EXPECT_EQ(recorded, 23);
  // Which change a model's bytes though stored otherwise or not at all:
  // retry_*: the record holds the map_vertices and lambda of the fit that
  // made the model; basis_form: SplineModel::basis_form; store_parameters:
  // SplineModel::parameters; threads changes no byte.
  const RecordedFitOptions r = RecordFitOptions(FitOptions());
  EXPECT_EQ(r.feature_angle_degrees, 30.0);
  EXPECT_TRUE(r.keep_features);
  EXPECT_EQ(r.max_error_percent, 0.5);  // as applied: 10 x rmse
}

// docs/CLI.md documents every flag of the table ("`--rmse PCT`").
TEST(FitOptionTableTest, CliDocsListEveryFlag) {
  const std::string docs = ReadText(SDCB_SOURCE_DIR "/docs/CLI.md");
  ASSERT_FALSE(docs.empty());
  for (const FitOptionDescriptor& d : FitOptionTable()) {
    if (d.flag == nullptr) continue;
    EXPECT_NE(docs.find("`--" + std::string(d.flag)), std::string::npos)
        << "docs/CLI.md lacks --" << d.flag;
  }
}

}  // namespace
}  // namespace sdcb
