// The results model (evaluation/report/): one Report, one JSON layout with SI values and units, one
// Markdown writer whose tables always have as many cells per row as their header.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>

#include "evaluation/report/report.h"
#include "evaluation/report/report_json.h"
#include "evaluation/report/report_markdown.h"

namespace mavloc {
namespace {

size_t Cells(const std::string& line) {
  size_t bars = 0;
  for (size_t i = 0; i < line.size(); ++i)
    if (line[i] == '|' && (i == 0 || line[i - 1] != '\\')) ++bars;
  return bars - 1;
}

ErrorStatistics Stats(double rmse, size_t count) {
  ErrorStatistics s;
  s.rmse = s.mean = s.median = s.max = rmse;
  s.count = count;
  return s;
}

Report SampleReport() {
  Report report;
  report.kind = "compare";
  report.title = "sample";
  report.protocol = ReportProtocol{};
  EstimatorResult a;
  a.name = "a|b";  // a name holding the table separator
  a.coverage = Coverage{250, 29120, 4.98, 145.6};
  a.metrics["ate_translation"] = {"m", std::nullopt, Stats(0.4, 250)};
  a.metrics["ate_rotation"] = {"rad", std::nullopt, Stats(M_PI / 180.0, 250)};
  a.metrics["roll"] = {"rad", std::nullopt, Stats(0.5 * M_PI / 180.0, 250)};
  a.parameters["time_offset"] = {0.0021, 0.0003, "s"};
  a.frames_without_pose = 3;
  a.rejected_measurements = 9488;
  report.estimators.push_back(a);
  EstimatorResult skipped;
  skipped.name = "pnp";
  skipped.ran = false;
  skipped.skipped_reason = "no tags | no map";
  report.estimators.push_back(skipped);
  return report;
}

TEST(ReportModel, MarkdownTablesEscapeSeparatorsAndKeepTheirColumns) {
  const std::string table = MarkdownTableOf({"|dp| [mm]", "b"}, {{"x|y", "1"}, {"z"}});
  std::istringstream lines(table);
  std::string line;
  while (std::getline(lines, line)) EXPECT_EQ(Cells(line), 2u) << line;
  EXPECT_NE(table.find("\\|dp\\| [mm]"), std::string::npos) << table;
}

TEST(ReportModel, MarkdownShowsRmseCoverageSeparateRejectionsAndDegrees) {
  const std::string md = RenderReportMarkdown(SampleReport());
  std::istringstream lines(md);
  std::string line, header;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] != '|') {
      header.clear();
      continue;
    }
    if (header.empty())
      header = line;
    else
      EXPECT_EQ(Cells(line), Cells(header)) << line << "\nheader: " << header;
  }
  EXPECT_NE(md.find("ATE RMSE [m]"), std::string::npos) << md;
  EXPECT_NE(md.find("rotation RMSE [deg]"), std::string::npos) << md;
  EXPECT_NE(md.find("250/29120 poses, 5.0 of 145.6 s (3 %)"), std::string::npos) << md;
  EXPECT_NE(md.find("| 3 | 9488 |"), std::string::npos) << md;  // apart, not summed
  EXPECT_NE(md.find("| 1 |"), std::string::npos) << md;         // 1 deg, not 0.01745 rad
  EXPECT_NE(md.find("Estimated calibration"), std::string::npos) << md;
  EXPECT_NE(md.find("time_offset"), std::string::npos) << md;
}

TEST(ReportModel, JsonIsSiWithUnitsAndNoNaN) {
  Report report = SampleReport();
  report.estimators[0].metrics["nan"] = {"m", std::numeric_limits<double>::quiet_NaN(),
                                         std::nullopt};
  const nlohmann::json j = ReportToJson(report);
  EXPECT_EQ(j["schema"], kReportSchema);
  const auto& a = j["estimators"][0];
  EXPECT_EQ(a["metrics"]["ate_rotation"]["unit"], "rad");
  EXPECT_NEAR(a["metrics"]["ate_rotation"]["statistics"]["rmse"].get<double>(), M_PI / 180.0,
              1e-15);
  EXPECT_TRUE(a["metrics"]["nan"]["value"].is_null());
  EXPECT_EQ(a["frames_without_pose"], 3);
  EXPECT_EQ(a["rejected_measurements"], 9488);
  EXPECT_NEAR(a["coverage"]["fraction"].get<double>(), 4.98 / 145.6, 1e-12);
  EXPECT_EQ(j["estimators"][1]["ran"], false);
  EXPECT_EQ(j["estimators"][1]["skipped_reason"], "no tags | no map");
  EXPECT_EQ(j.dump().find("NaN"), std::string::npos);
}

}  // namespace
}  // namespace mavloc
