// Two strings on one body or one bridge (SympatheticStrings.h, SharedBody.h): their normal modes, in
// unison and mistuned, as Weinreich found them on the piano.

#include "TestSupport.h"
#include "offline/Analysis.h"
#include "offline/OfflineRender.h"
#include "offline/Scene.h"
#include "physics/body/FactoryBodies.h"
#include "physics/body/SharedBody.h"
#include "physics/string/SpringLoadedModes.h"
#include "physics/string/StringDiscretisation.h"
#include "physics/string/StringModel.h"
#include "realtime/instrument/Instrument.h"
#include "realtime/sympathetic/SympatheticStrings.h"
#include "realtime/instrument/VoicePack.h"

#include <Eigen/Dense>
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <complex>
#include <deque>
#include <memory>
#include <numbers>
#include <numeric>
#include <sstream>
#include <vector>

using namespace jawari;

namespace
{
struct UnisonRun
{
    std::vector<double> first, second;
};

// Taraf strings tuned to `hz` (one each) on their bridges' springs on `body`, coupled by `coupling`
// (16 modes each, 192 kHz), the first plucked at 1 mm, for `seconds`: the first two strings' first
// modal coordinates q_1 at every step (with one string, the second's row is empty). `asSympathetic`:
// stepped as the shared body's sympathetic strings (split 0: their force fitted as affine).
UnisonRun tarafOnBody(const std::vector<double>& hz, const ModalBody& body, double coupling, double seconds,
                      bool asSympathetic = false)
{
    const double rate = 192000.0;
    std::deque<ModalSolver> solvers;  // built in place: a solver is not copied
    for (const double f : hz)
    {
        const auto string = sympatheticStringAt(f);
        auto config = stringSolverConfig(string, {sympatheticBridge(string.lengthMetres)}, kSympatheticModes, rate,
                                         0.9 * string.lengthMetres, PickupQuantity::displacement);
        config.pickupWeights.assign(config.pickupWeights.size(), 0.0);
        config.pickupWeights[0] = 1.0;  // the pickup reads q_1
        solvers.emplace_back(config);
    }
    const double L = sympatheticStringAt(hz.front()).lengthMetres;
    solvers[0].setInitialDisplacement(pluckModalShape(L, kSympatheticModes, 0.3 * L, 1e-3));
    SharedBody shared(body, coupling, solvers[0].timeStep());
    std::vector<ModalSolver*> pointers;
    for (auto& s : solvers)
    {
        shared.checkLinear(s);
        pointers.push_back(&s);
    }
    const int count = int(hz.size());
    UnisonRun run;
    for (long n = 0; n < long(seconds * rate); ++n)
    {
        shared.step(pointers.data(), count, asSympathetic ? 0 : count);
        run.first.push_back(solvers[0].pickup());
        if (count > 1)
            run.second.push_back(solvers[1].pickup());
    }
    return run;
}

// `strings` identical taraf strings at 370 Hz on the tanpura body.
UnisonRun unisonOnBody(int strings, double coupling, double seconds, bool asSympathetic = false)
{
    return tarafOnBody(std::vector<double>(size_t(strings), 370.0), *factoryBody("tanpura"), coupling, seconds,
                       asSympathetic);
}

// The decay rate (1/s) of x's envelope, the peak of |x| in each 10 ms, from a straight line fitted to
// its logarithm over [from, to) seconds at 192 kHz.
double decayRate(const std::vector<double>& x, double from, double to)
{
    const int window = 1920;
    std::vector<double> t, y;
    for (size_t start = size_t(from * 192000.0); start + window <= size_t(to * 192000.0); start += window)
    {
        double peak = 0.0;
        for (size_t n = start; n < start + window; ++n)
            peak = std::max(peak, std::abs(x[n]));
        t.push_back((double(start) + 0.5 * window) / 192000.0);
        y.push_back(std::log(peak));
    }
    const double n = double(t.size()), st = std::accumulate(t.begin(), t.end(), 0.0),
                 sy = std::accumulate(y.begin(), y.end(), 0.0);
    double stt = 0.0, sty = 0.0;
    for (size_t i = 0; i < t.size(); ++i)
    {
        stt += t[i] * t[i];
        sty += t[i] * y[i];
    }
    return -(n * sty - st * sy) / (n * stt - st * st);
}
}  // namespace

