#pragma once
// The scalar contact equation of ContactLaw.h (r + k G(r) = b) for several strings at once, one
// string per SIMD lane: the solve of solveScalarContact, with its branches as per-lane masks and
// its iterations run until every lane has converged by the same test. Each lane takes the same
// arithmetic as the scalar solve (the rare pow, log, expm1 and sqrt per lane through the same libm
// calls), so a lane's solution is the scalar one. The latency of the chain of divisions is paid
// once for all the lanes (docs/design.md section 5, "The string bank").
//
// The lanes share the law's exponent (and so its DividedSeries); stiffness, k, s and b are per
// lane. RT: no allocation.

#include "physics/contact/ContactLaw.h"

namespace jawari
{

inline constexpr int kContactLanes = 8;  // one AVX-512 register of doubles

struct ContactLaneBatch
{
    int count = 0;  // lanes in use; the rest are solved as out of contact and ignored
    double exponent = 1.3;
    const DividedSeries* series = nullptr;  // dividedSeries(exponent)
    // The equations (ScalarContactRequest's fields, lane by lane).
    alignas(64) double stiffness[kContactLanes] = {};
    alignas(64) double s[kContactLanes] = {};
    alignas(64) double b[kContactLanes] = {};
    alignas(64) double k[kContactLanes] = {};
    alignas(64) double knownX[kContactLanes] = {}, knownXAlpha[kContactLanes] = {}, knownInvX[kContactLanes] = {};
    // The solutions.
    ScalarContactSolution solution[kContactLanes];

    // OFF/RT: adds a request with this batch's exponent to the next lane.
    void add(const ScalarContactRequest& request);
};

// RT: solves the batch's `count` equations; each lane's solution is solveScalarContact's.
void solveContactLanes(ContactLaneBatch& batch);

}  // namespace jawari
