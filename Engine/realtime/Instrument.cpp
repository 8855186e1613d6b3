// The instrument's rendering: packs installed, the controls smoothed and applied (contact, damping,
// retunes), each chunk's strings stepped and mixed, the output guarded, the editor's snapshot.

#include "realtime/Instrument.h"

#include "realtime/Denormals.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace jawari
{
namespace
{
constexpr double kFadeSeconds = 0.005;     // a stolen string fades out over this
constexpr double kSilentFraction = 1e-10;  // a string below -100 dB of its peak energy stops sounding
constexpr int kRetuneChunks = 4;           // a moving bend retunes every 4 chunks (128 samples)
}  // namespace

double dampingCurveFrequency(int i)
{
    return 20.0 * std::pow(1000.0, double(i) / double(kDampingCurvePoints - 1));
}

double dampingCurveAt(const std::array<double, kDampingCurvePoints>& curve, double frequencyHz)
{
    const double position = std::log(std::max(frequencyHz, 1e-3) / 20.0) / std::log(1000.0) * (kDampingCurvePoints - 1);
    if (!(position > 0.0))
        return curve.front();
    if (position >= kDampingCurvePoints - 1)
        return curve.back();
    const int i = static_cast<int>(position);
    const double t = position - i;
    return std::exp((1.0 - t) * std::log(curve[size_t(i)]) + t * std::log(curve[size_t(i) + 1]));
}

Instrument::Instrument()
{
    const double pans[kDroneStrings] = {-0.6, -0.2, 0.2, 0.6};
    for (int i = 0; i < kDroneStrings; ++i)
        slots_[size_t(kMidiVoices + i)].pan = pans[i];
}

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
    fadeLength_ = std::max(1, static_cast<int>(std::lround(kFadeSeconds * pack->structure.hostRateHz)));
    dampingDirty_ = true;
    for (int i = 0; i < kSlots; ++i)
    {
        auto& s = slots_[size_t(i)];
        if (!carry)
        {
            s.sounding = false;
            s.fade = -1;
            pack_->voices[size_t(i)]->silence();
        }
        retune(i);
    }
    applyContact();
}

void Instrument::retune(int slot)
{
    if (pack_ == nullptr)
        return;
    ++activity_.retunes;
    auto& voice = *pack_->voices[size_t(slot)];
    const int M = pack_->modes;
    double* sigma = pack_->sigma.data() + size_t(slot) * M;
    const double r = slots_[size_t(slot)].ratio;
    StringParameters& string = pack_->string;
    const double baseTension = string.tensionNewtons;
    string.tensionNewtons = baseTension * r * r;  // B stays: EI scales with T
    string.damping.etaAir = DampingParameters{}.etaAir * std::max(current_.airScale, 0.0);
    string.damping.deltaVe = std::max(current_.deltaVe, 0.0);
    string.damping.qTeInv = std::max(current_.qTeInv, 0.0);
    const auto& f = voice.baseFrequencies();
    // The slide of the note's MPE channel: 0 doubles the damping, 1 halves it.
    const int channel = slots_[size_t(slot)].channel;
    const double slide = channel > 0 ? std::pow(4.0, 0.5 - channels_[size_t(channel)].slide) : 1.0;
    const double scale = std::max(current_.decayScale, 0.0) * slide;
    for (int p = 0; p < M; ++p)
    {
        const double fp = r * f[size_t(p)];
        sigma[p] =
            scale * dampingCurveAt(current_.dampingCurve, fp) * std::numbers::pi * fp * valetteInverseQ(string, fp);
    }
    string.tensionNewtons = baseTension;
    voice.retune(r, sigma);
}

void Instrument::applyContact()
{
    if (pack_ == nullptr)
        return;
    const ContactLaw law = contactLaw();
    for (int i = 0; i < kSlots; ++i)
        pack_->voices[size_t(i)]->setContactLaw(law, slotHeight(i));
}

ContactLaw Instrument::contactLaw() const
{
    return {std::max(current_.stiffness, 0.0), std::max(current_.exponent, 1.0)};
}

