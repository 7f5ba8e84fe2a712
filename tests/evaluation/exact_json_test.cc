// The exact JSON of a reproduction's per-run sums: every double comes back bit for bit through
// the JSON text (NaN as null), nested structs and containers included, and a missing field is an
// error rather than a zero.
#include "evaluation/exact_json.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <string>

namespace mavloc {
namespace {

struct Inner {
  double sum = 0.0;
  long count = 0;
};
constexpr auto ExactFields(std::type_identity<Inner>) {
  return std::make_tuple(ExactField("sum", &Inner::sum), ExactField("count", &Inner::count));
}

struct Outer {
  double runtime_s = 0.0;
  int runs = 0;
  Inner position;
  std::map<std::string, int> reasons;
  std::vector<double> samples;
  std::map<std::string, Inner> by_quantity;
  bool converged = false;
};
constexpr auto ExactFields(std::type_identity<Outer>) {
  return std::make_tuple(
      ExactField("runtime_s", &Outer::runtime_s), ExactField("runs", &Outer::runs),
      ExactField("position", &Outer::position), ExactField("reasons", &Outer::reasons),
      ExactField("samples", &Outer::samples), ExactField("by_quantity", &Outer::by_quantity),
      ExactField("converged", &Outer::converged));
}

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(ExactJson, EveryDoubleSurvivesTheTextRoundTrip) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> exponent(-300.0, 300.0);
  for (int trial = 0; trial < 1000; ++trial) {
    Outer value;
    value.runtime_s = std::pow(10.0, exponent(rng)) * (trial % 2 ? 1.0 : -1.0);
    value.runs = trial;
    value.position = {std::nextafter(1.0 / 3.0, 1.0) * trial, trial * 7L};
    value.reasons = {{"no tag", trial}, {"degenerate", 2}};
    value.samples = {0.1, 1e-310, -0.0, std::numeric_limits<double>::max(),
                     std::numeric_limits<double>::quiet_NaN()};
    value.by_quantity = {{"alpha", {value.runtime_s / 7.0, 3}}, {"d", {-1e-17, 0}}};
    value.converged = trial % 3 == 0;
    const Outer back = FromExactJson<Outer>(nlohmann::json::parse(ToExactJson(value).dump()));
    ASSERT_TRUE(SameBits(back.runtime_s, value.runtime_s)) << value.runtime_s;
    EXPECT_EQ(back.runs, value.runs);
    EXPECT_TRUE(SameBits(back.position.sum, value.position.sum));
    EXPECT_EQ(back.position.count, value.position.count);
    EXPECT_EQ(back.reasons, value.reasons);
    ASSERT_EQ(back.samples.size(), value.samples.size());
    for (size_t i = 0; i + 1 < value.samples.size(); ++i)
      EXPECT_TRUE(SameBits(back.samples[i], value.samples[i])) << i;
    EXPECT_TRUE(std::isnan(back.samples.back()));
    ASSERT_EQ(back.by_quantity.size(), 2u);
    EXPECT_TRUE(SameBits(back.by_quantity.at("alpha").sum, value.by_quantity.at("alpha").sum));
    EXPECT_EQ(back.by_quantity.at("alpha").count, 3);
    EXPECT_TRUE(SameBits(back.by_quantity.at("d").sum, -1e-17));
    EXPECT_EQ(back.converged, value.converged);
  }
}

TEST(ExactJson, NotANumberIsWrittenAsNullAndReadBackAsNaN) {
  Inner value{std::numeric_limits<double>::quiet_NaN(), 3};
  const nlohmann::json json = ToExactJson(value);
  EXPECT_TRUE(json.at("sum").is_null());
  EXPECT_TRUE(std::isnan(FromExactJson<Inner>(json).sum));
}

TEST(ExactJson, AMissingOrMistypedFieldIsAnError) {
  EXPECT_THROW(FromExactJson<Inner>(nlohmann::json{{"sum", 1.0}}), nlohmann::json::exception);
  EXPECT_THROW(FromExactJson<Inner>(nlohmann::json{{"sum", "x"}, {"count", 1}}),
               nlohmann::json::exception);
}

}  // namespace
}  // namespace mavloc
