// Large buffers filled with their pages first touched on several threads. A fresh buffer's pages
// are faulted in (and zeroed by the kernel) as they are first written: filling a page-sized bake
// buffer (a 2048 x 2048 page's texel hits are some 130 MB) on one thread spends most of its time
// there, while the other cores wait. The values written are the plain fill's.
#pragma once

#include <algorithm>
#include <cstddef>
#include <type_traits>
#include <vector>

#include "lodbake/core/parallel.h"

namespace lodbake {

namespace touched_detail {

constexpr size_t kPage = 4096;
constexpr size_t kChunkBytes = size_t(1) << 22;  // pages touched per task: 4 MB
constexpr size_t kMinBytes = size_t(1) << 23;    // smaller buffers are filled as they are

// Writes one byte of every page of [p, p + bytes) (storage allocated for the buffer, no object in it
// yet), the pages split between the threads.
inline void touchPages(unsigned char* p, size_t bytes, int threads) {
    parallelChunks(bytes, kChunkBytes, threads, [&](size_t begin, size_t end, size_t) {
        for (size_t i = begin; i < end; i += kPage) p[i] = 0;
    });
}

}  // namespace touched_detail

// v.assign(n, value), the new storage's pages first touched on `threads` threads (0 = all cores).
template <class T>
void assignTouched(std::vector<T>& v, size_t n, const T& value, int threads) {
    static_assert(std::is_trivially_copyable_v<T>, "pages are touched in storage that holds no object yet");
    const size_t bytes = n * sizeof(T);
    if (v.capacity() < n && bytes >= touched_detail::kMinBytes && resolveThreads(threads) > 1) {
        std::vector<T>().swap(v);
        v.reserve(n);
        touched_detail::touchPages(reinterpret_cast<unsigned char*>(v.data()), bytes, threads);
    }
    v.assign(n, value);
}

}  // namespace lodbake
