// Returning freed heap pages to the system between large phases of work, or keeping them for
// reuse when the whole run is small.
#pragma once

#include <cstddef>

namespace lodbake {

// Hands the heap pages freed so far back to the system. glibc keeps them in the arenas of the
// threads that freed them (and after a large free raises its mmap threshold, so later large
// buffers come from the heap as well): the next phase's peak would sit on top of them. Where a
// phase ends (a stage, a large factorisation, a level's measure or build) and the next allocates
// afresh, this keeps the resident peak that of the largest phase, not of their sum. With jemalloc
// (the tools' allocator where it is installed) every arena's freed pages are purged instead.
// No-op with any other allocator outside glibc, and while freed pages are kept.
void returnFreedPages();

// Inputs below this many triangles keep their freed pages (keepFreedPages).
constexpr size_t kKeepFreedPagesBelow = 250000;

// Whether freed pages stay with the allocator for the next allocations: no purges (then
// returnFreedPages does nothing) and, with jemalloc, no timed return of idle pages either. The
// purges hold a large input's peak near what it has live; on a small input they only make the
// next phase fault the same pages in again (each one zeroed by the kernel anew) for a peak far
// from any limit. Set from the input's size (kKeepFreedPagesBelow) by the stages as they load it;
// allocator settings only, so outputs never change.
void keepFreedPages(bool keep);

}  // namespace lodbake
