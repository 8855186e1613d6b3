// Tuning (Engine/realtime/playing/Tuning.h): the drone's pure intervals, Scala scales and keyboard maps,
// and what the instrument plays with them.

#include "offline/Analysis.h"
#include "realtime/instrument/Instrument.h"
#include "realtime/playing/Tuning.h"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <string>
#include <vector>

using namespace jawari;

namespace
{
const char* kEqual12 = R"(! equal.scl
!
12-tone equal temperament
 12
!
 100.0
 200.
 300.0
 400.0
 500.0
 600.0
 700.0
 800.0
 900.0
 1000.0
 1100.0
 2/1
)";

const char* kJust12 = R"(! ji-12.scl
5-limit just intonation on C
12
16/15
9/8
6/5
5/4
4/3
45/32
3/2
8/5
5/3
9/5
15/8
2/1
)";

// The whole mapping of a 12-key octave with A4 (69) at 440 Hz: degree 0 on C (60).
const char* kMapA440 = R"(! a440.kbm
12
0
127
60
69
440.0
12
0
1
2
3
4
5
6
7
8
9
10
11
)";

// The drone's four strings as the instrument tunes them (slot pitches after a second of drone).
std::array<double, kDroneStrings> dronePitches(DroneTuning tuning)
{
    InstrumentStructure s;
    s.quality = 0;
    auto pack = buildVoicePack(s);
    Instrument instrument;
    InstrumentControls c;
    c.drone = true;
    c.droneTuning = tuning;
    c.droneTonic = 49;     // Sa = C#3
    c.droneTempo = 400.0;  // all four strings plucked within the first second
    c.humanise = 0.0;
    instrument.setControls(c);
    instrument.install(pack.get(), nullptr);
    std::vector<float> l(512), r(512);
    for (int block = 0; block < 94; ++block)
        instrument.render(l.data(), r.data(), 512);
    std::array<double, kDroneStrings> pitches{};
    for (int k = 0; k < kDroneStrings; ++k)
        pitches[size_t(k)] = instrument.slotPitch(kMidiVoices + k);
    return pitches;
}

// One free string (its bridge lowered out of reach, so its partials are clean) played at a pitch
// through the keyboard's tuning table, for `seconds`.
std::vector<double> renderString(double pitch, double seconds)
{
    InstrumentStructure s;
    s.quality = 0;
    s.pluckPosition = 0.27;  // off every node of the partials measured (a centre pluck has no even ones)
    auto pack = buildVoicePack(s);
    Instrument instrument;
    InstrumentControls c;
    c.obstacleHeight = -0.01;
    c.keyPitches[60] = pitch;
    instrument.setControls(c);
    instrument.install(pack.get(), nullptr);
    std::vector<double> out;
    std::vector<float> l(512), r(512);
    instrument.render(l.data(), r.data(), 512);  // the controls take effect
    instrument.noteOn(60, 0.8);
    const long total = std::lround(seconds * 48000.0);
    for (long n = 0; n < total; n += 512)
    {
        instrument.render(l.data(), r.data(), 512);
        out.insert(out.end(), l.begin(), l.end());
    }
    return out;
}

// Partial p of the instrument's default steel string at `pitch`: mode 1 sounds the pitch, mode p
// p sqrt(1 + B p^2) / sqrt(1 + B) times it.
double partialHz(double pitch, int p)
{
    const double B = 1.78e-5, f1 = 440.0 * std::pow(2.0, (pitch - 69.0) / 12.0);
    return p * f1 * std::sqrt(1.0 + B * p * p) / std::sqrt(1.0 + B);
}

// The frequency of partial p of a rendered string, measured over 1 s .. end (interpolated peak).
double measuredPartial(const std::vector<double>& y, double pitch, int p)
{
    const double expected = partialHz(pitch, p);
    return peakFrequency(y, 48000.0, expected - 0.5, expected + 0.5, 48000, y.size() - 48000);
}
// Parsing `text` throws a TuningError whose message contains `message`.
template <typename Parse>
void checkRefused(Parse parse, const char* text, const char* message)
{
    std::string what;
    try
    {
        parse();
    }
    catch (const TuningError& e)
    {
        what = e.what();
    }
    INFO("text '" << text << "': " << what);
    CHECK_THAT(what, Catch::Matchers::Contains(message));
}
}  // namespace

