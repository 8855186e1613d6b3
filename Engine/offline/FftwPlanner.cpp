#include "offline/FftwPlanner.h"

namespace jawari
{
std::mutex& fftwPlannerMutex()
{
    static std::mutex m;
    return m;
}
}  // namespace jawari
