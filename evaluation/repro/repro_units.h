// The one runner of the reproductions (RunRepro, declared in repro.h): a definition's units x
// seeds, here or in --jobs sweep workers, each result through its JSON text so that --jobs 1 and
// --jobs N give the same numbers; and the helpers the definitions' summaries share.
#pragma once

#include <string>
#include <vector>

#include "evaluation/repro/repro.h"

namespace mavloc {

// A table whose columns are given as "name [unit]" (SI units; "name" alone for text and counts).
ReportTable ReproTable(const std::string& name, const std::string& title,
                       const std::vector<std::string>& columns);

// A table as CSV for tools: the header "name [unit]" (SI units), numbers with every digit, empty
// cells for null, text quoted as RFC 4180 says when it holds a comma, a quote or a line break.
std::string ReproTableCsv(const ReportTable& table);

}  // namespace mavloc
