#include "physics/contact/EngagedPoints.h"

#include <algorithm>

namespace jawari
{

void EngagedPoints::prepare(int points, bool enabled)
{
    enabled_ = enabled;
    engaged_.assign(size_t(points), 1);
    anyOut_ = false;
    rows_.assign(size_t(points), 0);
    count_ = 0;
    lanes_.assign(8 * size_t(points), 0.0);
    low_.assign(size_t(points), 0.0);
}

void EngagedPoints::engageAll()
{
    std::fill(engaged_.begin(), engaged_.end(), 1);
    anyOut_ = false;
}

void EngagedPoints::collect(const int* live, int count)
{
    count_ = 0;
    for (int k = 0; k < count; ++k)
        if (engaged_[size_t(live[k])])
            rows_[size_t(count_++)] = live[k];
}

void EngagedPoints::clearLanes(const int* rows, int count)
{
    for (int k = 0; k < count; ++k)
        std::fill_n(lanes_.data() + 8 * size_t(rows[k]), 8, 0.0);
}

}  // namespace jawari
