// The one writer of report folders: report.json (ReportToJson), report.md (RenderReportMarkdown)
// and the Report's files, each written atomically; the folder is created if needed.
#pragma once

#include <string>

#include "evaluation/report/report.h"

namespace mavloc {

// Fills the provenance's command, version and elapsed time (provenance.h) and writes. Throws
// InputError when the folder cannot be created or written.
void WriteReport(const std::string& folder, Report report);

// report.json as WriteReport writes it (for callers that write one file, e.g. eval --json).
std::string ReportJsonText(const Report& report);

}  // namespace mavloc