double Instrument::slotHeight(int slot) const
{
    const int channel = slots_[size_t(slot)].channel;
    return channel > 0 ? current_.obstacleHeight + kPressureHeightMetres * channels_[size_t(channel)].pressure
                       : current_.obstacleHeight;
}

void Instrument::render(float* left, float* right, int numSamples)
{
    ScopedFlushDenormals flush;
    std::fill(left, left + numSamples, 0.0f);
    std::fill(right, right + numSamples, 0.0f);
    if (pack_ == nullptr)
        return;
    const double rate = pack_->structure.hostRateHz;
    for (int offset = 0; offset < numSamples; offset += kChunk)
    {
        const int count = std::min(kChunk, numSamples - offset);
        const double gainStart = gain_;
        smoothControls(1.0 - std::exp(-count / (0.020 * rate)));
        retuneSounding(count, rate);
        scheduleDrone(count);
        mixChunk(left + offset, right + offset, count, gainStart);
        const long limited = guardOutput(left + offset, count) + guardOutput(right + offset, count);
        limitedSamples_ += limited;
        activity_.limitedSamples += limited;
        if (++chunksSinceSnapshot_ * kChunk >= rate / 30.0)
        {
            publishSnapshot();
            chunksSinceSnapshot_ = 0;
            chunkPenetration_ = 0.0;
        }
    }
}

void Instrument::settleControls()
{
    smoothControls(1.0);
}

// The controls' targets reached over a chunk: the obstacle (its height, stiffness geometrically,
// exponent), the bend range and the gain through a 20 ms one-pole (k20 its step over the chunk; 1 reaches them),
// the damping at once (then every string is retuned); a non-finite target keeps the current or
// default value.
void Instrument::smoothControls(double k20)
{
    static constexpr InstrumentControls defaults{};
    auto finiteOr = [](double v, double fallback) { return std::isfinite(v) ? v : fallback; };
    const double heightTarget = finiteOr(target_.obstacleHeight, current_.obstacleHeight);
    const double logK = std::log(std::max(current_.stiffness, 1.0));
    const double logKTarget = std::log(std::max(finiteOr(target_.stiffness, current_.stiffness), 1.0));
    const double exponentTarget = finiteOr(target_.exponent, current_.exponent);
    if (heightTarget != current_.obstacleHeight || logKTarget != logK || exponentTarget != current_.exponent)
    {
        auto approach = [&](double now, double goal, double tolerance) {
            return std::abs(goal - now) <= tolerance || k20 >= 1.0 ? goal : now + k20 * (goal - now);
        };
        current_.obstacleHeight = approach(current_.obstacleHeight, heightTarget, 1e-9);
        current_.stiffness = std::exp(approach(logK, logKTarget, 1e-6));
        current_.exponent = approach(current_.exponent, exponentTarget, 1e-6);
        applyContact();
    }
    if (target_.decayScale != current_.decayScale || target_.airScale != current_.airScale
        || target_.deltaVe != current_.deltaVe || target_.qTeInv != current_.qTeInv
        || target_.dampingCurve != current_.dampingCurve || target_.tuningA4Hz != current_.tuningA4Hz)
    {
        current_.decayScale = finiteOr(target_.decayScale, defaults.decayScale);
        current_.airScale = finiteOr(target_.airScale, defaults.airScale);
        current_.deltaVe = finiteOr(target_.deltaVe, defaults.deltaVe);
        current_.qTeInv = finiteOr(target_.qTeInv, defaults.qTeInv);
        for (int i = 0; i < kDampingCurvePoints; ++i)
            current_.dampingCurve[size_t(i)] =
                std::clamp(finiteOr(target_.dampingCurve[size_t(i)], 1.0), kDampingCurveMin, kDampingCurveMax);
        current_.tuningA4Hz = std::clamp(finiteOr(target_.tuningA4Hz, defaults.tuningA4Hz), 200.0, 1000.0);
        dampingDirty_ = true;
    }
    // The bend range glides too: a range switched at once would jump every bent string's pitch, and
    // pitch jumps repeated at audio rate pump energy into a string (each retune keeps its motion).
    const double rangeTarget = std::clamp(finiteOr(target_.bendRangeSemitones, defaults.bendRangeSemitones), 0.0, 24.0);
    const double range = current_.bendRangeSemitones;
    current_.bendRangeSemitones =
        std::abs(rangeTarget - range) < 1e-6 || k20 >= 1.0 ? rangeTarget : range + k20 * (rangeTarget - range);
    current_.gainDb = std::clamp(finiteOr(target_.gainDb, defaults.gainDb), -120.0, 24.0);
    current_.stereoWidth = std::clamp(finiteOr(target_.stereoWidth, defaults.stereoWidth), 0.0, 1.0);
    current_.drone = target_.drone;
    current_.droneTonic = target_.droneTonic;
    current_.droneFirst = target_.droneFirst;
    current_.droneTuning = target_.droneTuning;
    current_.droneSaHz = std::clamp(finiteOr(target_.droneSaHz, 0.0), 0.0, 2000.0);
    for (size_t k = 0; k < current_.droneFineCents.size(); ++k)
        current_.droneFineCents[k] = std::clamp(finiteOr(target_.droneFineCents[k], 0.0), -100.0, 100.0);
    current_.droneTempo = finiteOr(target_.droneTempo, defaults.droneTempo);
    current_.humanise = finiteOr(target_.humanise, 0.0);
    current_.droneStrength = std::clamp(finiteOr(target_.droneStrength, defaults.droneStrength), 0.0, 1.0);
    const double gainTarget = std::pow(10.0, current_.gainDb / 20.0);
    gain_ = std::abs(gainTarget - gain_) < 1e-6 || k20 >= 1.0 ? gainTarget : gain_ + k20 * (gainTarget - gain_);
}