TEST_CASE("Two unison strings on one body: their anti-phase motion never feels it and their in-phase motion "
          "loses to it twice what one string alone does (Weinreich's coupled strings)",
          "[sympathetic][body]")
{
    // Weinreich (JASA 62, 1977, "Coupled piano strings"): two strings on one bridge share it; the
    // anti-phase mode puts no net force on it, so it decays at the strings' own rate (J. O. Smith,
    // Physical Audio Signal Processing, "Coupled strings eigenanalysis": a point bridge is rigid to
    // anti-phase motion), the in-phase mode at the rate of a string loaded by both: here, with the
    // bridge's loss small beside the body's modal spacing, its own rate plus twice the one string's
    // loss to the body. The first modal coordinate of each string, the first plucked.
    const double seconds = 1.2;
    const auto rigid = unisonOnBody(1, 0.0, seconds);  // on its spring, the body decoupled
    const auto alone = unisonOnBody(1, 1.0, seconds);
    const auto pair = unisonOnBody(2, 1.0, seconds);
    std::vector<double> inPhase, antiPhase;
    double largest = 0.0, peak = 0.0;
    for (size_t n = 0; n < pair.first.size(); ++n)
    {
        inPhase.push_back(pair.first[n] + pair.second[n]);
        antiPhase.push_back(pair.first[n] - pair.second[n]);
        largest = std::max(largest, std::abs(antiPhase[n] - rigid.first[n]));
        peak = std::max(peak, std::abs(rigid.first[n]));
    }
    const double own = decayRate(rigid.first, 0.1, seconds), one = decayRate(alone.first, 0.1, seconds),
                 anti = decayRate(antiPhase, 0.1, seconds), in = decayRate(inPhase, 0.1, seconds);
    INFO("decay rates (1/s): the string on rigid supports "
         << own << ", alone on the body " << one << "; the pair's anti-phase motion " << anti << ", in-phase " << in
         << " (expected " << own + 2.0 * (one - own)
         << "); the anti-phase motion differs from the lone string "
            "on rigid supports by "
         << largest / peak << " of its peak");
    CHECK(one - own > 0.2 * own);  // the body takes a share worth measuring
    CHECK(largest < 1e-9 * peak);  // to rounding: the body never moves it
    CHECK(in - own == Approx(2.0 * (one - own)).epsilon(0.2));

    // The same pair as the shared body's sympathetic strings (split 0): their force affine in the
    // bridge's displacement, fitted from one trial a step (SharedBody::fitLinear), not solved at each of
    // the secant's evaluations. The same motion to rounding.
    const auto fitted = unisonOnBody(2, 1.0, seconds, true);
    double apart = 0.0;
    for (size_t n = 0; n < pair.first.size(); ++n)
        apart =
            std::max({apart, std::abs(fitted.first[n] - pair.first[n]), std::abs(fitted.second[n] - pair.second[n])});
    INFO("the pair through the affine fit differs from the pair solved by " << apart / peak << " of the peak");
    CHECK(apart < 1e-9 * peak);
}

