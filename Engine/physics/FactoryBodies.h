#pragma once
// The factory bodies (docs/design.md section 1, "The body"): modes derived from a top plate's
// published dimensions and material, their radiation fitted to a published response. OFF.
//
// A recipe gives the plate (area S, thickness h, density rho, Young's modulus E, Poisson's ratio nu,
// loss factor eta) and the measured response's band levels (dB relative to one band). From them:
//  - the frequencies: a thin plate's modes are evenly spaced on average, df = 2 / (S sqrt(rho h / D)),
//    D = E h^3 / (12 (1 - nu^2)), each moved by a deterministic share of the spacing (a plate's modes
//    are not a lattice); a band the spacing leaves empty gets one mode at its centre;
//  - the masses at the bridge: m_k = rho h S / s_k, s_k = psi_k(bridge)^2 for a mass-normalised mode,
//    4 sin^2(pi a_k) sin^2(pi b_k) for a quasi-random point (a_k, b_k) of the R2 sequence, whose mean
//    is 1: the plate's mean driving-point mobility is the infinite plate's (Cremer & Heckl);
//  - the damping: sigma_k = pi f_k eta;
//  - the radiation: c_k proportional to sqrt(m_k / (rho h S)) (a mode with a small amplitude at the
//    bridge radiates its volume all the same) with a deterministic sign, scaled by the bands' gains
//    (interpolated in log frequency between the bands' centres) until the response from the bridge
//    force to the pressure has the measured band levels, the reference
//    band at the infinite plate's point-force radiation below coincidence, |p / F| =
//    rho_air / (2 sqrt(2) pi r rho h) at r metres.

#include "physics/ModalBody.h"

#include <optional>
#include <string>
#include <vector>

namespace jawari
{

struct BandLevel
{
    double lowHz = 0.0, highHz = 0.0;
    double levelDb = 0.0;  // relative to the reference band
};

struct PlateBodyRecipe
{
    std::string name;
    double areaM2 = 0.0;
    double thicknessM = 0.0;
    double densityKgM3 = 0.0;
    double youngPa = 0.0;
    double poisson = 0.0;
    double lossFactor = 0.0;
    double lowestHz = 0.0;       // the first mode
    double highestHz = 0.0;      // modes up to here
    double listenerMetres = 0.0;  // where the response was measured
    std::vector<BandLevel> bands;  // the measured response, ascending
    int referenceBand = 0;         // the band at 0 dB
};

// The recipe's body (see above). Deterministic: the same recipe gives the same modes, bit for bit.
ModalBody plateBody(const PlateBodyRecipe& recipe);

// The band levels of a body's response from the bridge force to the pressure (dB, relative to the
// recipe's reference band): the mean of |P(f)|^2 over each band, on a grid fine enough for every peak.
std::vector<double> bodyBandLevels(const ModalBody& body, const std::vector<BandLevel>& bands, int referenceBand);

// The tanpura's: DAFx-16's measured response (van Walstijn, Bridges & Mehes, their Fig. 5).
const PlateBodyRecipe& tanpuraBodyRecipe();

// A factory body by name ("tanpura"), or none for an unknown name.
std::optional<ModalBody> factoryBody(const std::string& name);
std::vector<const char*> factoryBodyNames();

}  // namespace jawari
