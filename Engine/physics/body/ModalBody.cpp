#include "physics/body/ModalBody.h"

#include "physics/string/StringModel.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <iomanip>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace jawari
{
namespace
{
// A number in a message: up to six significant digits.
std::string shortNumber(double v)
{
    std::ostringstream s;
    s << std::setprecision(6) << v;
    return s.str();
}
}  // namespace

int listenerIndex(const ModalBody& body, const std::string& name)
{
    for (size_t l = 0; l < body.listeners.size(); ++l)
        if (body.listeners[l] == name)
            return int(l);
    return -1;
}

void validateBody(const ModalBody& body)
{
    const auto& names = body.listeners;
    if (names.empty() || names.size() > size_t(kMostListeners))
        throw std::invalid_argument("a body has 1 to " + std::to_string(kMostListeners) + " listeners, not "
                                    + std::to_string(names.size()));
    for (size_t l = 0; l < names.size(); ++l)
        if (names[l].empty() || listenerIndex(body, names[l]) != int(l))
            throw std::invalid_argument("listener " + std::to_string(l) + ": its name must be given once, got \""
                                        + names[l] + "\"");
    for (size_t k = 0; k < body.modes.size(); ++k)
    {
        const auto& m = body.modes[k];
        auto refuse = [&](const char* field, const std::string& range) {
            throw BodyRangeError(int(k), field, "must be " + range);
        };
        if (!(m.frequencyHz > 0.0 && m.frequencyHz <= kBodyHighestHz))
            refuse("frequency", "within (0, " + shortNumber(kBodyHighestHz) + "] Hz (got " + shortNumber(m.frequencyHz) + ")");
        const double critical = 2.0 * std::numbers::pi * m.frequencyHz;
        if (!(m.sigma >= 0.0 && m.sigma <= critical))
            refuse("damping", "within [0, " + shortNumber(critical) + "] /s, up to critical damping 2 pi frequency (got "
                                  + shortNumber(m.sigma) + ")");
        if (!(m.massKg >= kBodyLightestKg && m.massKg <= kBodyHeaviestKg))
            refuse("mass", "within [" + shortNumber(kBodyLightestKg) + ", " + shortNumber(kBodyHeaviestKg) + "] kg (got "
                               + shortNumber(m.massKg) + ")");
        for (size_t l = 0; l < m.radiation.size(); ++l)
        {
            if (!(std::abs(m.radiation[l]) <= kBodyLoudestRadiation))
                refuse("radiation", "within +-" + shortNumber(kBodyLoudestRadiation) + " Pa s/m (got "
                                        + shortNumber(m.radiation[l]) + ")");
            if (l >= names.size() && m.radiation[l] != 0.0)
                refuse("radiation", "0 for listener " + std::to_string(l) + ", which the body does not have");
        }
        for (const double r : m.correlation)
            if (!(r >= -1.0 && r <= 1.0))
                refuse("correlation", "within [-1, 1]");
    }
}

double largestDampingScale(const ModalBody& body)
{
    double largest = std::numeric_limits<double>::infinity();
    for (const auto& m : body.modes)
        if (m.sigma > 0.0)
            largest = std::min(largest, 2.0 * std::numbers::pi * m.frequencyHz / m.sigma);
    return largest;
}

namespace
{
// The strings' contact rows over their M modes: their own rows, or the sine modes' phi_p(x_j).
std::vector<double> stringRows(const ModalSolverConfig& c)
{
    if (!c.contactShapes.empty())
        return c.contactShapes;
    const int M = c.modes.size();
    std::vector<double> rows;
    rows.reserve(c.contacts.size() * size_t(M));
    for (const auto& point : c.contacts)
        for (int p = 1; p <= M; ++p)
            rows.push_back(modeShape(c.lengthMetres, p, point.position));
    return rows;
}

// The excitation's shape over the sine modes, when the configuration names a position but no shape.
void materialiseExcitation(ModalSolverConfig& c)
{
    if (c.excitationPosition && c.excitationShape.empty())
        for (int p = 1; p <= c.modes.size(); ++p)
            c.excitationShape.push_back(modeShape(c.lengthMetres, p, *c.excitationPosition));
}

// v over M modes, padded with K zeros (left empty when empty).
std::vector<double> padded(const std::vector<double>& v, int K)
{
    std::vector<double> out = v;
    if (!out.empty())
        out.resize(out.size() + size_t(K), 0.0);
    return out;
}
}  // namespace

ModalSolverConfig withBody(const ModalSolverConfig& strings, const BodyJoin& join)
{
    if (!join.body)
        throw std::invalid_argument("withBody needs a body");
    const ModalBody& body = *join.body;
    validateBody(body);
    if (strings.transform)
        throw std::invalid_argument("a body couples the contact points: it takes the projection path");
    if (join.pointOnBody.size() != strings.contacts.size())
        throw std::invalid_argument("withBody: one on-the-body flag per contact point");
    if (!(std::isfinite(join.coupling) && join.coupling >= 0.0))
        throw std::invalid_argument("the body's coupling must be finite and >= 0");
    const int M = strings.modes.size(), K = int(body.modes.size());
    const double mu = strings.linearDensity;
    ModalSolverConfig c = strings;
    materialiseExcitation(c);
    for (const auto& mode : body.modes)
    {
        c.modes.frequencyHz.push_back(mode.frequencyHz);
        c.modes.omega.push_back(2.0 * std::numbers::pi * mode.frequencyHz);
        c.modes.sigma.push_back(mode.sigma);
    }
    const auto rows = stringRows(strings);
    c.contactShapes.clear();
    c.contactShapes.reserve(strings.contacts.size() * size_t(M + K));
    for (size_t j = 0; j < strings.contacts.size(); ++j)
    {
        c.contactShapes.insert(c.contactShapes.end(), rows.begin() + long(j * M), rows.begin() + long((j + 1) * M));
        for (const auto& mode : body.modes)
            c.contactShapes.push_back(join.pointOnBody[j] ? -join.coupling * std::sqrt(mu / mode.massKg) : 0.0);
    }
    c.pickupWeights = padded(strings.pickupWeights, K);
    c.secondPickupWeights = padded(strings.secondPickupWeights, K);
    c.excitationShape = padded(c.excitationShape, K);
    // A pluck's map B, (M + K) x m: the strings' rows, then the body's, at rest. Empty stays empty
    // (the sine modes: the caller plucks the first M modes) unless asked for.
    if (!strings.shapeToModes.empty())
        c.shapeToModes.resize(strings.shapeToModes.size() / size_t(M) * size_t(M + K), 0.0);
    else if (join.mapShapes)
    {
        c.shapeToModes.assign(size_t(M + K) * size_t(M), 0.0);
        for (int p = 0; p < M; ++p)
            c.shapeToModes[size_t(p) * size_t(M) + size_t(p)] = 1.0;
    }
    return c;
}

void appendString(ModalSolverConfig& c, const ModalSolverConfig& other)
{
    if (c.transform || other.transform || !c.contactCompliance.empty() || !other.contactCompliance.empty())
        throw std::invalid_argument("strings on one body take the projection path without a residual compliance");
    const int M = c.modes.size(), N = other.modes.size();
    const double scale = std::sqrt(c.linearDensity / other.linearDensity);
    materialiseExcitation(c);
    const auto ownRows = stringRows(c), otherRows = stringRows(other);
    c.contactShapes.clear();
    for (size_t j = 0; j < c.contacts.size(); ++j)
    {
        c.contactShapes.insert(c.contactShapes.end(), ownRows.begin() + long(j * M), ownRows.begin() + long((j + 1) * M));
        c.contactShapes.resize(c.contactShapes.size() + size_t(N), 0.0);
    }
    for (size_t j = 0; j < other.contacts.size(); ++j)
    {
        c.contactShapes.resize(c.contactShapes.size() + size_t(M), 0.0);
        for (size_t p = 0; p < size_t(N); ++p)
            c.contactShapes.push_back(scale * otherRows[j * size_t(N) + p]);
    }
    c.contacts.insert(c.contacts.end(), other.contacts.begin(), other.contacts.end());
    for (auto* table : {&c.modes.frequencyHz, &c.modes.omega, &c.modes.sigma})
        table->reserve(size_t(M + N));
    c.modes.frequencyHz.insert(c.modes.frequencyHz.end(), other.modes.frequencyHz.begin(), other.modes.frequencyHz.end());
    c.modes.omega.insert(c.modes.omega.end(), other.modes.omega.begin(), other.modes.omega.end());
    c.modes.sigma.insert(c.modes.sigma.end(), other.modes.sigma.begin(), other.modes.sigma.end());
    c.pickupWeights = padded(c.pickupWeights, N);
    c.secondPickupWeights = padded(c.secondPickupWeights, N);
    c.excitationShape = padded(c.excitationShape, N);
    if (!c.shapeToModes.empty())
        c.shapeToModes.resize(c.shapeToModes.size() / size_t(M) * size_t(M + N), 0.0);
}

std::vector<char> contactPointsOnBody(const std::vector<Obstacle>& obstacles, const std::vector<char>& onBody,
                                      double lengthMetres, int gridIntervals)
{
    std::vector<char> points;
    for (size_t i = 0; i < obstacles.size(); ++i)
        points.resize(points.size() + contactPointsOnGrid({obstacles[i]}, lengthMetres, gridIntervals).size(),
                      onBody[i]);
    return points;
}

namespace
{
void checkListener(const ModalBody& body, int listener)
{
    if (listener < 0 || size_t(listener) >= body.listeners.size())
        throw std::invalid_argument("listener " + std::to_string(listener) + ": the body has "
                                    + std::to_string(body.listeners.size()) + " listeners");
}
}  // namespace

std::vector<double> radiationWeights(const ModalBody& body, int stringModes, double linearDensity, int listener)
{
    checkListener(body, listener);
    std::vector<double> h(size_t(stringModes), 0.0);
    for (const auto& mode : body.modes)
        h.push_back(mode.radiation[size_t(listener)] * std::sqrt(linearDensity / mode.massKg));
    return h;
}

BodyResponse bodyResponse(const ModalBody& body, double frequencyHz, int listener)
{
    checkListener(body, listener);
    const double w = 2.0 * std::numbers::pi * frequencyHz;
    std::complex<double> Y = 0.0, P = 0.0;
    for (const auto& mode : body.modes)
    {
        const double wk = 2.0 * std::numbers::pi * mode.frequencyHz;
        // z / F = 1 / (m_k (wk^2 - w^2 + 2 i sigma_k w))
        const std::complex<double> receptance =
            1.0 / (mode.massKg * std::complex<double>(wk * wk - w * w, 2.0 * mode.sigma * w));
        Y += std::complex<double>(0.0, w) * receptance;
        P += mode.radiation[size_t(listener)] * std::complex<double>(0.0, w) * receptance;
    }
    return {Y.real(), Y.imag(), P.real(), P.imag()};
}

}  // namespace jawari
