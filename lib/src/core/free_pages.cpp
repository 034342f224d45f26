#include "lodbake/core/free_pages.h"

#include <cstdlib>  // any C library header defines __GLIBC__ where glibc is the C library

#if defined(LODBAKE_HAVE_JEMALLOC)
#include <jemalloc/jemalloc.h>

#include <string>
#elif defined(__GLIBC__)
#include <malloc.h>
#endif

namespace lodbake {

void returnFreedPages() {
#if defined(LODBAKE_HAVE_JEMALLOC)
    // Every arena's dirty pages at once (jemalloc otherwise returns them after a delay).
    static const std::string purgeAll = "arena." + std::to_string(MALLCTL_ARENAS_ALL) + ".purge";
    mallctl(purgeAll.c_str(), nullptr, nullptr, nullptr, 0);
#elif defined(__GLIBC__)
    malloc_trim(0);
#endif
}

}  // namespace lodbake
