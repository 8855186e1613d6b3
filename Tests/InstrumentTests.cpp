// The playable instrument (Engine/Instrument.h): retuning, pitch, polyphony and stealing, sustain,
// the tanpura drone, structure swaps while sounding.

#include "TestSupport.h"
#include "offline/Analysis.h"
#include "realtime/instrument/Instrument.h"
#include "realtime/voice/Voice.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

using namespace jawari;

namespace
{
// Renders `seconds` of the instrument and returns the left channel.
std::vector<double> play(Instrument& instrument, double seconds, double rate = 48000.0, int block = 256)
{
    return test::playLeft(instrument, seconds, rate, block);
}

double largestStep(const std::vector<double>& y, size_t begin, size_t end)
{
    double m = 0.0;
    for (size_t n = std::max<size_t>(begin, 1); n < end && n < y.size(); ++n)
        m = std::max(m, std::abs(y[n] - y[n - 1]));
    return m;
}

constexpr int kHeldBlocks = 80;  // 8 s

InstrumentStructure freeStructure()
{
    InstrumentStructure s;
    s.quality = 0;  // draft: quick
    return s;
}

// The obstacle out of reach (1 cm below the string): a free string.
InstrumentControls freeControls()
{
    InstrumentControls c;
    c.obstacleHeight = -0.01;
    return c;
}
}  // namespace

TEST_CASE("A retuned voice equals a voice built for the scaled string", "[instrument]")
{
    // Every frequency scaled by r is the string with T and EI scaled by r^2 (B the same): the
    // residual compliance scales by 1/r^2 exactly, so the two voices must agree to rounding.
    const double r = std::pow(2.0, 7.0 / 12.0);
    VoiceConfig a;
    a.string = test::paperString();
    a.obstacles = {test::pointObstacle(0.501)};
    a.modes = 120;
    a.oversampling = 4;
    VoiceConfig b = a;
    b.string.tensionNewtons *= r * r;
    Voice built(b);
    Voice retuned(a);
    retuned.retune(r, built.solver().sigma().data());
    for (Voice* v : {&built, &retuned})
        v->setInitialShape(0.3, 1.5e-3);
    const double difference = test::relativeMaxDifference(retuned, built, 4800);
    INFO("difference " << difference << " of the peak");
    CHECK(difference < 1e-9);
}

TEST_CASE("Notes play in tune and pitch bend moves them", "[instrument]")
{
    auto pack = buildVoicePack(freeStructure());
    Instrument instrument;
    instrument.setControls(freeControls());
    instrument.install(pack.get(), nullptr);
    for (const auto& [note, hz] : {std::pair{69, 440.0}, std::pair{57, 220.0}, std::pair{62, 293.665}})
    {
        instrument.allNotesOff();
        play(instrument, 2.0);  // ring down
        instrument.noteOn(note, 0.8);
        const auto y = play(instrument, 1.0);
        const double f = peakFrequency(y, 48000.0, 0.8 * hz, 1.2 * hz, 4800);
        INFO("note " << note << ": " << f << " Hz, expected " << hz);
        CHECK(std::abs(f / hz - 1.0) < 1e-3);
    }
    // Bend up by the whole range (2 semitones): 62 -> 64.
    instrument.pitchBend(1.0);
    const auto y = play(instrument, 1.0);
    const double f = peakFrequency(y, 48000.0, 280.0, 360.0, 9600);
    INFO("bent " << f << " Hz, expected 329.63");
    CHECK(std::abs(f / 329.628 - 1.0) < 1e-3);
}

