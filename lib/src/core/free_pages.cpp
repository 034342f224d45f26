#include "lodbake/core/free_pages.h"

#include <cstdlib>  // any C library header defines __GLIBC__ where glibc is the C library

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace lodbake {

void returnFreedPages() {
#if defined(__GLIBC__)
    malloc_trim(0);
#endif
}

}  // namespace lodbake
