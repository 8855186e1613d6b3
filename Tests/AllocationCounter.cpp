#include "AllocationCounter.h"

#include <cstdlib>
#include <new>

namespace
{
thread_local jawari::test::RealtimeCounts* marked = nullptr;

void countAllocation()
{
    if (marked != nullptr)
        ++marked->allocations;
}
}  // namespace

namespace jawari::test
{
RealtimeCounts audioThreadCounts;
std::atomic<long>& allocations = audioThreadCounts.allocations;

void countOnThisThread(RealtimeCounts* counts)
{
    marked = counts;
}
RealtimeCounts* countsOfThisThread()
{
    return marked;
}
void countAllocationsOnThisThread(bool on)
{
    marked = on ? &audioThreadCounts : nullptr;
}
}  // namespace jawari::test

// The C allocator too (Eigen's temporaries come from std::malloc, not operator new): glibc's
// functions replaced by counting ones that call its own (__libc_*). Not under ASan or TSan, which
// replace them themselves.
#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
#define JAWARI_COUNTS_MALLOC 1
extern "C"
{
    void* __libc_malloc(std::size_t);
    void* __libc_calloc(std::size_t, std::size_t);
    void* __libc_realloc(void*, std::size_t);
    void* __libc_memalign(std::size_t, std::size_t);

    void* malloc(std::size_t size)
    {
        countAllocation();
        return __libc_malloc(size);
    }
    void* calloc(std::size_t count, std::size_t size)
    {
        countAllocation();
        return __libc_calloc(count, size);
    }
    void* realloc(void* p, std::size_t size)
    {
        countAllocation();
        return __libc_realloc(p, size);
    }
    void* aligned_alloc(std::size_t alignment, std::size_t size)
    {
        countAllocation();
        return __libc_memalign(alignment, size);
    }
    int posix_memalign(void** out, std::size_t alignment, std::size_t size)
    {
        countAllocation();
        *out = __libc_memalign(alignment, size);
        return *out != nullptr ? 0 : 12;  // ENOMEM
    }
}
#endif

void* operator new(std::size_t size)
{
#ifndef JAWARI_COUNTS_MALLOC
    countAllocation();
#endif
    if (void* p = std::malloc(size == 0 ? 1 : size))
        return p;
    throw std::bad_alloc();
}
void* operator new[](std::size_t size)
{
    return operator new(size);
}
void* operator new(std::size_t size, std::align_val_t alignment)
{
#ifndef JAWARI_COUNTS_MALLOC
    countAllocation();
#endif
    if (void* p = std::aligned_alloc(static_cast<std::size_t>(alignment),
                                     (size + static_cast<std::size_t>(alignment) - 1)
                                         / static_cast<std::size_t>(alignment) * static_cast<std::size_t>(alignment)))
        return p;
    throw std::bad_alloc();
}
void* operator new[](std::size_t size, std::align_val_t alignment)
{
    return operator new(size, alignment);
}
void operator delete(void* p) noexcept
{
    std::free(p);
}
void operator delete[](void* p) noexcept
{
    std::free(p);
}
void operator delete(void* p, std::size_t) noexcept
{
    std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept
{
    std::free(p);
}
void operator delete(void* p, std::align_val_t) noexcept
{
    std::free(p);
}
void operator delete[](void* p, std::align_val_t) noexcept
{
    std::free(p);
}
void operator delete(void* p, std::size_t, std::align_val_t) noexcept
{
    std::free(p);
}
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept
{
    std::free(p);
}