TEST_CASE("Eight strings sound at once and a ninth note steals without a click", "[instrument]")
{
    auto pack = buildVoicePack(freeStructure());
    Instrument instrument;
    instrument.setControls(freeControls());
    instrument.install(pack.get(), nullptr);
    for (int i = 0; i < 8; ++i)
        instrument.noteOn(48 + 3 * i, 0.9);
    const auto before = play(instrument, 0.5);
    CHECK(instrument.activeStrings() == 8);
    // Each pluck's pulse is the fastest thing in the sound; the steal must not be faster.
    const double normal = largestStep(before, 2400, before.size());
    instrument.noteOn(80, 0.9);
    const auto during = play(instrument, 0.1);
    const double steal = largestStep(during, 0, during.size());
    INFO("largest sample step: playing " << normal << ", around the steal " << steal);
    CHECK(steal < 1.5 * normal);
    CHECK(instrument.activeStrings() == 8);
    bool stolen = false;
    for (int s = 0; s < kMidiVoices; ++s)
        stolen = stolen || instrument.slotNote(s) == 80;
    CHECK(stolen);
}

TEST_CASE("The voice limit: notes beyond it steal, and a lowered limit fades the strings above it without a click",
          "[instrument]")
{
    auto pack = buildVoicePack(freeStructure());
    Instrument instrument;
    auto controls = freeControls();
    controls.midiVoices = 3;
    test::start(instrument, *pack, controls);
    for (int i = 0; i < 5; ++i)
        instrument.noteOn(48 + 3 * i, 0.9);
    const auto three = play(instrument, 0.5);
    CHECK(instrument.activeStrings() == 3);
    // The two oldest notes were stolen: the three newest sound, in the first three strings.
    for (int s = 0; s < 3; ++s)
        CHECK(instrument.slotNote(s) >= 54);
    // Raised to eight, five notes sound together; lowered to two, the three above fade out.
    controls.midiVoices = 8;
    instrument.setControls(controls);
    for (int i = 0; i < 5; ++i)
        instrument.noteOn(61 + 2 * i, 0.9);
    const auto eight = play(instrument, 0.5);
    CHECK(instrument.activeStrings() == 8);
    const double normal = largestStep(eight, 2400, eight.size());
    controls.midiVoices = 2;
    instrument.setControls(controls);
    const auto lowered = play(instrument, 0.1);
    const double fade = largestStep(lowered, 0, lowered.size());
    INFO("largest sample step: playing " << normal << ", as the limit falls " << fade);
    CHECK(fade < 1.5 * normal);
    CHECK(instrument.activeStrings() == 2);
    // Nothing above the limit takes a note, and the two below it still play theirs.
    instrument.noteOn(90, 0.9);
    play(instrument, 0.1);
    CHECK(instrument.activeStrings() == 2);
    for (int s = 2; s < kMidiVoices; ++s)
        CHECK(!instrument.slotSounding(s));
}

TEST_CASE("A note waiting for a string above a lowered voice limit plays within it", "[instrument]")
{
    auto pack = buildVoicePack(freeStructure());
    Instrument instrument;
    auto controls = freeControls();
    test::start(instrument, *pack, controls);
    for (int i = 0; i < 8; ++i)
        instrument.noteOn(48 + 3 * i, 0.9);
    play(instrument, 0.2);
    instrument.noteOff(48 + 3 * 5, 0);  // the one released string: the next note steals it
    play(instrument, 0.05);
    instrument.noteOn(95, 0.9);
    controls.midiVoices = 2;
    instrument.setControls(controls);
    play(instrument, 0.1);
    bool within = false;
    for (int s = 0; s < 2; ++s)
        within = within || (instrument.slotNote(s) == 95 && instrument.slotSounding(s));
    CHECK(within);
    CHECK(instrument.activeStrings() == 2);
}