// The bend through a 5 ms one-pole; a sounding string is retuned when its damping changed, or
// when its pitch moved and a retune is due (every kRetuneChunks, and when the bend settles).
void Instrument::retuneSounding(int count, double rate)
{
    const double k5 = 1.0 - std::exp(-count / (0.005 * rate));
    const double bendBefore = bendSmoothed_;
    bendSmoothed_ = std::abs(bend_ - bendSmoothed_) < 1e-6 ? bend_ : bendSmoothed_ + k5 * (bend_ - bendSmoothed_);
    const bool bendSettled = bendSmoothed_ == bend_ && bendBefore != bend_;
    ++chunkClock_;
    for (int i = 0; i < kSlots; ++i)
    {
        auto& s = slots_[size_t(i)];
        if (!s.sounding || s.fade >= 0)
            continue;
        const double wanted = noteRatio(slotPitchNow(i));
        const bool pitchMoved = std::abs(wanted / s.ratio - 1.0) > 1e-9;
        const bool due = bendSettled || chunkClock_ % kRetuneChunks == 0;
        if (dampingDirty_ || slideMoved_[size_t(s.channel)] || (pitchMoved && due))
        {
            s.ratio = wanted;
            retune(i);
        }
    }
    dampingDirty_ = false;
    slideMoved_.fill(false);
    if (pressureMoved_)
    {
        applyContact();
        pressureMoved_ = false;
    }
}

// Every sounding string's chunk at the internal rate (each voice alone, or the bank stepping them
// together), mixed into the left and right buffers, then decimated once per channel into left/right.
void Instrument::mixChunk(float* left, float* right, int count, double gainStart)
{
    const size_t internal = size_t(count) * size_t(pack_->oversampling);
    std::fill(pack_->mixLeft.begin(), pack_->mixLeft.begin() + long(internal), 0.0);
    std::fill(pack_->mixRight.begin(), pack_->mixRight.begin() + long(internal), 0.0);
    Sounding sounding;
    const size_t chunkSteps = size_t(kChunk) * size_t(pack_->oversampling);
    for (int i = 0; i < kSlots; ++i)
        if (slots_[size_t(i)].sounding || slots_[size_t(i)].fade >= 0)
        {
            const int k = sounding.count++;
            sounding.voices[size_t(k)] = pack_->voices[size_t(i)].get();
            sounding.blocks[size_t(k)] = pack_->stringBlocks.data() + size_t(i) * chunkSteps;
            sounding.seconds[size_t(k)] = pack_->secondBlocks.data() + size_t(i) * chunkSteps;
            sounding.slots[size_t(k)] = i;
        }
    stepStrings(sounding, count);
    for (int k = 0; k < sounding.count; ++k)
        mixString(sounding.slots[size_t(k)], sounding.blocks[size_t(k)], sounding.seconds[size_t(k)], count,
                  gainStart);
    const int os = pack_->oversampling;
    for (int m = 0; m < count; ++m)
    {
        left[m] += static_cast<float>(pack_->decimators[0].process(pack_->mixLeft.data() + size_t(m) * os));
        right[m] += static_cast<float>(pack_->decimators[1].process(pack_->mixRight.data() + size_t(m) * os));
    }
}

