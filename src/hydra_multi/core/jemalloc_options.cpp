// jemalloc's options for every executable that links it (CMakeLists.txt, HYDRA_MULTI_JEMALLOC):
// jemalloc reads this symbol when it starts, and a MALLOC_CONF in the environment after it.
// thp:always: its blocks are given to the kernel as candidates for transparent huge pages
// (madvise), so where the system allows them (transparent_hugepage "madvise" or "always") a
// round's large blocks fault in 2 MB at a time instead of 4 kB (docs/DECISIONS.md: "Transparent
// huge pages for jemalloc's blocks").

extern "C" {
extern const char* malloc_conf;
const char* malloc_conf = "thp:always";
}
