// Returns the heap's free pages to the system. glibc's malloc keeps memory freed in small blocks
// (the per-keyframe matrices of a long log: hundreds of MB) resident in the process, where only a
// later allocation of the same kind can reuse it; a stage that frees such memory and is followed
// by one that allocates differently calls this so that the two stages' memory does not add up.
// Numbers do not change, only the resident size (malloc_trim, glibc).
#pragma once

namespace mavloc {

void ReleaseFreeHeapPages();

}  // namespace mavloc
