// Writes a whole file or nothing: the text goes to "<path>.tmp-<pid>" which is renamed over path.
// The temporary file is registered with core/interrupt.h, so SIGINT/SIGTERM remove it too.
#pragma once

#include <string>

namespace mavloc {

// Throws InputError when the folder does not exist or the file cannot be written.
void WriteFileAtomically(const std::string& path, const std::string& contents);

}  // namespace mavloc
