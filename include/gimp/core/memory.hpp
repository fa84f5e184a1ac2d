// Returning freed memory to the system between phases.
#pragma once

#include <cstdlib> // (defines __GLIBC__ with the GNU C library)

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace gimp {

/// Hands the heap's free pages back to the system (glibc: malloc_trim). Large arrays freed in
/// the middle of the heap otherwise stay resident: the stencils released before a frame would
/// still count while the frame's buffers are written, and the frame's buffers while the next
/// steps' stencils are built. A no-op where the C library has no such call.
inline void returnFreeMemory() {
#if defined(__GLIBC__)
  (void)malloc_trim(0);
#endif
}

} // namespace gimp