TEST_CASE("The drone's strings below Sa are pure intervals, or equal-tempered ones", "[tuning]")
{
    const double sa = 49.0;
    CHECK(dronePitch(0, sa, DroneFirstString::pa, DroneTuning::just)
          == Approx(sa + 12.0 * std::log2(0.75)).epsilon(1e-15));
    CHECK(dronePitch(0, sa, DroneFirstString::ma, DroneTuning::just) == Approx(sa + 12.0 * std::log2(2.0 / 3.0)));
    CHECK(dronePitch(0, sa, DroneFirstString::ni, DroneTuning::just) == Approx(sa + 12.0 * std::log2(15.0 / 16.0)));
    CHECK(dronePitch(0, sa, DroneFirstString::pa, DroneTuning::equal) == sa - 5.0);
    CHECK(dronePitch(0, sa, DroneFirstString::ni, DroneTuning::equal) == sa - 1.0);
    CHECK(dronePitch(1, sa, DroneFirstString::pa, DroneTuning::just) == sa);
    CHECK(dronePitch(3, sa, DroneFirstString::pa, DroneTuning::just) == sa - 12.0);
    // Ni 11.7 cents and Pa 2 cents off in equal temperament.
    CHECK(100.0 * (sa - 1.0 - dronePitch(0, sa, DroneFirstString::ni, DroneTuning::just))
          == Approx(11.73).margin(0.01));
    CHECK(100.0 * (dronePitch(0, sa, DroneFirstString::pa, DroneTuning::just) - (sa - 5.0))
          == Approx(1.955).margin(0.01));
}

TEST_CASE("The drone's partials that should coincide do in just intonation, and beat in equal temperament", "[tuning]")
{
    // Sa = C#3: Pa's 4th and Sa's 3rd partials lie near 415.8 Hz, 0.5 Hz apart in equal
    // temperament. Each string of the drone is rendered alone at the pitch the drone gives it
    // (6 s, measured over the last 5: 0.2 Hz bins, interpolated).
    for (const auto tuning : {DroneTuning::just, DroneTuning::equal})
    {
        const auto pitch = dronePitches(tuning);  // Pa, Sa, Sa, low Sa
        const auto pa = renderString(pitch[0], 6.0), sa = renderString(pitch[1], 6.0),
                   low = renderString(pitch[3], 6.0);
        const double pa4 = measuredPartial(pa, pitch[0], 4), sa3 = measuredPartial(sa, pitch[1], 3);
        const double sa1 = measuredPartial(sa, pitch[1], 1), low2 = measuredPartial(low, pitch[3], 2);
        const bool just = tuning == DroneTuning::just;
        INFO((just ? "just" : "equal") << ": Pa 4th " << pa4 << " Hz (model " << partialHz(pitch[0], 4) << "), Sa 3rd "
                                       << sa3 << " Hz, apart " << std::abs(pa4 - sa3) << " Hz; low Sa 2nd " << low2
                                       << " Hz, Sa 1st " << sa1 << " Hz");
        CHECK(pitch[1] == 49.0);
        CHECK(pitch[3] == 37.0);
        CHECK(std::abs(pa4 - partialHz(pitch[0], 4)) < 0.02);
        if (just)
            CHECK(std::abs(pa4 - sa3) < 0.1);
        else
            CHECK(std::abs(pa4 - sa3) > 0.4);
        CHECK(std::abs(low2 - sa1) < 0.1);
    }
}

TEST_CASE("A Scala scale in 12-tone equal temperament gives the keyboard's own pitches", "[tuning]")
{
    const auto scale = parseScalaScale(kEqual12);
    CHECK(scale.description == "12-tone equal temperament");
    REQUIRE(scale.cents.size() == 12);
    const auto pitches = keyboardPitches(scale, KeyboardMap{});
    double worst = 0.0;
    for (int n = 0; n < kMidiNotes; ++n)
        worst = std::max(worst, std::abs(pitches[size_t(n)] - n));
    INFO("worst deviation " << worst << " semitones");
    CHECK(worst < 1e-9);
    const auto mapped = keyboardPitches(scale, parseKeyboardMap(kMapA440));
    CHECK(std::abs(mapped[69] - 69.0) < 1e-9);
    CHECK(std::abs(mapped[60] - 60.0) < 1e-9);
}

