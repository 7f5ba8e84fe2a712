// report.json's details in SI (evaluation/report/si_details.h): keys with a display-unit suffix and
// objects with a display "unit" are converted, counts, text settings and SI keys are left alone.
#include "evaluation/report/si_details.h"

#include <gtest/gtest.h>

#include "core/rotation.h"

namespace mavloc {
namespace {

TEST(SiDetails, DisplayUnitKeysAndUnitObjectsBecomeSi) {
  const nlohmann::json display = nlohmann::json::parse(R"({
    "tables": {"fig15": {"rows": [{"position_rmse_cm": 2.5, "yaw_rmse_deg": 1.0, "runs": 3}]}},
    "translation_error_xyz_mm": [1.0, -2.0, 3.0],
    "yaw_drift_deg_per_m": 0.5,
    "ape": {"rotation_deg": {"rmse": 2.0, "sse": 8.0, "count": 2}},
    "timing_ms": {"total": 40.0, "rectification": 10.0},
    "settings": {"bearing_noise_deg": "0.5"},
    "quantities": {"roll": {"rmse": 2.0, "paper": 1.0, "per_run": [1.0, 3.0], "count": 7,
                            "unit": "deg"},
                   "x": {"rmse": 0.1, "unit": "m"}},
    "position_rmse_m": 0.2, "ok": true, "note": "x_deg"
  })");
  const nlohmann::json si = DetailsInSi(display);
  const auto& row = si["tables"]["fig15"]["rows"][0];
  EXPECT_DOUBLE_EQ(row["position_rmse_m"].get<double>(), 0.025);
  EXPECT_DOUBLE_EQ(row["yaw_rmse_rad"].get<double>(), kDeg);
  EXPECT_EQ(row["runs"], 3);
  EXPECT_FALSE(row.contains("position_rmse_cm"));
  EXPECT_DOUBLE_EQ(si["translation_error_xyz_m"][1].get<double>(), -2e-3);
  EXPECT_DOUBLE_EQ(si["yaw_drift_rad_per_m"].get<double>(), 0.5 * kDeg);
  EXPECT_DOUBLE_EQ(si["ape"]["rotation_rad"]["rmse"].get<double>(), 2.0 * kDeg);
  EXPECT_DOUBLE_EQ(si["ape"]["rotation_rad"]["sse"].get<double>(), 8.0 * kDeg * kDeg);
  EXPECT_EQ(si["ape"]["rotation_rad"]["count"], 2);
  EXPECT_DOUBLE_EQ(si["timing_s"]["total"].get<double>(), 0.04);
  EXPECT_EQ(si["settings"]["bearing_noise_deg"], "0.5");  // an echoed setting: text, kept
  const auto& roll = si["quantities"]["roll"];
  EXPECT_EQ(roll["unit"], "rad");
  EXPECT_DOUBLE_EQ(roll["rmse"].get<double>(), 2.0 * kDeg);
  EXPECT_DOUBLE_EQ(roll["paper"].get<double>(), kDeg);
  EXPECT_DOUBLE_EQ(roll["per_run"][1].get<double>(), 3.0 * kDeg);
  EXPECT_EQ(roll["count"], 7);
  EXPECT_EQ(si["quantities"]["x"], display["quantities"]["x"]);
  EXPECT_EQ(si["position_rmse_m"], 0.2);
  EXPECT_EQ(si["ok"], true);
  EXPECT_EQ(si["note"], "x_deg");
}

// No key of the result ends in a display unit when it holds numbers.
void ExpectNoDisplayUnits(const nlohmann::json& j, const std::string& path) {
  if (!j.is_object() && !j.is_array()) return;
  for (const auto& [key, value] : j.items()) {
    for (const char* suffix : {"_deg", "_mm", "_cm", "_ms"}) {
      const std::string s(suffix);
      if (key.size() > s.size() && key.compare(key.size() - s.size(), s.size(), s) == 0)
        EXPECT_FALSE(value.is_number()) << path << "/" << key;
    }
    if (j.is_object() && key == "unit") EXPECT_NE(value, "deg") << path;
    ExpectNoDisplayUnits(value, path + "/" + key);
  }
}

TEST(SiDetails, NestedArraysOfObjectsAreConvertedToo) {
  const nlohmann::json display = nlohmann::json::parse(R"({"runs": [
    {"a": {"b_deg": 1.0, "c": [{"d_mm": 2.0, "unit_free": 1}]}, "e": {"unit": "deg", "v": 1.0}}]})");
  const nlohmann::json si = DetailsInSi(display);
  ExpectNoDisplayUnits(si, "");
  EXPECT_DOUBLE_EQ(si["runs"][0]["a"]["c"][0]["d_m"].get<double>(), 2e-3);
}

}  // namespace
}  // namespace mavloc