// One string's chunk at the internal rate (block), panned and added into the mix with the gain ramp
// from gainStart (and a steal's fade), both stepped per host sample; a stolen string that has faded
// out starts its pending note, and a string that has decayed to nothing stops sounding.
void Instrument::mixString(int slot, const double* block, const double* second, int count, double gainStart)
{
    auto& s = slots_[size_t(slot)];
    auto& voice = *pack_->voices[size_t(slot)];
    const int most = voice.takeMaxIterations();
    maxIterations_ = std::max(maxIterations_, most);
    activity_.mostIterations = std::max(activity_.mostIterations, most);
    activity_.newtonIterations += voice.takeIterationCount();
    chunkPenetration_ = std::max(chunkPenetration_, voice.takeMaxPenetration());
    const double level = slot < kMidiVoices ? 1.0 : 0.5;  // the drone's four strings share the headroom
    const double pan = slot < kMidiVoices ? keyboardPan(slotPitchNow(slot)) : s.pan;
    const double panLeft = level * std::sqrt(0.5 * (1.0 - pan)), panRight = level * std::sqrt(0.5 * (1.0 + pan));
    const double outputScale = pack_->outputScale;
    const int os = pack_->oversampling;
    // The right channel: the first pickup, the second mixed in with the width.
    const double secondShare = current_.stereoWidth * pack_->secondPickupGain, firstShare = 1.0 - current_.stereoWidth;
    for (int n = 0; n < count; ++n)
    {
        double g = gainStart + (gain_ - gainStart) * (n + 1) / count;
        if (s.fade >= 0)
        {
            g *= double(s.fade) / fadeLength_;
            if (s.fade > 0)
                --s.fade;
        }
        const double toLeft = panLeft * outputScale * g, toRight = panRight * outputScale * g;
        for (int k = n * os; k < (n + 1) * os; ++k)
        {
            pack_->mixLeft[size_t(k)] += toLeft * block[k];
            pack_->mixRight[size_t(k)] += toRight * (firstShare * block[k] + secondShare * second[k]);
        }
    }
    if (s.fade == 0)
    {
        startPendingNote(slot);
        return;
    }
    const double e = voice.stringEnergy();
    s.peakEnergy = std::max(s.peakEnergy, e);
    if (!(e > kSilentFraction * s.peakEnergy))
        s.sounding = false;
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

int Instrument::activeStrings() const
{
    int n = 0;
    for (const auto& s : slots_)
        n += s.sounding ? 1 : 0;
    return n;
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

void Instrument::publishSnapshot()
{
    auto& snap = snapshots_.back();
    int loudest = -1;
    double most = 0.0, total = 0.0;
    for (int i = 0; i < kSlots; ++i)
    {
        if (!slots_[size_t(i)].sounding)
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
        snap.obstacle[size_t(k)] = static_cast<float>(pack_->drawObstacle[size_t(k)] + current_.obstacleHeight);
    }
    snap.energy = static_cast<float>(total);
    snap.penetration = static_cast<float>(chunkPenetration_);
    snap.maxIterations = maxIterations_;
    snap.activeStrings = activeStrings();
    snap.blowUps = blowUps();
    snap.limited = limitedSamples_;
    snap.sequence = ++snapshotSequence_;
    snapshots_.publish();
}

}  // namespace jawari
