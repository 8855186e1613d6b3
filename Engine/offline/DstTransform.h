#pragma once
// The reference's fast path to its contact points (docs/design.md section 2): on the grid
// x_i = i L/(M+1) with every contact point on its own node, q <-> u is a DST-I (FFTW's RODFT00),
// O(M log M) a step instead of O(M P). Many contact points (a sampled bridge) need it; a few do not.

#include "physics/modes/ModalSolver.h"

#include <vector>

namespace jawari
{

enum class ContactPath
{
    automatic,   // the transform when more than 24 points can touch and the grid allows it
    projection,  // the few-point path
    transform    // the DST-I path; an error where the grid does not allow it
};

// Each contact point's grid node on x_i = i L/(M+1), or an empty vector when some point is off
// the grid or two points share a node (then only projection applies).
std::vector<int> distinctGridNodes(const std::vector<ContactPoint>& contacts, double lengthMetres, int modes);

// Sets the solver configuration's transform for the chosen path. OFF.
void chooseContactPath(ModalSolverConfig& config, ContactPath path);

}  // namespace jawari
