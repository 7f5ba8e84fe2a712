#include "core/heap_release.h"

#include <malloc.h>

namespace mavloc {

void ReleaseFreeHeapPages() { malloc_trim(0); }

}  // namespace mavloc
