// Transparent huge pages for mavloc's own heap. On the virtual machines mavloc often runs on, a
// first touch of a 4 KiB page costs microseconds, and a command that holds a million-pose
// trajectory touches tens of thousands of pages: page faults were a fifth of `eval`'s time.
// glibc's malloc can back its heap and its large blocks with 2 MiB pages (madvise MADV_HUGEPAGE),
// but it reads that choice (the tunable glibc.malloc.hugetlb=1) only from the GLIBC_TUNABLES
// environment variable at start-up. So the process re-executes itself once with the tunable added
// when the kernel offers huge pages on request (/sys/kernel/mm/transparent_hugepage/enabled is
// "madvise"; with "always" the heap gets them anyway, with "never" nothing helps).
// MAVLOC_HUGE_PAGES=0 turns it off. Numbers do not change: only where memory comes from.
#pragma once

namespace mavloc {

// Call first in main, before any thread starts: returns only when no re-execution is needed or
// it failed (then the process goes on with 4 KiB pages).
void ReexecWithHugePages(char** argv);

}  // namespace mavloc
