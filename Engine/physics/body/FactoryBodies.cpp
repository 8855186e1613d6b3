#include "physics/body/FactoryBodies.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace jawari
{
namespace
{
constexpr double kAirDensity = 1.2;     // kg/m^3
constexpr double kSpeedOfSound = 343.0;  // m/s, at 20 C

double fractionalPart(double x)
{
    return x - std::floor(x);
}

// The R2 low-discrepancy sequence's point k (Roberts 2018): (a_k, b_k) spread evenly over the unit
// square, so s_k below averages 1 without clustering.
double squaredShapeAtBridge(int k)
{
    const double g1 = 0.7548776662466927, g2 = 0.5698402909980532;  // 1/phi2, 1/phi2^2 (plastic number)
    const double a = fractionalPart(0.5 + (k + 1) * g1), b = fractionalPart(0.5 + (k + 1) * g2);
    const double s = 4.0 * std::pow(std::sin(std::numbers::pi * a) * std::sin(std::numbers::pi * b), 2.0);
    return std::max(s, 0.05);  // a mode with a node at the bridge barely couples: its mass at most 20 M
}

double bendingStiffness(const PlateBodyRecipe& r)
{
    return r.youngPa * r.thicknessM * r.thicknessM * r.thicknessM / (12.0 * (1.0 - r.poisson * r.poisson));
}

std::vector<double> modeFrequencies(const PlateBodyRecipe& r)
{
    const double surfaceDensity = r.densityKgM3 * r.thicknessM;
    const double spacing = 2.0 / (r.areaM2 * std::sqrt(surfaceDensity / bendingStiffness(r)));
    std::vector<double> f;
    for (int k = 0;; ++k)
    {
        // Each mode moved within +-0.4 of the spacing by the golden ratio's sequence; the first stays.
        const double jitter = k == 0 ? 0.0 : 0.8 * (fractionalPart(k * std::numbers::phi) - 0.5);
        const double fk = r.lowestHz + (k + jitter) * spacing;
        if (fk > r.highestHz)
            break;
        f.push_back(fk);
    }
    for (const auto& band : r.bands)
        if (std::none_of(f.begin(), f.end(), [&](double x) { return x >= band.lowHz && x < band.highHz; }))
            f.push_back(std::sqrt(band.lowHz * band.highHz));
    std::sort(f.begin(), f.end());
    return f;
}

// The bands' gains interpolated in log frequency between the bands' centres (constant beyond the
// first and the last): a mode near a band's edge takes some of its neighbour's, so a strong band's
// modes do not spill into a weak neighbour at full strength.
double gainAt(const std::vector<BandLevel>& bands, const std::vector<double>& gain, double f)
{
    auto centre = [&](size_t b) { return std::log(std::sqrt(bands[b].lowHz * bands[b].highHz)); };
    const double x = std::log(f);
    if (x <= centre(0))
        return gain.front();
    for (size_t b = 0; b + 1 < bands.size(); ++b)
        if (x <= centre(b + 1))
        {
            const double t = (x - centre(b)) / (centre(b + 1) - centre(b));
            return std::exp((1.0 - t) * std::log(gain[b]) + t * std::log(gain[b + 1]));
        }
    return gain.back();
}

// Mean |P(f)|^2 over [low, high]: the trapezoid rule on a grid whose step is a fraction of the
// narrowest peak's half-power width there (f eta).
double meanPressurePower(const ModalBody& body, double low, double high, double lossFactor, int listener)
{
    const double ratio = 1.0 + lossFactor / 8.0;
    double sum = 0.0, f = low;
    auto power = [&](double x) {
        const auto r = bodyResponse(body, x, listener);
        return r.pressureReal * r.pressureReal + r.pressureImag * r.pressureImag;
    };
    double previous = power(f);
    while (f < high)
    {
        const double next = std::min(high, f * ratio);
        const double value = power(next);
        sum += 0.5 * (previous + value) * (next - f);
        previous = value;
        f = next;
    }
    return sum / (high - low);
}

double smallestLossFactor(const ModalBody& body)
{
    double eta = 1.0;
    for (const auto& m : body.modes)
        eta = std::min(eta, m.sigma / (std::numbers::pi * m.frequencyHz));
    return std::max(eta, 1e-4);
}

// A number in [0, 1) drawn from an index by the SplitMix64 generator's output function (Steele, Lea
// and Flood 2014): the same index gives the same number on every machine.
double uniformOfIndex(std::uint64_t index)
{
    std::uint64_t z = index * 0x9E3779B97F4A7C15ull + 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return double(z >> 11) * 0x1.0p-53;
}

// Each band's modes scaled by what the band lacks at the listener; the bands' tails reach their
// neighbours, so a few passes.
void fitBands(ModalBody& body, const PlateBodyRecipe& r, double referencePower, int listener)
{
    for (int pass = 0; pass < 8; ++pass)
    {
        std::vector<double> gain;
        for (const auto& band : r.bands)
        {
            const double want = referencePower * std::pow(10.0, band.levelDb / 10.0);
            gain.push_back(
                std::sqrt(want / meanPressurePower(body, band.lowHz, band.highHz, r.lossFactor, listener)));
        }
        for (auto& mode : body.modes)
            mode.radiation[size_t(listener)] *= gainAt(r.bands, gain, mode.frequencyHz);
    }
}

// Mode k's unscaled weights at the left and right listeners, given its weight `centre` (+-1) at the
// centre: jointly they have unit variance over the modes and the correlations of directionCorrelation
// (centre to a side: the sides' sine apart; left to right: twice that), the part a side shares with
// the centre plus a part of its own, at an angle drawn by a hash of k (a low-discrepancy sequence
// would drift with the centre's signs over a band's run of modes, and correlate them).
struct SideWeights
{
    double left = 0.0, right = 0.0;
};
SideWeights sideWeights(int k, double centre, double f, double radius, double angleDegrees)
{
    const double u = std::sin(angleDegrees * std::numbers::pi / 180.0);
    const double r1 = directionCorrelation(f, radius, u), r2 = directionCorrelation(f, radius, 2.0 * u);
    const double own = 1.0 - r1 * r1, shared = r2 - r1 * r1;  // var(e_L) = var(e_R), cov(e_L, e_R)
    const double angle = 2.0 * std::numbers::pi * uniformOfIndex(std::uint64_t(k));
    const double n1 = std::numbers::sqrt2 * std::cos(angle), n2 = std::numbers::sqrt2 * std::sin(angle);
    const double even = std::sqrt(std::max(0.0, 0.5 * (own + shared))), odd = std::sqrt(std::max(0.0, 0.5 * (own - shared)));
    return {r1 * centre + even * n1 + odd * n2, r1 * centre + even * n1 - odd * n2};
}

// BodyMode::correlation: per mode, the correlation of each listener's weights with the first's over
// the modes within a sixth of an octave, each weighted by its share of the response's power at a
// listener, c^2 / (m^2 sigma) (its resonance's peak c / (2 m sigma), its width sigma).
void measureCorrelations(ModalBody& body)
{
    for (auto& mode : body.modes)
        for (size_t l = 1; l < body.listeners.size(); ++l)
        {
            double cross = 0.0, first = 0.0, other = 0.0;
            for (const auto& near : body.modes)
                if (std::abs(std::log2(near.frequencyHz / mode.frequencyHz)) <= 1.0 / 6.0)
                {
                    const double w = 1.0 / (near.massKg * near.massKg * std::max(near.sigma, 1e-9));
                    cross += w * near.radiation[0] * near.radiation[l];
                    first += w * near.radiation[0] * near.radiation[0];
                    other += w * near.radiation[l] * near.radiation[l];
                }
            mode.correlation[l] = std::clamp(cross / std::sqrt(first * other), -1.0, 1.0);
        }
}

// J1(x) by Bessel's integral, (1 / 2 pi) times the integral over a period of cos(t - x sin t): the
// trapezoid rule on a periodic integrand converges geometrically once the points outnumber |x|.
double besselJ1(double x)
{
    const int n = 64 + 2 * static_cast<int>(std::ceil(std::abs(x)));
    double sum = 0.0;
    for (int j = 0; j < n; ++j)
    {
        const double t = 2.0 * std::numbers::pi * j / n;
        sum += std::cos(t - x * std::sin(t));
    }
    return sum / n;
}
}  // namespace

double directionCorrelation(double frequencyHz, double radiusMetres, double sineApart)
{
    const double x = std::abs(2.0 * std::numbers::pi * frequencyHz * radiusMetres * sineApart / kSpeedOfSound);
    return x < 1e-8 ? 1.0 : 2.0 * besselJ1(x) / x;
}

std::vector<double> bodyBandLevels(const ModalBody& body, const std::vector<BandLevel>& bands, int referenceBand,
                                   int listener)
{
    const double eta = smallestLossFactor(body);
    std::vector<double> levels;
    for (const auto& band : bands)
        levels.push_back(10.0 * std::log10(meanPressurePower(body, band.lowHz, band.highHz, eta, listener)));
    const double reference = levels[size_t(referenceBand)];
    for (double& l : levels)
        l -= reference;
    return levels;
}

ModalBody plateBody(const PlateBodyRecipe& r)
{
    const double surfaceDensity = r.densityKgM3 * r.thicknessM;
    const double plateMass = surfaceDensity * r.areaM2;
    ModalBody body;
    body.name = r.name;
    body.listeners = {"centre", "left", "right"};
    const auto frequencies = modeFrequencies(r);
    const double radius = std::sqrt(r.areaM2 / std::numbers::pi);
    for (size_t k = 0; k < frequencies.size(); ++k)
    {
        const double s = squaredShapeAtBridge(int(k));
        const double sign = fractionalPart(double(k + 1) * std::numbers::sqrt2) < 0.5 ? 1.0 : -1.0;
        const double f = frequencies[k];
        const auto sides = sideWeights(int(k), sign, f, radius, r.sideAngleDegrees);
        body.modes.push_back({f, std::numbers::pi * f * r.lossFactor, plateMass / s,
                              {sign / std::sqrt(s), sides.left / std::sqrt(s), sides.right / std::sqrt(s)}});
    }
    // The reference band's level: the infinite plate's |p / F| below coincidence.
    const double referencePower =
        std::pow(kAirDensity / (2.0 * std::numbers::sqrt2 * std::numbers::pi * r.listenerMetres * surfaceDensity), 2.0);
    for (int listener = 0; listener < int(body.listeners.size()); ++listener)
        fitBands(body, r, referencePower, listener);
    measureCorrelations(body);
    return body;
}

const PlateBodyRecipe& tanpuraBodyRecipe()
{
    static const PlateBodyRecipe recipe = [] {
        PlateBodyRecipe r;
        r.name = "tanpura";
        // A male tanpura's tabli: a toon (Toona ciliata) plate about 0.40 m across (T. Levy's maker's
        // table: 37-45 cm), 4 mm thick (assumed); toon at 513 kg/m^3 and 9.0 GPa along the grain
        // (Smithsonian MCI), across the grain 0.075 of that (assumed), so an isotropic plate of their
        // geometric mean; a loss factor of 0.02 (piano soundboards, Ege & Boutillon; the measured
        // response's decay, T60 about 0.11 s near 1 kHz). The first mode near 100 Hz.
        r.areaM2 = std::numbers::pi * 0.2 * 0.2;
        r.thicknessM = 4e-3;
        r.densityKgM3 = 513.0;
        r.youngPa = 9.0e9 * std::sqrt(0.075);
        r.poisson = 0.3;
        r.lossFactor = 0.02;
        r.lowestHz = 100.0;
        r.highestHz = 13000.0;
        r.listenerMetres = 0.8;
        r.sideAngleDegrees = 30.0;
        // DAFx-16's Fig. 5, their impulse response from the bridge to a microphone at 80 cm, in
        // bands relative to 1.25-2 kHz (docs/design.md section 1, "The body").
        const double edges[] = {50, 80, 125, 200, 315, 500, 800, 1250, 2000, 3150, 5000, 8000, 12500};
        const double levels[] = {-30.5, -33, -33, -29, -16.5, -1.3, -5.5, 0, -2.2, -6.8, -7.5, -12};
        for (size_t b = 0; b < std::size(levels); ++b)
            r.bands.push_back({edges[b], edges[b + 1], levels[b]});
        r.referenceBand = 7;
        return r;
    }();
    return recipe;
}

const PlateBodyRecipe& sitarBodyRecipe()
{
    static const PlateBodyRecipe recipe = [] {
        // A sitar's tabli: the tanpura's toon plate and its assumed 4 mm, 0.32 m across (the median
        // width of three sitars in the MINIM-UK collection, 245, 320 and 380 mm; the tabli is at most
        // the instrument's width). A plate of the same wood and thickness has its modes at frequencies
        // in inverse proportion to its area, so the tanpura's first mode and its measured response's
        // bands move up by the ratio of the areas (docs/design.md section 1, "The sitar's body": no
        // sitar's response is published); the bands beyond the modes' 13 kHz are left out.
        const auto& tanpura = tanpuraBodyRecipe();
        PlateBodyRecipe r = tanpura;
        r.name = "sitar";
        r.areaM2 = std::numbers::pi * 0.16 * 0.16;
        const double scale = tanpura.areaM2 / r.areaM2;
        r.lowestHz = tanpura.lowestHz * scale;
        r.bands.clear();
        for (const auto& band : tanpura.bands)
            if (band.highHz * scale <= r.highestHz)
                r.bands.push_back({band.lowHz * scale, band.highHz * scale, band.levelDb});
        return r;
    }();
    return recipe;
}

std::optional<ModalBody> factoryBody(const std::string& name)
{
    // Fitted once per process (the tanpura's three listeners' fits take about 0.17 s), then copied.
    if (name == "tanpura")
    {
        static const ModalBody tanpura = plateBody(tanpuraBodyRecipe());
        return tanpura;
    }
    if (name == "sitar")
    {
        static const ModalBody sitar = plateBody(sitarBodyRecipe());
        return sitar;
    }
    return std::nullopt;
}

std::vector<const char*> factoryBodyNames()
{
    return {"tanpura", "sitar"};
}

}  // namespace jawari
