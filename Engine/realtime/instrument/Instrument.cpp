// The instrument's rendering: packs installed, and each chunk's steps in order: the controls and
// the notes' expression followed, the drone's plucks, the sounding strings stepped (InstrumentStrings.cpp)
// and mixed, the mix decimated, the output guarded, the editor's snapshot.

#include "realtime/instrument/Instrument.h"

#include "realtime/voice/Denormals.h"

#include <algorithm>
#include <cmath>

namespace jawari
{
namespace
{
constexpr double kSilentFraction = 1e-10;  // a string below -100 dB of its peak energy stops sounding

// A chunk's ramp from `from` to `to`, at the end of its host sample n of count.
double ramp(double from, double to, int n, int count)
{
    return from + (to - from) * (n + 1) / count;
}
}  // namespace

void Instrument::install(VoicePack* pack, VoicePack* previous)
{
    const bool carry = previous != nullptr && previous->modes == pack->modes
                       && previous->structure.hostRateHz == pack->structure.hostRateHz;
    if (carry)
        pack->takeMotionFrom(*previous);
    blowUpsRetired_ += packBlowUps() - blowUpsAtInstall_;
    pack_ = pack;
    blowUpsAtInstall_ = packBlowUps();
    ++activity_.packsInstalled;
    dampingDirty_ = true;
    // Strings leaving a body for rigid supports find their obstacles where its bridge stood.
    const bool offBody = carry && previous->body && !pack->body;
    strings_.install(*pack, carry, offBody ? previous->body->bridgeDisplacement() : 0.0);
    sympathetic_.install(*pack, carry);
    if (pack->body && !carry)
        pack->body->silence();
    else if (pack->body && previous->body)
        pack->body->takeMotionFrom(*previous->body);
}

void Instrument::noteOn(int note, double velocity, int channel)
{
    if (pack_ != nullptr)
        notes_.noteOn(note, velocity, channel);
}

void Instrument::noteOff(int note, int channel)
{
    if (pack_ != nullptr)
        notes_.noteOff(note, channel);
}

void Instrument::render(float* left, float* right, int numSamples)
{
    ScopedFlushDenormals flush;
    std::fill(left, left + numSamples, 0.0f);
    std::fill(right, right + numSamples, 0.0f);
    if (pack_ == nullptr)
        return;
    for (int offset = 0; offset < numSamples; offset += kChunk)
        renderChunk(left + offset, right + offset, std::min(kChunk, numSamples - offset));
}

void Instrument::renderChunk(float* left, float* right, int count)
{
    const double rate = pack_->structure.hostRateHz;
    const auto& c = controls_.current();
    const MixStart start{controls_.gain(), c.bodyMix, c.sympatheticLevel};
    followControls(1.0 - std::exp(-count / (0.020 * rate)));
    followExpression(count, rate);
    drone_.advance(count, controls_.current(), rate, strings_, activity_);
    notes_.fitVoiceLimit();
    tarafShareHeard_ = start.sympatheticLevel != 1.0 || controls_.current().sympatheticLevel != 1.0;
    Sounding sounding = soundingStrings();
    stepStrings(sounding, count);
    mixStrings(sounding, count, start);
    notes_.startStolenNotes();
    decimate(left, right, count);
    guard(left, right, count);
    publishSnapshotWhenDue(rate);
}

// The controls one chunk on (k20 the 20 ms one-pole's step over it): a moved obstacle re-applies
// the contact at once; moved damping retunes the sounding strings in followExpression; the body's
// width follows the stereo width.
void Instrument::followControls(double k20)
{
    const ControlChanges changes = controls_.advance(k20);
    const double width = controls_.current().stereoWidth;
    const bool arrived = std::isnan(bodyWidth_) || std::abs(width - bodyWidth_) < 1e-6;
    bodyWidth_ = arrived ? width : bodyWidth_ + k20 * (width - bodyWidth_);
    if (changes.contact && pack_ != nullptr)
        strings_.applyContact();
    dampingDirty_ = dampingDirty_ || changes.damping;
}

// The bend through a 5 ms one-pole; the sounding strings retuned where their damping, slide or
// pitch moved (StringSlots::retuneSounding).
void Instrument::followExpression(int count, double rate)
{
    const bool bendSettled = expression_.followBend(1.0 - std::exp(-count / (0.005 * rate)));
    strings_.retuneSounding(dampingDirty_, bendSettled);
    strings_.relaxCarriedBridge(count, rate);
    sympathetic_.follow(dampingDirty_);
    dampingDirty_ = false;
    expression_.clearMoves();
}

Instrument::Sounding Instrument::soundingStrings()
{
    Sounding sounding;
    const size_t chunkSteps = size_t(kChunk) * size_t(pack_->oversampling);
    for (int i = 0; i < kSlots; ++i)
        if (strings_[i].sounding || strings_[i].fade >= 0)
        {
            const int k = sounding.count++;
            sounding.voices[size_t(k)] = pack_->voices[size_t(i)].get();
            sounding.blocks[size_t(k)] = pack_->stringBlocks.data() + size_t(i) * chunkSteps;
            sounding.seconds[size_t(k)] = pack_->secondBlocks.data() + size_t(i) * chunkSteps;
            sounding.slots[size_t(k)] = i;
        }
    return sounding;
}

// Every sounding string's chunk at the internal rate, mixed into the left and right buffers.
void Instrument::mixStrings(const Sounding& sounding, int count, const MixStart& start)
{
    const auto internal = long(count) * pack_->oversampling;
    std::fill(pack_->mixLeft.begin(), pack_->mixLeft.begin() + internal, 0.0);
    std::fill(pack_->mixRight.begin(), pack_->mixRight.begin() + internal, 0.0);
    for (int k = 0; k < sounding.count; ++k)
        mixString(sounding.slots[size_t(k)], sounding.blocks[size_t(k)], sounding.seconds[size_t(k)], count, start);
    if (pack_->body)
        mixBody(count, start);
}

// One string's chunk at the internal rate (block, and its second pickup's), panned and added into
// the mix with the gain ramp from start.gain (and a steal's fade), both stepped per host sample. A
// string that has decayed to nothing stops sounding; one whose steal has faded out is left to
// MidiNotes::startStolenNotes.
void Instrument::mixString(int slot, const double* block, const double* second, int count, const MixStart& start)
{
    auto& s = strings_[slot];
    auto& voice = strings_.voice(slot);
    takeStatistics(voice);
    const auto& c = controls_.current();
    const double level = slot < kMidiVoices ? 1.0 : 0.5;  // the drone's four strings share the headroom
    // A MIDI string sits by its pitch: hard left at C3 and below, hard right at C7 and above, scaled by the width.
    const double pan =
        slot < kMidiVoices ? c.stereoWidth * std::clamp((strings_.pitchNow(slot) - 72.0) / 24.0, -1.0, 1.0) : s.pan;
    const double panLeft = level * std::sqrt(0.5 * (1.0 - pan)), panRight = level * std::sqrt(0.5 * (1.0 + pan));
    const double outputScale = pack_->outputScale;
    const int os = pack_->oversampling;
    // Without a body the right channel hears the first pickup and the second mixed in with the width;
    // with one, both channels hear the string's pickup (its velocity) beside the body's sound (mixBody),
    // by bodyMix.
    const bool body = pack_->body != nullptr;
    const double secondShare = body ? 0.0 : c.stereoWidth * pack_->secondPickupGain;
    const double firstShare = body ? 1.0 : 1.0 - c.stereoWidth;
    const double gainEnd = controls_.gain();
    for (int n = 0; n < count; ++n)
    {
        double g = ramp(start.gain, gainEnd, n, count);
        if (s.fade >= 0)
        {
            g *= double(s.fade) / strings_.fadeLength();
            if (s.fade > 0)
                --s.fade;
        }
        if (body)
            g *= (1.0 - ramp(start.bodyMix, c.bodyMix, n, count)) * pack_->secondPickupGain;
        const double toLeft = panLeft * outputScale * g, toRight = panRight * outputScale * g;
        for (int k = n * os; k < (n + 1) * os; ++k)
        {
            pack_->mixLeft[size_t(k)] += toLeft * block[k];
            pack_->mixRight[size_t(k)] += toRight * (firstShare * block[k] + secondShare * second[k]);
        }
    }
    if (s.fade == 0)
        return;
    const double e = voice.stringEnergy();
    s.peakEnergy = std::max(s.peakEnergy, e);
    if (!(e > kSilentFraction * s.peakEnergy) && !voice.pulsing())  // a push from rest starts at 0
        s.sounding = false;
}

// The body's radiated sound at each channel (its listeners as the stereo width mixes them:
// SharedBody::listenBetween) by the body's mix and the gain, with the sympathetic strings' share of
// it (the pressure their forces alone make) scaled by their level; all three ramped per host sample.
void Instrument::mixBody(int count, const MixStart& start)
{
    const auto& c = controls_.current();
    const int os = pack_->oversampling;
    const double gainEnd = controls_.gain(), centre = std::sqrt(0.5);
    const bool taraf = sympathetic_.count() > 0;
    const auto& body = pack_->bodyBlocks;
    const auto& part = pack_->sympatheticBlocks;
    for (int n = 0; n < count; ++n)
    {
        const double level =
            centre * pack_->outputScale * ramp(start.gain, gainEnd, n, count) * ramp(start.bodyMix, c.bodyMix, n, count);
        const double tarafCut = 1.0 - ramp(start.sympatheticLevel, c.sympatheticLevel, n, count);
        for (int k = n * os; k < (n + 1) * os; ++k)
        {
            const size_t i = size_t(k);
            double left = body[0][i], right = body[1][i];
            if (taraf)
            {
                left -= tarafCut * part[0][i];
                right -= tarafCut * part[1][i];
            }
            pack_->mixLeft[i] += level * left;
            pack_->mixRight[i] += level * right;
        }
    }
}

// The voice's solver statistics since the last chunk, into the instrument's.
void Instrument::takeStatistics(Voice& voice)
{
    const int most = voice.takeMaxIterations();
    maxIterations_ = std::max(maxIterations_, most);
    activity_.mostIterations = std::max(activity_.mostIterations, most);
    activity_.newtonIterations += voice.takeIterationCount();
    chunkPenetration_ = std::max(chunkPenetration_, voice.takeMaxPenetration());
}

// The mix decimated once per channel (the decimator is linear) into left/right.
void Instrument::decimate(float* left, float* right, int count)
{
    const int os = pack_->oversampling;
    for (int m = 0; m < count; ++m)
    {
        left[m] += static_cast<float>(pack_->decimators[0].process(pack_->mixLeft.data() + size_t(m) * os));
        right[m] += static_cast<float>(pack_->decimators[1].process(pack_->mixRight.data() + size_t(m) * os));
    }
}

void Instrument::guard(float* left, float* right, int count)
{
    const long limited = guardOutput(left, count) + guardOutput(right, count);
    limitedSamples_ += limited;
    activity_.limitedSamples += limited;
}

long guardOutput(float* samples, int numSamples)
{
    long changed = 0;
    for (int n = 0; n < numSamples; ++n)
    {
        const float v = samples[n];
        const float guarded = std::isfinite(v) ? std::clamp(v, -kOutputCeiling, kOutputCeiling) : 0.0f;
        changed += guarded != v ? 1 : 0;  // a NaN differs from its 0 too
        samples[n] = guarded;
    }
    return changed;
}

long Instrument::blowUps() const
{
    return blowUpsRetired_ + packBlowUps() - blowUpsAtInstall_;
}

long Instrument::packBlowUps() const
{
    long n = 0;
    if (pack_ != nullptr)
        for (const auto& v : pack_->voices)
            n += v->blowUps();
    return n;
}

// Thirty snapshots a second.
void Instrument::publishSnapshotWhenDue(double rate)
{
    if (++chunksSinceSnapshot_ * kChunk < rate / 30.0)
        return;
    publishSnapshot();
    chunksSinceSnapshot_ = 0;
    chunkPenetration_ = 0.0;
}

void Instrument::publishSnapshot()
{
    auto& snap = snapshots_.back();
    int loudest = -1;
    double most = 0.0, total = 0.0;
    for (int i = 0; i < kSlots; ++i)
    {
        if (!strings_[i].sounding)
            continue;
        const double e = pack_->voices[size_t(i)]->stringEnergy();
        total += e;
        if (e > most)
        {
            most = e;
            loudest = i;
        }
    }
    std::array<double, kDrawPoints> u{}, h{};
    const bool two = !pack_->drawHorizontal.empty();
    if (loudest >= 0)
    {
        auto& solver = pack_->voices[size_t(loudest)]->solver();
        solver.displacementAt(pack_->drawShapes.data(), kDrawPoints, u.data());
        if (two)
            solver.displacementAt(pack_->drawHorizontal.data(), kDrawPoints, h.data());
    }
    snap.twoPolarisations = two;
    for (int k = 0; k < kDrawPoints; ++k)
    {
        snap.shape[size_t(k)] = static_cast<float>(u[size_t(k)]);
        snap.horizontal[size_t(k)] = static_cast<float>(h[size_t(k)]);
        snap.obstacle[size_t(k)] =
            static_cast<float>(pack_->drawObstacle[size_t(k)] + controls_.current().obstacleHeight);
    }
    snap.energy = static_cast<float>(total);
    snap.penetration = static_cast<float>(chunkPenetration_);
    snap.maxIterations = maxIterations_;
    snap.activeStrings = strings_.sounding();
    snap.blowUps = blowUps();
    snap.limited = limitedSamples_;
    snap.sequence = ++snapshotSequence_;
    snapshots_.publish();
}

}  // namespace jawari
