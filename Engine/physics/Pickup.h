#pragma once
// What the pickup reads off the string.

namespace jawari
{

enum class PickupQuantity
{
    displacement,  // m
    velocity,      // m/s
    force          // N, on the termination at x = 0
};

}  // namespace jawari
