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
//    rho_air / (2 sqrt(2) pi r rho h) at r metres;
//  - the listeners: the centre where the response was measured, and left and right at the same
//    distance, sideAngleDegrees to either side: each mode's weights there share with the centre's
//    what directionCorrelation (below) gives, the rest from a deterministic sequence, and each
//    listener's bands are fitted to the same measured levels (the band's mean power is about the
//    same in every direction when a band holds many modes).

#include "physics/body/ModalBody.h"

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
    double listenerMetres = 0.0;  // where the response was measured: the centre listener
    double sideAngleDegrees = 0.0;  // the left and right listeners, this far to either side of it
    std::vector<BandLevel> bands;  // the measured response, ascending
    int referenceBand = 0;         // the band at 0 dB
};

// The recipe's body (see above). Deterministic: the same recipe gives the same modes, bit for bit.
ModalBody plateBody(const PlateBodyRecipe& recipe);

// The band levels of a body's response from the bridge force to the pressure at a listener (dB,
// relative to the recipe's reference band): the mean of |P(f)|^2 over each band, on a grid fine
// enough for every peak.
std::vector<double> bodyBandLevels(const ModalBody& body, const std::vector<BandLevel>& bands, int referenceBand,
                                   int listener = 0);

// How alike a plate's radiation is in two directions whose sines differ by `sineApart`, at a
// frequency: the correlation over many modes of their far-field pressures, 2 J1(x) / x with
// x = k_air a sineApart for a disc of radius a whose modes' velocity patterns are finer than the
// wavelength in air (the van Cittert-Zernike theorem). 1 at low frequencies (the plate radiates the
// same everywhere), 0 first where x = 3.83.
double directionCorrelation(double frequencyHz, double radiusMetres, double sineApart);

// The tanpura's: DAFx-16's measured response (van Walstijn, Bridges & Mehes, their Fig. 5).
const PlateBodyRecipe& tanpuraBodyRecipe();

// The sitar's: the tanpura's plate at a sitar's size, its response the tanpura's with its frequencies
// scaled as the plate's modes are (see sitarBodyRecipe in the .cpp).
const PlateBodyRecipe& sitarBodyRecipe();

// A factory body by name ("tanpura", "sitar"), or none for an unknown name. Thread-safe: each is built once.
std::optional<ModalBody> factoryBody(const std::string& name);
std::vector<const char*> factoryBodyNames();

}  // namespace jawari