namespace
{

// The pair's two normal modes near `hz` from their first modal coordinates over [from, to) s at
// 192 kHz, as lambda (1/s: -decay + i 2 pi f, the slower decay first). Each coordinate is brought
// down by e^{-i 2 pi hz t} and averaged over one period of hz (rounded to whole steps), which all but
// removes the partials above and the image at -2 hz and keeps each normal mode's exponential (a time-invariant filter
// scales each one, never moves it). The complex envelopes a(t) then follow a(t + D) = Q a(t), D = 1 ms, with Q = exp(M
// D) whose eigenvalues give the modes: Q fitted by least squares every half millisecond.
std::array<std::complex<double>, 2> normalModes(const UnisonRun& run, double hz, double from, double to)
{
    const double rate = 192000.0, w = 2.0 * std::numbers::pi * hz;
    const int period = int(std::lround(rate / hz)), ahead = 192, stride = 96;
    const size_t n = run.first.size();
    // Running sums of q e^{-i w t} for both strings: the average over [t - period, t) by differences.
    std::array<std::vector<std::complex<double>>, 2> sums;
    for (size_t c = 0; c < 2; ++c)
    {
        const auto& q = c == 0 ? run.first : run.second;
        sums[c].assign(n + 1, 0.0);
        for (size_t k = 0; k < n; ++k)
            sums[c][k + 1] = sums[c][k] + q[k] * std::polar(1.0, -w * double(k) / rate);
    }
    auto envelope = [&](size_t k) {
        Eigen::RowVector2cd a;
        for (size_t c = 0; c < 2; ++c)
            a[Eigen::Index(c)] = (sums[c][k] - sums[c][k - size_t(period)]) / double(period);
        return a;
    };
    REQUIRE(from * rate >= period);  // a whole period before the first envelope
    REQUIRE(std::min(to * rate, double(n)) >= from * rate + ahead + stride);  // and some to fit
    const size_t first = size_t(from * rate), last = std::min(size_t(to * rate), n) - size_t(ahead);
    const Eigen::Index rows = Eigen::Index((last - first) / size_t(stride));
    Eigen::MatrixXcd X(rows, 2), Y(rows, 2);
    for (Eigen::Index k = 0; k < rows; ++k)
    {
        X.row(k) = envelope(first + size_t(k) * size_t(stride));
        Y.row(k) = envelope(first + size_t(k) * size_t(stride) + size_t(ahead));
    }
    const Eigen::Matrix2cd QT = X.colPivHouseholderQr().solve(Y);  // Y = X Q^T
    const Eigen::ComplexEigenSolver<Eigen::Matrix2cd> eigen(QT.transpose());
    std::array<std::complex<double>, 2> lambda;
    for (Eigen::Index k = 0; k < 2; ++k)
        lambda[size_t(k)] = std::log(eigen.eigenvalues()[k]) / (double(ahead) / rate) + std::complex<double>(0.0, w);
    if (lambda[0].real() < lambda[1].real())
        std::swap(lambda[0], lambda[1]);
    return lambda;
}

std::string describe(std::complex<double> lambda)
{
    std::ostringstream out;
    out << -lambda.real() << " /s at " << lambda.imag() / (2.0 * std::numbers::pi) << " Hz";
    return out.str();
}
}  // namespace

