#include "core/heap.h"

#include <cstdlib>  // defines __GLIBC__ on glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace aamap {

void keepFreedMemoryForReuse() {
#if defined(__GLIBC__)
    // Setting either turns off glibc's dynamic thresholds, so both are set: mmap only what is
    // over 32 MiB (the largest threshold glibc accepts on 64-bit), trim only past 256 MiB free.
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 256 << 20);
#endif
}

}  // namespace aamap