TEST_CASE("The sustain pedal holds released notes until it is lifted", "[instrument]")
{
    auto pack = buildVoicePack(freeStructure());
    Instrument pedal, plain;
    for (Instrument* i : {&pedal, &plain})
    {
        i->setControls(freeControls());
        i->install(pack.get(), nullptr);
    }
    auto pack2 = buildVoicePack(freeStructure());
    plain.install(pack2.get(), nullptr);
    pedal.sustain(true);
    for (Instrument* i : {&pedal, &plain})
    {
        i->noteOn(60, 0.8);
        play(*i, 0.2);
        i->noteOff(60);
    }
    const auto held = play(pedal, 0.6);
    const auto released = play(plain, 0.6);
    auto rms = [](const std::vector<double>& y) {
        double s = 0.0;
        for (size_t n = y.size() - 4800; n < y.size(); ++n)
            s += y[n] * y[n];
        return std::sqrt(s / 4800);
    };
    INFO("last 0.1 s rms: sustained " << rms(held) << ", released " << rms(released));
    CHECK(rms(released) < 0.05 * rms(held));
    pedal.sustain(false);
    play(pedal, 2.0);
    CHECK(pedal.activeStrings() == 0);
}

TEST_CASE("The tanpura drone plucks Pa Sa Sa Sa in cycle on its own bridges", "[instrument]")
{
    InstrumentStructure s;
    s.quality = 0;
    s.obstaclePosition = 0.006;  // the tanpura's bridge near the end
    auto pack = buildVoicePack(s);
    Instrument instrument;
    InstrumentControls c;
    c.drone = true;
    c.droneTuning = DroneTuning::equal;  // the equal-tempered notes below; the just ones in TuningTests
    c.droneTempo = 120.0;                // a pluck every 0.5 s, 1 s after the low Sa: a 2.5 s cycle
    c.humanise = 0.0;
    c.droneTonic = 49;
    instrument.setControls(c);
    instrument.install(pack.get(), nullptr);
    const auto y = play(instrument, 5.0);
    INFO("plucks in 5 s: " << instrument.dronePlucks());
    CHECK(instrument.dronePlucks() == 8);                  // t = 0, .5, 1, 1.5 | 2.5, 3, 3.5, 4
    const int expected[kDroneStrings] = {44, 49, 49, 37};  // Pa below Sa, Sa, Sa, low Sa
    for (int i = 0; i < kDroneStrings; ++i)
    {
        CHECK(instrument.slotNote(kMidiVoices + i) == expected[i]);
        const double f = pack->baseFundamentalHz * instrument.slotRatio(kMidiVoices + i);
        CHECK(std::abs(f / (440.0 * std::pow(2.0, (expected[i] - 69) / 12.0)) - 1.0) < 1e-12);
    }
    double peak = 0.0;
    for (double v : y)
        peak = std::max(peak, std::abs(v));
    INFO("peak " << peak << ", blow-ups " << instrument.blowUps() << ", samples limited "
                 << instrument.limitedSamples());
    CHECK(peak > 0.01);
    CHECK(peak < 1.0);  // below full scale, the output guard (at 4) untouched
    CHECK(instrument.blowUps() == 0);
    CHECK(instrument.limitedSamples() == 0);
}

TEST_CASE("A new obstacle position takes over the sounding string without a jump", "[instrument]")
{
    InstrumentStructure s = freeStructure();
    s.obstaclePosition = 0.3;
    auto first = buildVoicePack(s);
    s.obstaclePosition = 0.32;
    auto second = buildVoicePack(s);
    Instrument instrument;
    InstrumentControls c;
    c.obstacleHeight = 0.0;
    instrument.setControls(c);
    instrument.install(first.get(), nullptr);
    instrument.noteOn(55, 0.9);
    const auto before = play(instrument, 0.5);
    const double normal = largestStep(before, 2400, before.size());
    instrument.install(second.get(), first.get());
    const auto after = play(instrument, 0.2);
    std::vector<double> joined(before.end() - 100, before.end());
    joined.insert(joined.end(), after.begin(), after.end());
    const double swap = largestStep(joined, 0, joined.size());
    INFO("largest sample step: before " << normal << ", across the swap " << swap);
    CHECK(swap < 1.5 * normal);
    CHECK(instrument.activeStrings() == 1);
}

