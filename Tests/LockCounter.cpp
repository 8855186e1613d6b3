#include "LockCounter.h"

#include "AllocationCounter.h"

#ifdef JAWARI_COUNTS_LOCKS
#include <atomic>
#include <cstdlib>
#include <dlfcn.h>
#include <pthread.h>
#include <semaphore.h>

// Every way to take a pthread mutex, rwlock or spin lock, or to wait on a POSIX semaphore
// (std::mutex, std::shared_mutex, std::timed_mutex and std::condition_variable's lock go through
// them: libstdc++'s gthreads call the pthread functions by name). A condition wait needs a mutex
// locked first, counted there. Not seen: futex waits of the atomics' own (std::atomic::wait,
// std::counting_semaphore), which the worker sleeps on by design.
namespace
{
void countLock()
{
    if (jawari::test::RealtimeCounts* counts = jawari::test::countsOfThisThread())
        ++counts->locks;
}

// glibc's function of that name, found once. The slot is constant-initialised (no guard, which
// could itself lock); two threads racing to fill it store the same address.
template <typename Function>
Function next(std::atomic<Function>& slot, const char* name)
{
    Function f = slot.load(std::memory_order_relaxed);
    if (f == nullptr)
    {
        f = reinterpret_cast<Function>(dlsym(RTLD_NEXT, name));
        if (f == nullptr)
            std::abort();
        slot.store(f, std::memory_order_relaxed);
    }
    return f;
}
}  // namespace

// `specifier`: glibc's declaration's (noexcept, or none for a cancellation point).
#define JAWARI_COUNTED_LOCK(name, parameters, arguments, specifier)                                                    \
    int name parameters specifier                                                                                      \
    {                                                                                                                  \
        countLock();                                                                                                   \
        using Real = int(*) parameters specifier; /* without the declaration's attributes (nonnull) */                 \
        static std::atomic<Real> real{nullptr};                                                                        \
        return next(real, #name) arguments;                                                                            \
    }

extern "C"
{
    JAWARI_COUNTED_LOCK(pthread_mutex_lock, (pthread_mutex_t * m), (m), noexcept)
    JAWARI_COUNTED_LOCK(pthread_mutex_trylock, (pthread_mutex_t * m), (m), noexcept)
    JAWARI_COUNTED_LOCK(pthread_mutex_timedlock, (pthread_mutex_t * m, const timespec* t), (m, t), noexcept)
    JAWARI_COUNTED_LOCK(pthread_mutex_clocklock, (pthread_mutex_t * m, clockid_t c, const timespec* t), (m, c, t),
                        noexcept)
    JAWARI_COUNTED_LOCK(pthread_rwlock_rdlock, (pthread_rwlock_t * l), (l), noexcept)
    JAWARI_COUNTED_LOCK(pthread_rwlock_tryrdlock, (pthread_rwlock_t * l), (l), noexcept)
    JAWARI_COUNTED_LOCK(pthread_rwlock_timedrdlock, (pthread_rwlock_t * l, const timespec* t), (l, t), noexcept)
    JAWARI_COUNTED_LOCK(pthread_rwlock_clockrdlock, (pthread_rwlock_t * l, clockid_t c, const timespec* t), (l, c, t),
                        noexcept)
    JAWARI_COUNTED_LOCK(pthread_rwlock_wrlock, (pthread_rwlock_t * l), (l), noexcept)
    JAWARI_COUNTED_LOCK(pthread_rwlock_trywrlock, (pthread_rwlock_t * l), (l), noexcept)
    JAWARI_COUNTED_LOCK(pthread_rwlock_timedwrlock, (pthread_rwlock_t * l, const timespec* t), (l, t), noexcept)
    JAWARI_COUNTED_LOCK(pthread_rwlock_clockwrlock, (pthread_rwlock_t * l, clockid_t c, const timespec* t), (l, c, t),
                        noexcept)
    JAWARI_COUNTED_LOCK(pthread_spin_lock, (pthread_spinlock_t * l), (l), noexcept)
    JAWARI_COUNTED_LOCK(pthread_spin_trylock, (pthread_spinlock_t * l), (l), noexcept)
    JAWARI_COUNTED_LOCK(sem_wait, (sem_t * s), (s), )
    JAWARI_COUNTED_LOCK(sem_trywait, (sem_t * s), (s), noexcept)
    JAWARI_COUNTED_LOCK(sem_timedwait, (sem_t * s, const timespec* t), (s, t), )
    JAWARI_COUNTED_LOCK(sem_clockwait, (sem_t * s, clockid_t c, const timespec* t), (s, c, t), )
}
#endif
