#pragma once
// Counts the locks a thread marked real-time takes (AllocationCounter.h's marks and counts):
// LockCounter.cpp, linked into jawari-realtime-tests only, defines pthread's lock functions, each
// counting the call and forwarding it to glibc's (the next definition, dlsym(RTLD_NEXT)). Linux and
// glibc only, and not under a sanitizer, which interposes them itself.

#include <cstddef>  // glibc's <features.h>: __GLIBC__

#if defined(__linux__) && defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
#define JAWARI_COUNTS_LOCKS 1
#endif

namespace jawari::test
{
#ifdef JAWARI_COUNTS_LOCKS
inline constexpr bool kCountsLocks = true;
#else
inline constexpr bool kCountsLocks = false;
#endif
}  // namespace jawari::test