TEST_CASE("A held string's fast modes decay through the instrument's render to zero, never to a subnormal number",
          "[instrument]")
{
    // Instrument::render steps the strings with flush-to-zero: a mode decays through the subnormal
    // range (below 2.2e-308) straight to zero instead of crawling through it slowly. A held note's
    // high modes decay far faster than its fundamental (Valette's law), so they pass that range
    // while the string still sounds. The test sets no floating-point mode of its own: it sees
    // subnormal numbers unless the render flushes them.
    volatile double tiny = 1e-300;
    REQUIRE(tiny * 1e-10 != 0.0);  // this thread keeps subnormal numbers
    auto pack = buildVoicePack(freeStructure());
    Instrument instrument;
    instrument.setControls(freeControls());
    instrument.install(pack.get(), nullptr);
    instrument.noteOn(60, 1.0);
    Voice& voice = *pack->voices[0];
    REQUIRE(instrument.slotNote(0) == 60);
    long subnormal = 0, zero = 0;
    std::vector<float> l(4800), r(4800);
    for (int b = 0; b < kHeldBlocks; ++b)  // 0.1 s each
    {
        instrument.render(l.data(), r.data(), 4800);
        zero = 0;
        for (bool previous : {false, true})
            for (double q : voice.solver().modalState(previous))
            {
                subnormal += std::fpclassify(q) == FP_SUBNORMAL ? 1 : 0;
                zero += q == 0.0 ? 1 : 0;
            }
    }
    INFO("after " << kHeldBlocks / 10.0 << " s: " << zero << " of " << 2 * pack->modes
                  << " modal values exactly zero; subnormal values seen after any block " << subnormal);
    CHECK(instrument.activeStrings() == 1);  // still sounding, still stepped
    CHECK(subnormal == 0);
    CHECK(zero > 0);  // the fast modes did reach the bottom of the range
}

TEST_CASE("MPE: one note bends on its own channel while another holds its pitch; pressure and slide act per note",
          "[instrument]")
{
    auto pack = buildVoicePack(freeStructure());
    Instrument instrument;
    instrument.setControls(freeControls());
    instrument.install(pack.get(), nullptr);
    instrument.noteOn(57, 0.8, 2);  // A3 on channel 2
    instrument.noteOn(52, 0.8, 3);  // E3 on channel 3
    play(instrument, 0.2);
    instrument.channelBend(2, 2.0);  // A3 up a whole tone, to B3
    const auto y = play(instrument, 1.2);
    const auto frequency = [&](int slot) { return pack->baseFundamentalHz * instrument.slotRatio(slot); };
    REQUIRE(instrument.slotChannel(0) == 2);
    REQUIRE(instrument.slotChannel(1) == 3);
    const double b3 = 440.0 * std::pow(2.0, -10.0 / 12.0), e3 = 440.0 * std::pow(2.0, -17.0 / 12.0);
    CHECK(std::abs(frequency(0) / b3 - 1.0) < 1e-12);
    CHECK(std::abs(frequency(1) / e3 - 1.0) < 1e-12);
    const double bent = peakFrequency(y, 48000.0, 235.0, 255.0, 9600, y.size() - 9600);
    const double held = peakFrequency(y, 48000.0, 158.0, 170.0, 9600, y.size() - 9600);
    INFO("bent note " << bent << " Hz (B3 " << b3 << "), held note " << held << " Hz (E3 " << e3 << ")");
    CHECK(std::abs(bent / b3 - 1.0) < 0.003);
    CHECK(std::abs(held / e3 - 1.0) < 0.003);

    // Pressure on channel 3 presses E3's bridge in by up to 0.5 mm; A3's stays.
    const double before = pack->voices[1]->solver().contact(0).height;
    instrument.channelPressure(3, 1.0);
    play(instrument, 0.01);
    CHECK(pack->voices[1]->solver().contact(0).height - before == Approx(Instrument::kPressureHeightMetres));
    CHECK(pack->voices[0]->solver().contact(0).height == before);
    // Slide 0 on channel 2 doubles A3's damping; E3's stays.
    const double sigmaA = pack->voices[0]->solver().sigma()[0], sigmaE = pack->voices[1]->solver().sigma()[0];
    instrument.channelSlide(2, 0.0);
    play(instrument, 0.01);
    CHECK(pack->voices[0]->solver().sigma()[0] / sigmaA == Approx(2.0).epsilon(1e-9));
    CHECK(pack->voices[1]->solver().sigma()[0] == sigmaE);
    // A note-off on another channel leaves the note alone; on its own, it releases it.
    instrument.noteOff(57, 3);
    CHECK(instrument.activeStrings() == 2);
    instrument.noteOff(57, 2);
    play(instrument, 3.0);
    CHECK(instrument.activeStrings() == 1);
}

