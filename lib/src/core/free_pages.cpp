#include "lodbake/core/free_pages.h"

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
