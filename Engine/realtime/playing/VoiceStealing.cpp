#include "realtime/playing/VoiceStealing.h"

#include <limits>

namespace jawari
{

int chooseStolenString(const StringActivity* strings, int count)
{
    int victim = -1;
    double quietest = std::numeric_limits<double>::infinity();
    for (int i = 0; i < count; ++i)
    {
        const auto& s = strings[i];
        if (s.fading || s.held || s.sustained)
            continue;
        if (s.energy < quietest)
        {
            quietest = s.energy;
            victim = i;
        }
    }
    if (victim >= 0)
        return victim;
    uint64_t oldest = std::numeric_limits<uint64_t>::max();
    for (int i = 0; i < count; ++i)
        if (!strings[i].fading && strings[i].age < oldest)
        {
            oldest = strings[i].age;
            victim = i;
        }
    return victim;
}

}  // namespace jawari