TEST_CASE("The MIDI strings spread across the stereo field by pitch with a second pickup on the right, and width 0 "
          "is mono",
          "[instrument]")
{
    // Renders one note: the level of the right channel over the left, and their correlation.
    struct Image
    {
        double rightOverLeft = 0.0, correlation = 0.0;
    };
    auto image = [](int note, double width) {
        auto pack = buildVoicePack(freeStructure());
        Instrument instrument;
        auto c = freeControls();
        c.stereoWidth = width;
        instrument.setControls(c);
        instrument.install(pack.get(), nullptr);
        instrument.noteOn(note, 0.8);
        std::vector<float> l(4800), r(4800);
        instrument.render(l.data(), r.data(), 4800);
        double left = 0.0, right = 0.0, both = 0.0;
        for (size_t n = 0; n < l.size(); ++n)
        {
            left += double(l[n]) * l[n];
            right += double(r[n]) * r[n];
            both += double(l[n]) * r[n];
        }
        return Image{std::sqrt(right / left), both / std::sqrt(left * right + 1e-300)};
    };
    const Image low = image(48, 1.0), high = image(96, 1.0), middle = image(60, 0.6), mono = image(60, 0.0);
    INFO("right/left: C3 " << low.rightOverLeft << ", C7 " << high.rightOverLeft << ", C4 at width 0.6 "
                           << middle.rightOverLeft << " (correlation " << middle.correlation << "), at width 0 "
                           << mono.rightOverLeft << " (correlation " << mono.correlation << ")");
    CHECK(low.rightOverLeft < 1e-6);  // hard left
    CHECK(high.rightOverLeft > 1e6);  // hard right
    // Width 0.6: pan -0.3 (equal power: right/left = sqrt(0.7 / 1.3) = 0.73 for one pickup), the
    // right channel 0.4 of the first pickup and 0.6 of the second (at the first's level), so near
    // that level but not a copy of the left.
    CHECK(middle.rightOverLeft == Approx(std::sqrt(0.7 / 1.3)).epsilon(0.1));
    CHECK(middle.correlation < 0.999);
    CHECK(middle.correlation > 0.0);
    // Width 0: mono, the right channel the left's copy.
    CHECK(mono.rightOverLeft == Approx(1.0).epsilon(1e-12));
    CHECK(mono.correlation == Approx(1.0).epsilon(1e-12));
    CHECK(image(90, 0.0).rightOverLeft == Approx(1.0).epsilon(1e-12));
}

