#include "evaluation/report/report_folder.h"

#include <filesystem>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/interrupt.h"
#include "evaluation/report/provenance.h"
#include "evaluation/report/report_json.h"
#include "evaluation/report/report_markdown.h"

namespace mavloc {

std::string ReportJsonText(const Report& report) {
  Report complete = report;
  complete.provenance = WithInvocation(report.provenance);
  return ReportToJson(complete).dump(2) + "\n";
}

void WriteReport(const std::string& folder, Report report) {
  report.provenance = WithInvocation(report.provenance);
  std::error_code error;
  CreateOutputDirectories(folder, error);
  if (error || !std::filesystem::is_directory(folder))
    throw InputError(folder, 0, "",
                     "cannot create report folder" + (error ? ": " + error.message() : ""));
  const auto path = [&](const std::string& name) {
    return (std::filesystem::path(folder) / name).string();
  };
  for (const auto& [name, contents] : report.files) WriteFileAtomically(path(name), contents);
  WriteFileAtomically(path("report.json"), ReportToJson(report).dump(2) + "\n");
  WriteFileAtomically(path("report.md"), RenderReportMarkdown(report));
}

}  // namespace mavloc
