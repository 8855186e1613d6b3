#pragma once
// jawari-convergence's ladders of reference configurations (ReferenceConvergence.cpp) and its
// command line.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

namespace jawari::convergence
{

// One configuration of the reference: its modes, internal rate and the distributed obstacles'
// contact grid, x_i = i L / intervals.
struct Rung
{
    int modes = 1001;
    double rateHz = 2e6;
    int intervals = 1002;
    bool extrapolated = false;  // rendered at rateHz and twice it: 2 y(2R) - y(R)
    bool staticExact = false;   // the static-exact forcing (a scene's "forcing": "static-exact")
};

struct Ladder
{
    const char* name;
    std::vector<Rung> rungs;
};

// `extend`: one rung more on each single knob (8003 modes, 32 MHz, L/8016 and L/16032), all cheap
// on the projection path with few contact points.
inline std::vector<Ladder> allLadders(bool extend)
{
    std::vector<Ladder> ladders{
        {"modes", {{1001, 2e6, 1002}, {2003, 2e6, 1002}, {4001, 2e6, 1002}}},
        {"rate", {{1001, 2e6, 1002}, {1001, 4e6, 1002}, {1001, 8e6, 1002}, {1001, 16e6, 1002}}},
        {"spacing", {{1001, 2e6, 1002}, {1001, 2e6, 2004}, {1001, 2e6, 4008}}},
        {"all", {{1001, 2e6, 1002}, {2003, 4e6, 2004}, {4001, 8e6, 4002}, {4001, 16e6, 4002}}},
        // The modes again with the contact points as fine as the spacing ladder's last rung, so the
        // string between two points is never finer than the points (projection: off the grid).
        {"modes-fine", {{1001, 2e6, 16032}, {2003, 2e6, 16032}, {4001, 2e6, 16032}}},
        // Modes and rate together, the rate as the square of the modes (a stiff string's top mode
        // grows as M^2, so the step keeps its ratio to that mode's period), the points at L/16032.
        {"joint", {{1001, 2e6, 16032}, {2003, 8e6, 16032}, {4001, 32e6, 16032}}},
        // Modes and rate together with the rate extrapolated (the rate's first-order error cancelled),
        // the rate doubling with the modes.
        {"extrapolated", {{1001, 8e6, 16032, true}, {2003, 16e6, 16032, true}, {4001, 32e6, 16032, true}}},
        // The static-exact forcing (ModalSolverConfig::staticExactForcing), each knob alone from
        // (2003 modes, 2 MHz, L/16032): the modes at 4 MHz, the rate, the points.
        {"static-modes",
         {{1001, 4e6, 16032, false, true}, {2003, 4e6, 16032, false, true}, {4001, 4e6, 16032, false, true}}},
        {"static-rate",
         {{2003, 1e6, 16032, false, true},
          {2003, 2e6, 16032, false, true},
          {2003, 4e6, 16032, false, true},
          {2003, 8e6, 16032, false, true}}},
        {"static-spacing",
         {{2003, 2e6, 8016, false, true},
          {2003, 2e6, 16032, false, true},
          {2003, 2e6, 32064, false, true},
          {2003, 2e6, 64128, false, true}}}};
    if (extend)
    {
        ladders[0].rungs.push_back({8003, 2e6, 1002});
        ladders[1].rungs.push_back({1001, 32e6, 1002});
        ladders[2].rungs.push_back({1001, 2e6, 8016});
        ladders[2].rungs.push_back({1001, 2e6, 16032});
        ladders[5].rungs.push_back({8003, 128e6, 16032});
        ladders[6].rungs.push_back({8003, 64e6, 16032, true});
    }
    return ladders;
}

struct Options
{
    std::string scenePath = std::string(JAWARI_RESOURCES_DIR) + "/Scenes/sitar-bridge.json";
    double duration = 0.1;
    std::vector<std::string> knobs{"modes", "rate", "spacing", "all", "modes-fine", "joint", "extrapolated"};
    size_t rungs = 100;
    std::string cacheDir;
    bool floor = true;
    bool extend = false;
    std::vector<Rung> custom;  // --ladder: its own rungs, run after the named knobs
    unsigned jobs = std::max(1u, std::thread::hardware_concurrency());
};

inline const char* kUsage = "usage: jawari-convergence [--scene FILE] [--duration S]\n"
                     "                          [--knobs modes,rate,spacing,all,modes-fine,joint,extrapolated,\n"
                     "                                   static-modes,static-rate,static-spacing]\n"
                     "                          [--rungs N] [--ladder M:RATE:N[:x|:s|:xs],...] [--cache DIR] "
                     "[--no-floor] [--extend] [--quick]\n"
                     "                          [--jobs N]\n";

inline std::vector<std::string> splitCommas(const std::string& text)
{
    std::vector<std::string> parts;
    size_t begin = 0;
    while (begin <= text.size())
    {
        const size_t end = std::min(text.find(',', begin), text.size());
        parts.push_back(text.substr(begin, end - begin));
        begin = end + 1;
    }
    return parts;
}

// A whole-string number, or NaN.
inline double parseNumber(const char* text)
{
    char* end = nullptr;
    const double v = std::strtod(text, &end);
    return end != text && *end == '\0' ? v : std::nan("");
}

inline bool fail(const std::string& message)
{
    std::fprintf(stderr, "jawari-convergence: %s\n%s", message.c_str(), kUsage);
    return false;
}

// "M:rate:intervals[:x],...": at least two rungs of whole modes and intervals, a rate in Hz.
inline bool parseLadder(const std::string& text, std::vector<Rung>& rungs)
{
    for (const auto& item : splitCommas(text))
    {
        Rung r;
        int used = 0;
        const bool read = std::sscanf(item.c_str(), "%d:%lf:%d%n", &r.modes, &r.rateHz, &r.intervals, &used) == 3;
        const std::string rest = read ? item.substr(size_t(used)) : std::string();
        r.extrapolated = rest == ":x" || rest == ":xs";
        r.staticExact = rest == ":s" || rest == ":xs";
        if (!read || !(rest.empty() || r.extrapolated || r.staticExact) || r.modes < 1 || r.modes > 100000
            || !(r.rateHz >= 1e3 && r.rateHz <= 1e9) || r.intervals < 2)
            return fail("--ladder rung '" + item
                        + "' is not M:rate_hz:intervals[:x|:s|:xs] (M 1..100000, rate 1e3..1e9 "
                          "Hz, intervals >= 2; x the rate extrapolated, s the static-exact forcing)");
        rungs.push_back(r);
    }
    return rungs.size() >= 2 || fail("--ladder needs at least two rungs");
}

// Reads the command line into `o`; false (after a message) on anything it does not understand.
inline bool parseOptions(int argc, char** argv, Options& o)
{
    const std::vector<std::string> known{"modes", "rate",         "spacing",      "all",         "modes-fine",
                                         "joint", "extrapolated", "static-modes", "static-rate", "static-spacing"};
    for (int i = 1; i < argc; ++i)
    {
        const std::string a = argv[i];
        const bool hasValue = i + 1 < argc;
        if (a == "--quick")
            o.rungs = 2;
        else if (a == "--no-floor")
            o.floor = false;
        else if (a == "--extend")
            o.extend = true;
        else if (a == "--scene" || a == "--duration" || a == "--knobs" || a == "--rungs" || a == "--cache"
                 || a == "--ladder" || a == "--jobs")
        {
            if (!hasValue)
                return fail(a + " needs a value");
            const char* v = argv[++i];
            if (a == "--scene")
                o.scenePath = v;
            else if (a == "--cache")
                o.cacheDir = v;
            else if (a == "--ladder")
            {
                if (!parseLadder(v, o.custom))
                    return false;
            }
            else if (a == "--duration")
            {
                o.duration = parseNumber(v);
                if (!(o.duration >= 0.05 && o.duration <= 10.0))
                    return fail(std::string("--duration must be a number of seconds in [0.05, 10], got '") + v + "'");
            }
            else if (a == "--jobs")
            {
                const double n = parseNumber(v);
                if (!(n >= 1.0 && n <= 256.0 && n == std::floor(n)))
                    return fail(std::string("--jobs must be a whole number from 1 to 256, got '") + v + "'");
                o.jobs = static_cast<unsigned>(n);
            }
            else if (a == "--rungs")
            {
                const double n = parseNumber(v);
                if (!(n >= 1.0 && n <= 100.0 && n == std::floor(n)))
                    return fail(std::string("--rungs must be a whole number from 1 to 100, got '") + v + "'");
                o.rungs = static_cast<size_t>(n);
            }
            else
            {
                o.knobs = *v == '\0' ? std::vector<std::string>{} : splitCommas(v);
                for (const auto& k : o.knobs)
                    if (std::find(known.begin(), known.end(), k) == known.end())
                        return fail("unknown knob '" + k
                                    + "' (knobs: modes, rate, spacing, all, modes-fine, joint, extrapolated, "
                                      "static-modes, static-rate, static-spacing)");
            }
        }
        else
            return fail("unknown option '" + a + "'");
    }
    return true;
}

}  // namespace jawari::convergence
