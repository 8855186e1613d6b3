#include "physics/string/StringModel.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace jawari
{

double StringParameters::flexibleFundamentalHz() const
{
    return std::sqrt(tensionNewtons / linearDensity) / (2.0 * lengthMetres);
}

double StringParameters::bendingStiffness() const
{
    constexpr double pi = std::numbers::pi;
    return inharmonicity * tensionNewtons * lengthMetres * lengthMetres / (pi * pi);
}

double valetteInverseQ(const StringParameters& string, double frequencyHz)
{
    constexpr double pi = std::numbers::pi;
    const auto& d = string.damping;
    const double mu = string.linearDensity;
    const double T = string.tensionNewtons;
    const double R =
        2.0 * pi * d.etaAir + 2.0 * pi * string.diameterMetres * std::sqrt(pi * d.etaAir * d.rhoAir * frequencyHz);
    const double air = R / (2.0 * pi * mu * frequencyHz);
    const double viscoelastic =
        4.0 * pi * pi * mu * string.bendingStiffness() * d.deltaVe * frequencyHz * frequencyHz / (T * T);
    return air + viscoelastic + d.qTeInv;
}

ModalTable buildModalTable(const StringParameters& string, int modeCount)
{
    constexpr double pi = std::numbers::pi;
    if (modeCount < 1)
        throw std::invalid_argument("modal table needs at least one mode");
    ModalTable table;
    table.frequencyHz.resize(modeCount);
    table.omega.resize(modeCount);
    table.sigma.resize(modeCount);
    const double f0 = string.flexibleFundamentalHz();
    for (int i = 0; i < modeCount; ++i)
    {
        const double p = i + 1;
        table.frequencyHz[i] = p * f0 * std::sqrt(1.0 + string.inharmonicity * p * p);
    }
    for (const auto& o : string.modeOverrides)
        if (o.number >= 1 && o.number <= modeCount && o.frequencyHz)
            table.frequencyHz[o.number - 1] = *o.frequencyHz;

    for (int i = 0; i < modeCount; ++i)
    {
        const double f = table.frequencyHz[i];
        table.omega[i] = 2.0 * pi * f;
        switch (string.damping.law)
        {
            case DampingLaw::valette: table.sigma[i] = pi * f * valetteInverseQ(string, f); break;
            case DampingLaw::none: table.sigma[i] = 0.0; break;
            case DampingLaw::constant: table.sigma[i] = string.damping.sigma; break;
            case DampingLaw::wavenumber:
            {
                const double beta = (i + 1) * pi / string.lengthMetres;
                const auto& d = string.damping;
                table.sigma[i] = d.sigma0 + d.sigma1 * beta + d.sigma3 * beta * beta * beta;
                break;
            }
        }
    }
    for (const auto& o : string.modeOverrides)
        if (o.number >= 1 && o.number <= modeCount && o.sigma)
            table.sigma[o.number - 1] = *o.sigma;
    return table;
}

double sinPi(double t)
{
    double r = std::fmod(t, 2.0);  // exact
    if (r < 0.0)
        r += 2.0;
    double sign = 1.0;
    if (r >= 1.0)
    {
        r -= 1.0;  // exact
        sign = -1.0;
    }
    if (r > 0.5)
        r = 1.0 - r;  // exact in [0.5, 1]
    return r == 0.0 ? 0.0 : sign * std::sin(std::numbers::pi * r);
}

double modeShape(double lengthMetres, int p, double x)
{
    return std::sqrt(2.0 / lengthMetres) * sinPi(p * (x / lengthMetres));
}

std::vector<double> pluckModalShape(double lengthMetres, int modeCount, double pluckPosition, double amplitudeMetres)
{
    constexpr double pi = std::numbers::pi;
    const double L = lengthMetres;
    const double c = pluckPosition;
    std::vector<double> q(modeCount);
    for (int i = 0; i < modeCount; ++i)
    {
        const double p = i + 1;
        q[i] = std::sqrt(2.0 / L) * amplitudeMetres * L * L * L * sinPi(p * (c / L)) / (p * p * pi * pi * c * (L - c));
    }
    return q;
}

}  // namespace jawari
