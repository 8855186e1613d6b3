#include "AllocationCounter.h"

#include <cstdlib>
#include <new>

namespace
{
thread_local bool countingAllocations = false;
}

namespace jawari::test
{
std::atomic<long> allocations{0};
void countAllocationsOnThisThread(bool on)
{
    countingAllocations = on;
}
}  // namespace jawari::test

using jawari::test::allocations;

void* operator new(std::size_t size)
{
    if (countingAllocations)
        ++allocations;
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
    if (countingAllocations)
        ++allocations;
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
