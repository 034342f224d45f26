// Returning freed heap pages to the system between large phases of work.
#pragma once

namespace lodbake {

// Hands the heap pages freed so far back to the system. glibc keeps them in the arenas of the
// threads that freed them (and after a large free raises its mmap threshold, so later large
// buffers come from the heap as well): the next phase's peak would sit on top of them. Where a
// phase ends (a stage, a large factorisation, a level's measure or build) and the next allocates
// afresh, this keeps the resident peak that of the largest phase, not of their sum. With jemalloc
// (the tools' allocator where it is installed) every arena's freed pages are purged instead.
// No-op with any other allocator outside glibc.
void returnFreedPages();

}  // namespace lodbake
