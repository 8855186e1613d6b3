#pragma once
// FFTW's planner is not thread-safe (execution of a finished plan is): every plan in Jawari is
// made and destroyed under this one lock. OFF.

#include <mutex>

namespace jawari
{
std::mutex& fftwPlannerMutex();
}
