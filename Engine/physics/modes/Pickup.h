#pragma once
// What the pickup reads off the string.

namespace jawari
{

enum class PickupQuantity
{
    displacement,  // m
    velocity,      // m/s
    force,         // N, on the termination at x = 0
    pressure,      // Pa, the body's radiated sound at the listener (ModalBody.h)
    bridgeForce    // N, what the string pushes on the body's obstacles (every obstacle without a body)
};

}  // namespace jawari
