#include "lodbake/core/free_pages.h"

#include <atomic>
#include <cstdlib>  // any C library header defines __GLIBC__ where glibc is the C library

#if defined(LODBAKE_HAVE_JEMALLOC)
#include <jemalloc/jemalloc.h>

#include <mutex>
#include <string>
#include <sys/types.h>
#elif defined(__GLIBC__)
#include <malloc.h>
#endif

namespace lodbake {
namespace {

std::atomic<bool> kept{false};

#if defined(LODBAKE_HAVE_JEMALLOC)
// jemalloc's decay times (ms; -1 = never) for arenas made from now on and for every existing one.
void setDecay(ssize_t dirty, ssize_t muzzy) {
    mallctl("arenas.dirty_decay_ms", nullptr, nullptr, &dirty, sizeof(dirty));
    mallctl("arenas.muzzy_decay_ms", nullptr, nullptr, &muzzy, sizeof(muzzy));
    unsigned arenas = 0;
    size_t size = sizeof(arenas);
    if (mallctl("arenas.narenas", &arenas, &size, nullptr, 0) != 0) return;
    for (unsigned a = 0; a < arenas; ++a) {
        const std::string arena = "arena." + std::to_string(a);
        // Arenas not yet initialised refuse: they take the defaults set above.
        mallctl((arena + ".dirty_decay_ms").c_str(), nullptr, nullptr, &dirty, sizeof(dirty));
        mallctl((arena + ".muzzy_decay_ms").c_str(), nullptr, nullptr, &muzzy, sizeof(muzzy));
    }
}
#endif

}  // namespace

void returnFreedPages() {
    if (kept.load()) return;
#if defined(LODBAKE_HAVE_JEMALLOC)
    // Every arena's dirty pages at once (jemalloc otherwise returns them after a delay).
    static const std::string purgeAll = "arena." + std::to_string(MALLCTL_ARENAS_ALL) + ".purge";
    mallctl(purgeAll.c_str(), nullptr, nullptr, nullptr, 0);
#elif defined(__GLIBC__)
    malloc_trim(0);
#endif
}

void keepFreedPages(bool keep) {
#if defined(LODBAKE_HAVE_JEMALLOC)
    // The configured decay times, read before the first change, come back when pages are no
    // longer kept.
    static std::mutex mutex;
    static bool read = false;
    static ssize_t dirty = 10000, muzzy = 0;
    std::lock_guard<std::mutex> lock(mutex);
    if (!read) {
        size_t size = sizeof(ssize_t);
        mallctl("arenas.dirty_decay_ms", &dirty, &size, nullptr, 0);
        size = sizeof(ssize_t);
        mallctl("arenas.muzzy_decay_ms", &muzzy, &size, nullptr, 0);
        read = true;
    }
    if (keep == kept.load()) return;
    kept.store(keep);
    if (keep) setDecay(-1, -1);
    else setDecay(dirty, muzzy);
#else
    kept.store(keep);
#endif
}

}  // namespace lodbake
