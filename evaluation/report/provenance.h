// What the provenance of every report starts from: the command line of this process, mavloc's
// version and the time since the command started.
#pragma once

#include <string>

#include "evaluation/report/report.h"

namespace mavloc {

// Call once from main(): remembers the arguments (quoted where a shell would need it, for a
// command line a user can copy) and the start time.
void RecordInvocation(int argc, const char* const* argv);

std::string InvocationText();  // "mavloc compare --scenario ..."; "mavloc" when not recorded
std::string MavlocVersion();
double SecondsSinceInvocation();

// The provenance with command, version and elapsed time filled in where they are empty.
Provenance WithInvocation(Provenance provenance);

}  // namespace mavloc