TEST_CASE("The instrument counts what it did: notes from rest, pulses, drone plucks, retunes, iterations",
          "[instrument]")
{
    auto pack = buildVoicePack(test::scriptStructure(ObstacleShape::point));
    Instrument instrument;
    instrument.install(pack.get(), nullptr);
    CHECK(instrument.activity().packsInstalled == 1);
    instrument.setControls(InstrumentControls{});
    instrument.settleControls();
    instrument.clearActivity();
    instrument.noteOn(55, 0.8);
    play(instrument, 0.2);
    const InstrumentActivity first = instrument.activity();
    CHECK(first.notesStarted == 1);
    CHECK(first.pulses == 0);
    CHECK(first.retunes >= 1);
    CHECK(first.newtonIterations > 100);  // the string lies on the tanpura's bridge
    CHECK(first.mostIterations >= 1);
    CHECK(first.mostIterations <= first.newtonIterations);

    instrument.clearActivity();
    instrument.noteOn(55, 0.8);  // again while it sounds: a pulse
    InstrumentControls drone;
    drone.drone = true;
    drone.droneTempo = 300.0;
    instrument.setControls(drone);
    play(instrument, 1.0);
    const InstrumentActivity second = instrument.activity();
    CHECK(second.notesStarted >= 1);  // the drone's first string starts from rest
    CHECK(second.pulses >= 1);
    CHECK(second.dronePlucks >= 4);
    CHECK(second.packsInstalled == 0);
}

TEST_CASE("With two polarisations the instrument plays in tune on the tanpura's point, and draws its vertical",
          "[instrument]")
{
    auto one = test::scriptStructure(ObstacleShape::point);
    auto two = one;
    two.polarisations = 2;
    auto packOne = buildVoicePack(one), packTwo = buildVoicePack(two);
    CHECK(packTwo->modes == 2 * packOne->modes);
    std::vector<double> outputs[2];
    InstrumentSnapshot snapshots[2];
    for (int k = 0; k < 2; ++k)
    {
        Instrument instrument;
        instrument.install(k == 0 ? packOne.get() : packTwo.get(), nullptr);
        instrument.setControls(InstrumentControls{});
        instrument.settleControls();
        instrument.noteOn(57, 0.8);
        outputs[k] = play(instrument, 1.0);
        REQUIRE(instrument.snapshots().read(snapshots[k]));
        CHECK(instrument.blowUps() == 0);
        CHECK(instrument.limitedSamples() == 0);
    }
    // The pitch one polarisation plays on this point (its contact raises it a little).
    const double f1 = peakFrequency(outputs[0], 48000.0, 180.0, 260.0, 4800);
    const double f2 = peakFrequency(outputs[1], 48000.0, 180.0, 260.0, 4800);
    INFO("A3: " << f1 << " Hz with one polarisation, " << f2 << " Hz with two");
    CHECK(std::abs(f2 / f1 - 1.0) < 1e-3);
    // The same pluck in the vertical: the two strings start alike and part as the coupling acts.
    const double early = relativeL2(outputs[1], outputs[0], 480), late = relativeL2(outputs[1], outputs[0], 48000);
    INFO("relative distance to one polarisation: " << early << " over 10 ms, " << late << " over 1 s");
    CHECK(early < 0.1);
    CHECK(late > 2.0 * early);
    // The editor's string: the vertical's shape, as large as one polarisation's, and the
    // horizontal's, which the coupling has set moving (with one polarisation: none). The horizontal
    // touches no obstacle, so it keeps what it takes: after 1 s about as much as the vertical.
    double most[2] = {0.0, 0.0}, across[2] = {0.0, 0.0};
    for (int k = 0; k < 2; ++k)
        for (int i = 0; i < kDrawPoints; ++i)
        {
            most[k] = std::max(most[k], double(std::abs(snapshots[k].shape[size_t(i)])));
            across[k] = std::max(across[k], double(std::abs(snapshots[k].horizontal[size_t(i)])));
        }
    INFO("largest drawn: vertical " << most[0] << " m with one polarisation; vertical " << most[1]
                                    << " m and horizontal " << across[1] << " m with two");
    CHECK(most[1] > 0.2 * most[0]);
    CHECK(most[1] < 5.0 * most[0]);
    CHECK_FALSE(snapshots[0].twoPolarisations);
    CHECK(across[0] == 0.0);
    CHECK(snapshots[1].twoPolarisations);
    // After 1 s the motion has turned: the horizontal as large as the vertical (measured 1.23x:
    // 1.53e-4 m against 1.24e-4 m), within 30 %.
    CHECK(across[1] / most[1] == Approx(1.23).epsilon(0.3));
}