TEST_CASE("A just scale with a keyboard map puts A4 at 440 Hz and C at 264 Hz", "[tuning]")
{
    const auto pitches = keyboardPitches(parseScalaScale(kJust12), parseKeyboardMap(kMapA440));
    auto hz = [&](int n) { return 440.0 * std::pow(2.0, (pitches[size_t(n)] - 69.0) / 12.0); };
    CHECK(hz(69) == Approx(440.0).epsilon(1e-12));
    CHECK(hz(60) == Approx(264.0).epsilon(1e-12));  // A = C 5/3
    CHECK(hz(67) == Approx(396.0).epsilon(1e-12));  // G = C 3/2
    CHECK(hz(72) == Approx(528.0).epsilon(1e-12));
    CHECK(hz(48) == Approx(132.0).epsilon(1e-12));
}

TEST_CASE("Unmapped keys stay silent", "[tuning]")
{
    // A 7-note (white keys only) map: the black keys are x.
    const auto map = parseKeyboardMap("12\n0\n127\n60\n69\n440\n7\n0\nx\n1\nx\n2\n3\nx\n4\nx\n5\nx\n6\n");
    const auto scale = parseScalaScale("diatonic\n7\n9/8\n5/4\n4/3\n3/2\n5/3\n15/8\n2/1\n");
    const auto pitches = keyboardPitches(scale, map);
    CHECK(std::isnan(pitches[61]));
    CHECK(std::isfinite(pitches[62]));
    CHECK(440.0 * std::pow(2.0, (pitches[72] - 69.0) / 12.0) == Approx(528.0).epsilon(1e-12));

    InstrumentStructure s;
    s.quality = 0;
    auto pack = buildVoicePack(s);
    Instrument instrument;
    InstrumentControls c;
    c.keyPitches = pitches;
    instrument.setControls(c);
    instrument.install(pack.get(), nullptr);
    std::vector<float> l(64), r(64);
    instrument.render(l.data(), r.data(), 64);  // the controls take effect
    instrument.noteOn(61, 0.8);
    CHECK(instrument.activeStrings() == 0);
    instrument.noteOn(62, 0.8);
    CHECK(instrument.activeStrings() == 1);
    CHECK(instrument.slotPitch(0) == pitches[62]);
}

TEST_CASE("Bad Scala files are rejected with a message naming the problem", "[tuning]")
{
    const std::pair<const char*, const char*> scales[] = {
        {"", "needs a description line"},
        {"name\n3\n100.0\n200.0\n", "announces 3 pitches but gives 2"},
        {"name\nthree\n", "note count: 'three' is not a whole number"},
        {"name\n0\n", "note count must be 1 to 1024"},
        {"name\n2\n100.0\nabc\n", "line 4: ratio: 'abc' is not a whole number"},
        {"name\n2\n3/0\n2/1\n", "line 3: ratio '3/0' must be positive"},
        {"name\n2\n-3/2\n2/1\n", "must be positive"},
        {"name\n1\n-100.0\n", "the period (the last pitch) must be above"},
        {"name\n1\n1e999.0\n", "is not a number"},
    };
    for (const auto& [text, message] : scales)
        checkRefused([&] { parseScalaScale(text); }, text, message);
    const std::pair<const char*, const char*> maps[] = {
        {"12\n0\n127\n", "needs 7 header values"},
        {"12\n0\n200\n60\n69\n440\n12\n", "note numbers must be 0 to 127 (got 200)"},
        {"12\n0\n127\n60\n69\n-440\n12\n", "reference frequency must be positive"},
        {"129\n0\n127\n60\n69\n440\n12\n", "map size must be 0 to 128"},
        {"2\n0\n127\n60\n69\n440\n12\n0\ny\n", "map entry: 'y' is not a whole number"},
    };
    for (const auto& [text, message] : maps)
        checkRefused([&] { parseKeyboardMap(text); }, text, message);
}
