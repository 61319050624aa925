#pragma once
// The C library's allocator tuned for a short-lived solver process: call once, first thing in
// main() (the liftoff executable and the benches), before anything allocates.
//
// Why: a tolerance run allocates and frees the same few buffers of 10 kB - 10 MB level after
// level (discretisations, band storage, the certificate's system). With glibc's defaults a
// buffer above the mmap threshold (128 kB, rising) is mapped and unmapped each time and the
// heap's top is trimmed above 128 kB, so each new buffer is paid for again in kernel page
// faults (13-16 % of `liftoff solve --tolerance 1e-8` on the seed beams, profiled). Below the
// thresholds set here the freed memory stays in the process and is reused; a process that solves
// one scene and exits gives it back at exit. Elsewhere than glibc this does nothing.

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace liftoff {

inline void tune_allocator() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 256 * 1024 * 1024);  // larger buffers (a 1e6-element band) still mapped
  mallopt(M_TRIM_THRESHOLD, 1024 * 1024 * 1024);
#endif
}

}  // namespace liftoff