TEST_CASE("The output guard acts and is counted: eight loud notes at +24 dB held at its ceiling, what lies "
          "between full scale and it passed", "[instrument]")
{
    // Eight loud notes at +24 dB: far beyond full scale, and beyond the guard's +12 dBFS.
    auto pack = buildVoicePack(freeStructure());
    Instrument instrument;
    auto c = freeControls();
    c.gainDb = 24.0;
    test::start(instrument, *pack, c);
    instrument.clearActivity();
    for (int i = 0; i < kMidiVoices; ++i)
        instrument.noteOn(48 + 2 * i, 1.0);
    std::vector<float> l(4800), r(4800);
    instrument.render(l.data(), r.data(), 4800);
    float peak = 0.0f;
    long beyondFullScale = 0;
    for (size_t n = 0; n < l.size(); ++n)
    {
        peak = std::max({peak, std::abs(l[n]), std::abs(r[n])});
        beyondFullScale += (std::abs(l[n]) > 1.0f ? 1 : 0) + (std::abs(r[n]) > 1.0f ? 1 : 0);
    }
    InstrumentSnapshot snapshot;
    REQUIRE(instrument.snapshots().read(snapshot));
    INFO("peak " << peak << ", samples beyond full scale " << beyondFullScale << ", limited "
                 << instrument.limitedSamples() << " (snapshot " << snapshot.limited << ")");
    CHECK(peak == kOutputCeiling);
    CHECK(instrument.limitedSamples() > 0);
    CHECK(beyondFullScale > instrument.limitedSamples());  // between full scale and the ceiling: passed
    CHECK(instrument.activity().limitedSamples == instrument.limitedSamples());
    CHECK(snapshot.limited > 0);
    CHECK(snapshot.limited <= instrument.limitedSamples());
    CHECK(instrument.blowUps() == 0);
}

TEST_CASE("The output guard zeroes non-finite samples and holds what lies beyond its ceiling there", "[instrument]")
{
    // The guard itself: NaN and the infinities, and what lies beyond the ceiling.
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    std::vector<float> y{0.5f, nan, inf, -inf, 4.0f, -4.5f, 3.9f, 1.5f, -1.0f};
    CHECK(guardOutput(y.data(), int(y.size())) == 4);
    CHECK(y == std::vector<float>{0.5f, 0.0f, 0.0f, 0.0f, 4.0f, -4.0f, 3.9f, 1.5f, -1.0f});
}

TEST_CASE("A string that runs away is restarted from rest and counted, the count outliving its pack", "[instrument]")
{
    // The explicit penalty force on the tanpura's point at draft's rate runs away: the voice's guard
    // restarts the string from rest, counted, and the count outlives the pack it happened in.
    auto s = test::scriptStructure(ObstacleShape::point);
    s.method = ContactMethod::penalty;
    auto pack = buildVoicePack(s), next = buildVoicePack(s);
    Instrument instrument;
    instrument.install(pack.get(), nullptr);
    instrument.setControls(InstrumentControls{});
    instrument.settleControls();
    instrument.noteOn(55, 1.0);
    play(instrument, 0.5);
    const long blowUps = instrument.blowUps();
    InstrumentSnapshot snapshot;
    REQUIRE(instrument.snapshots().read(snapshot));
    INFO("blow-ups " << blowUps << " (snapshot " << snapshot.blowUps << "), limited "
                     << instrument.limitedSamples());
    CHECK(blowUps > 0);
    CHECK(snapshot.blowUps > 0);
    CHECK(instrument.limitedSamples() == 0);  // the voice's guard muted it first
    instrument.install(next.get(), pack.get());
    CHECK(instrument.blowUps() == blowUps);
}