TEST_CASE("Two strings on one bridge, mistuned: their normal modes lock in pitch and split in decay within the "
          "coupling, and split in pitch beyond it (Weinreich's coupled strings)",
          "[sympathetic][body]")
{
    // Weinreich (JASA 62, 1977): two strings of frequencies w_a, w_b on a bridge of admittance Y each
    // feel it as a rate c = gamma (1 + i B/G); their normal modes are
    //   lambda = i (w_a + w_b)/2 - sigma_0 - c +- sqrt(c^2 - delta^2),  delta = (w_a - w_b)/2,
    // so on a resistive bridge (B = 0) they share one pitch and decay at sigma_0 + gamma +- sqrt(gamma^2
    // - delta^2) while the mistuning is within the coupling (delta < gamma: at unison one mode keeps the
    // strings' own decay, the other takes twice the bridge's loss), and beyond it (delta > gamma) they
    // decay alike at sigma_0 + gamma and their pitches split by 2 sqrt(delta^2 - gamma^2), less than the
    // strings' own 2 delta (J. O. Smith, Physical Audio Signal Processing, "Coupled strings
    // eigenanalysis", the same at unison). The bridge here: one body mode at the strings' nominal pitch
    // (they sound 0.8 % above it), so nearly resistive there (Y = 1 / (2 m sigma_b) at resonance; c's
    // imaginary part is 3 % of its real part), and broad beside every split (Q = 5).
    const double hz = 370.0, seconds = 1.2, from = 0.05;
    ModalBody body;
    body.modes.push_back({hz, std::numbers::pi * hz / 5.0, 0.1});
    // At unison the anti-phase mode is the strings' own (the bridge never moves): iw_0 - sigma_0; the
    // in-phase mode is iw_0 - sigma_0 - 2c, which measures c.
    const auto unisonRun = tarafOnBody({hz, hz}, body, 1.0, seconds);
    const double near = normalModes(unisonRun, hz, from, seconds)[0].imag();  // demodulated again there
    const auto unison = normalModes(unisonRun, near / (2.0 * std::numbers::pi), from, seconds);
    const std::complex<double> own = unison[0], c = 0.5 * (unison[0] - unison[1]);
    INFO("at unison: anti-phase " << describe(unison[0]) << ", in-phase " << describe(unison[1]) << ": c = " << c
                                  << " /s");
    REQUIRE(c.real() > 1.0);              // a coupling worth measuring within the second
    CHECK(-own.real() < 0.4 * c.real());  // the anti-phase mode keeps the strings' own decay
    // The strings sound at `scale` times the pitch they are tuned to on their springs (these solvers
    // leave out the residual compliance that the tuning counts): their own half-difference delta.
    const double scale = own.imag() / (2.0 * std::numbers::pi * hz);
    auto check = [&](double deltaOverC, double withinFraction) {
        const double delta = deltaOverC * std::abs(c), apartHz = delta / (std::numbers::pi * scale);
        const auto pair = tarafOnBody({hz + 0.5 * apartHz, hz - 0.5 * apartHz}, body, 1.0, seconds);
        const auto measured = normalModes(pair, own.imag() / (2.0 * std::numbers::pi), from, seconds);
        const std::complex<double> root = std::sqrt(c * c - delta * delta);
        std::array<std::complex<double>, 2> expected{own - c + root, own - c - root};
        // Paired with the measured modes whichever way is nearer: their decays may be nearly alike.
        if (std::abs(measured[0] - expected[1]) + std::abs(measured[1] - expected[0])
            < std::abs(measured[0] - expected[0]) + std::abs(measured[1] - expected[1]))
            std::swap(expected[0], expected[1]);
        INFO("delta " << deltaOverC << " |c|: " << describe(measured[0]) << " and " << describe(measured[1])
                      << "; Weinreich's " << describe(expected[0]) << " and " << describe(expected[1]));
        for (size_t k = 0; k < 2; ++k)
            CHECK(std::abs(measured[k] - expected[k]) < withinFraction * std::abs(c));
        return measured;
    };
    // Measured (mass 0.1 kg): c = 2.546 - 0.075i /s; at delta = 0.6 |c| the modes within 0.5 % of |c|
    // of the formula's, at 2 |c| within 2.5 % (a 10 % error in delta moves them by 4.9 % and 23 % of |c|).
    // Within the coupling: one pitch (apart by 6 % of the strings' own 2 delta), the decays split.
    const auto within = check(0.6, 0.015);
    CHECK(std::abs(within[0].imag() - within[1].imag()) < 0.1 * 2.0 * 0.6 * std::abs(c));
    // Beyond it: alike decays, the pitches split by less than the strings' own (0.88 of it; the
    // formula's 0.87 for a resistive bridge).
    const auto beyond = check(2.0, 0.05);
    CHECK(std::abs(beyond[0].real() - beyond[1].real()) < 0.1 * c.real());
}
