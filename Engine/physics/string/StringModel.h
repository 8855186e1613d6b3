#pragma once
// The stiff, damped string as a modal table (docs/design.md section 1).
//
// Thread tags (RT, CT, OFF) as in docs/design.md section 6. Everything here is OFF unless tagged.

#include <optional>
#include <vector>

namespace jawari
{

enum class DampingLaw
{
    valette,  // 1/Q = 1/Q_air + 1/Q_ve + 1/Q_te (paper eq. 9)
    none,     // lossless: the energy tests need it
    constant,   // one sigma (1/s) for every mode
    wavenumber  // sigma_p = sigma0 + sigma1 beta_p + sigma3 beta_p^3, beta_p = p pi / L (van Walstijn et al. 2016)
};

struct DampingParameters
{
    DampingLaw law = DampingLaw::valette;
    double etaAir = 1.8e-5;   // dynamic viscosity of air, kg/(m s)
    double rhoAir = 1.2;      // density of air, kg/m^3
    double deltaVe = 0.006;   // viscoelastic loss angle
    double qTeInv = 1.38e-4;  // thermoelastic 1/Q, constant
    double sigma = 0.0;       // 1/s, for DampingLaw::constant
    // DampingLaw::wavenumber: air (1/s), internal friction (m/s) and bending (m^3/s) losses.
    double sigma0 = 0.0, sigma1 = 0.0, sigma3 = 0.0;
};

// A measured mode replacing the law's value (the paper measures 36 modes).
struct ModeOverride
{
    int number = 1;  // p, from 1
    std::optional<double> frequencyHz;
    std::optional<double> sigma;  // 1/s
};

struct StringParameters
{
    double lengthMetres = 1.002;
    double tensionNewtons = 180.5;
    double linearDensity = 1.17e-3;  // kg/m
    double diameterMetres = 0.43e-3;
    double inharmonicity = 1.78e-5;  // B = pi^2 EI / (T L^2)
    DampingParameters damping;
    std::vector<ModeOverride> modeOverrides;

    double flexibleFundamentalHz() const;  // f0 = sqrt(T/mu) / (2L)
    double bendingStiffness() const;       // EI = B T L^2 / pi^2, N m^2
};

// The paper's configuration: 1001 modes (the grid x_i = i L/1002) at 2 MHz; and the most modes any
// model takes.
inline constexpr double kReferenceRateHz = 2'000'000.0;
inline constexpr int kReferenceModes = 1001;
inline constexpr int kMaxModes = 100000;

// Per-mode frequency and damping, p = 1..M stored at index p-1.
struct ModalTable
{
    std::vector<double> frequencyHz;
    std::vector<double> omega;  // rad/s
    std::vector<double> sigma;  // 1/s

    int size() const { return static_cast<int>(omega.size()); }
};

// f_p = p f0 sqrt(1 + B p^2), sigma_p = pi f_p / Q_p, then the overrides.
ModalTable buildModalTable(const StringParameters& string, int modeCount);

// 1/Q of Valette's law at frequency f (paper eq. 9).
double valetteInverseQ(const StringParameters& string, double frequencyHz);

// sin(pi t) with the argument reduced exactly (fmod is exact): sin(pi k) is 0 for whole k,
// and high modes keep full accuracy (sin(p pi x/L) would lose about p ulps). RT.
double sinPi(double t);

// phi_p(x) = sqrt(2/L) sin(p pi x / L). RT.
double modeShape(double lengthMetres, int p, double x);

// Modal coefficients q_p (p = 1..M) of the triangular pluck of the given amplitude at x_e:
// q_p = sqrt(2/L) A L^3 sin(p pi x_e/L) / (p^2 pi^2 x_e (L - x_e)), the exact projection.
std::vector<double> pluckModalShape(double lengthMetres, int modeCount, double pluckPosition, double amplitudeMetres);

}  // namespace jawari
