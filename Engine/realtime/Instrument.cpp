#include "realtime/Instrument.h"

#include "realtime/Denormals.h"
#include "realtime/VoiceStealing.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace jawari
{
namespace
{
constexpr double kPluckMetresPerVelocity = 1.5e-3 * 127.0 / 100.0;  // MIDI velocity 100: 1.5 mm
constexpr double kFadeSeconds = 0.005;                              // a stolen string fades out over this
constexpr double kSilentFraction = 1e-10;  // a string below -100 dB of its peak energy stops sounding
constexpr int kRetuneChunks = 4;           // a moving bend retunes every 4 chunks (128 samples)

double clampFraction(double x)
{
    return std::clamp(x, 0.005, 0.995);
}

// The right channel's pickup: kSecondPickupOffset further from the nearer end than the first.
double secondPickupFraction(double pickup)
{
    const double x = clampFraction(pickup);
    return std::clamp(x > 0.5 ? x - kSecondPickupOffset : x + kSecondPickupOffset, 0.02, 0.98);
}
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

StringParameters instrumentString(const InstrumentStructure& s)
{
    const auto& type = kStringTypes[std::clamp(s.stringType, 0, kStringTypeCount - 1)];
    StringParameters p;
    p.lengthMetres = type.lengthMetres;
    p.linearDensity = type.linearDensity;
    p.diameterMetres = type.diameterMetres;
    const double c = 2.0 * type.lengthMetres * type.fundamentalHz;
    p.tensionNewtons = type.linearDensity * c * c;
    p.inharmonicity = std::max(0.0, s.inharmonicity);
    return p;
}

std::vector<Obstacle> instrumentObstacles(const InstrumentStructure& s, const ContactLaw& law, double height)
{
    const double L = instrumentString(s).lengthMetres;
    std::vector<Obstacle> obstacles;
    Obstacle o;
    o.law = law;
    o.height = height;
    o.width = std::max(s.obstacleWidth, 1e-5);
    switch (s.shape)
    {
        case ObstacleShape::point:
            o.type = ObstacleType::point;
            o.position = clampFraction(s.obstaclePosition) * L;
            obstacles.push_back(o);
            break;
        case ObstacleShape::parabola:
            o.type = ObstacleType::parabola;
            o.position = clampFraction(s.obstaclePosition) * L;
            o.curvature = std::max(0.0, s.curvature);
            obstacles.push_back(o);
            break;
        case ObstacleShape::frets:
            o.type = ObstacleType::point;
            for (int k = 1; k <= 5; ++k)
            {
                o.position = L * std::pow(2.0, -k / 12.0);
                obstacles.push_back(o);
            }
            break;
    }
    return obstacles;
}

VoiceQuality instrumentQuality(const InstrumentStructure& s)
{
    const auto settings = qualitySettings(s.shape == ObstacleShape::parabola ? ObstacleKind::bridge : ObstacleKind::points);
    const int q = std::clamp(s.quality, 0, static_cast<int>(settings.size()) - 1);
    return resolveQuality(settings[size_t(q)], instrumentString(s), s.hostRateHz);
}

std::unique_ptr<VoicePack> buildVoicePack(const InstrumentStructure& structure)
{
    auto pack = std::make_unique<VoicePack>();
    pack->structure = structure;
    pack->string = instrumentString(structure);
    const auto quality = instrumentQuality(structure);
    VoiceConfig config;
    config.string = pack->string;
    config.obstacles = instrumentObstacles(structure, ContactLaw{}, 0.0);
    const double L = pack->string.lengthMetres;
    config.excitationPosition = clampFraction(structure.pluckPosition) * L;
    config.pickupPosition = clampFraction(structure.pickupPosition) * L;
    config.secondPickupPosition = secondPickupFraction(structure.pickupPosition) * L;
    config.quantity = PickupQuantity::displacement;
    config.modes = quality.modes;
    config.oversampling = quality.oversampling;
    config.hostRateHz = structure.hostRateHz;
    config.releaseSeconds = std::max(structure.releaseSeconds, 0.01);
    // The quadratic spline solves decoupled points in closed form; the coupled points of a bridge
    // or of the frets take the energy-conserving Newton, the scheme it approximates.
    config.method = structure.method == ContactMethod::quadraticSpline && structure.shape != ObstacleShape::point
                        ? ContactMethod::energyConserving
                        : structure.method;
    config.keepEveryMode = true;
    const ModalSolverConfig solverConfig = voiceSolverConfig(config);
    for (int i = 0; i < kSlots; ++i)
        pack->voices.push_back(std::make_unique<Voice>(config, solverConfig));
    pack->modes = quality.modes;
    pack->baseFundamentalHz = solverConfig.modes.frequencyHz.front();
    pack->sigma.assign(size_t(kSlots) * quality.modes, 0.0);
    pack->drawShapes.resize(size_t(kDrawPoints) * quality.modes);
    pack->drawObstacle.assign(kDrawPoints, std::numeric_limits<double>::quiet_NaN());
    for (int k = 0; k < kDrawPoints; ++k)
    {
        const double x = L * k / (kDrawPoints - 1);
        for (int p = 1; p <= quality.modes; ++p)
            pack->drawShapes[size_t(k) * quality.modes + p - 1] = modeShape(L, p, x);
    }
    for (const auto& o : config.obstacles)
    {
        if (o.isDistributed())
        {
            for (int k = 0; k < kDrawPoints; ++k)
            {
                const double x = L * k / (kDrawPoints - 1);
                if (x >= o.supportBegin() && x <= o.supportEnd())
                    pack->drawObstacle[size_t(k)] = o.heightAt(x);
            }
        }
        else
        {
            const int k =
                std::clamp(static_cast<int>(std::lround(o.position / L * (kDrawPoints - 1))), 0, kDrawPoints - 1);
            pack->drawObstacle[size_t(k)] = o.height;
        }
    }
    pack->latencySamples = pack->voices.front()->latencySamples();
    pack->oversampling = quality.oversampling;
    pack->decimators.assign(2, Decimator(quality.oversampling, structure.hostRateHz));
    const size_t chunkSteps = size_t(Instrument::kChunk) * size_t(quality.oversampling);
    pack->mixLeft.assign(chunkSteps, 0.0);
    pack->mixRight.assign(chunkSteps, 0.0);
    pack->stringBlocks.assign(size_t(kSlots) * chunkSteps, 0.0);
    pack->secondBlocks.assign(size_t(kSlots) * chunkSteps, 0.0);
    auto pickupSine = [](double fraction) { return std::max(std::sin(std::numbers::pi * fraction), 0.02); };
    const double sine = pickupSine(clampFraction(structure.pickupPosition));
    pack->outputScale = 120.0 / sine;
    // The second pickup at the first's level by the same law (it sits further from the end, where
    // the string moves more).
    pack->secondPickupGain = sine / pickupSine(secondPickupFraction(structure.pickupPosition));
    return pack;
}

void VoicePack::takeMotionFrom(VoicePack& other)
{
    if (other.modes != modes || other.structure.hostRateHz != structure.hostRateHz)
        return;
    for (size_t i = 0; i < voices.size() && i < other.voices.size(); ++i)
        voices[i]->takeMotionFrom(*other.voices[i]);
    if (other.oversampling == oversampling)
        for (size_t c = 0; c < decimators.size(); ++c)
            decimators[c] = other.decimators[c];  // equal lengths: no allocation
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
    pack_ = pack;
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

double Instrument::noteRatio(double note) const
{
    const double f = current_.tuningA4Hz * std::pow(2.0, (note - 69.0) / 12.0);
    return f / pack_->baseFundamentalHz;
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

// A MIDI key: the pitch its tuning gives it (an unmapped key does not sound). The newest tuning
// applies at once: pitches are not smoothed.
void Instrument::startKey(int slot, int note, double velocity, int channel)
{
    const double pitch =
        note >= 0 && note < kMidiNotes ? target_.keyPitches[size_t(note)] : std::numeric_limits<double>::quiet_NaN();
    if (std::isfinite(pitch))
        start(slot, note, pitch, velocity, channel);
}

double Instrument::slotPitchNow(int slot) const
{
    const auto& s = slots_[size_t(slot)];
    if (slot >= kMidiVoices)
        return s.pitch;
    const double pitch = s.pitch + bendSmoothed_ * current_.bendRangeSemitones;
    return s.channel > 0 ? pitch + channels_[size_t(s.channel)].bend : pitch;
}

double Instrument::slotHeight(int slot) const
{
    const int channel = slots_[size_t(slot)].channel;
    return channel > 0 ? current_.obstacleHeight + kPressureHeightMetres * channels_[size_t(channel)].pressure
                       : current_.obstacleHeight;
}

double Instrument::keyboardPan(double pitch) const
{
    return current_.stereoWidth * std::clamp((pitch - 72.0) / 24.0, -1.0, 1.0);
}

void Instrument::channelBend(int channel, double semitones)
{
    if (channel >= 1 && channel <= 16)
        channels_[size_t(channel)].bend = std::isfinite(semitones) ? std::clamp(semitones, -96.0, 96.0) : 0.0;
}

void Instrument::channelPressure(int channel, double amount)
{
    if (channel < 1 || channel > 16)
        return;
    channels_[size_t(channel)].pressure = std::isfinite(amount) ? std::clamp(amount, 0.0, 1.0) : 0.0;
    pressureMoved_ = true;
}

void Instrument::channelSlide(int channel, double amount)
{
    if (channel < 1 || channel > 16)
        return;
    channels_[size_t(channel)].slide = std::isfinite(amount) ? std::clamp(amount, 0.0, 1.0) : 0.5;
    slideMoved_[size_t(channel)] = true;
}

void Instrument::start(int slot, int note, double pitch, double velocity, int channel)
{
    auto& s = slots_[size_t(slot)];
    auto& voice = *pack_->voices[size_t(slot)];
    const bool fromRest = !s.sounding || s.note != note;
    const bool newChannel = s.channel != channel;
    s.note = note;
    s.pitch = pitch;
    s.channel = channel;
    s.ratio = noteRatio(slotPitchNow(slot));
    if (newChannel)
        voice.setContactLaw(contactLaw(), slotHeight(slot));
    if (fromRest)
    {
        voice.silence();
        s.peakEnergy = 0.0;
    }
    retune(slot);
    voice.cancelRelease();
    if (fromRest)
    {
        voice.pluckFromShape(kPluckMetresPerVelocity * velocity);
        ++activity_.notesStarted;
    }
    else
    {
        voice.pluckWithPulse(velocity);
        ++activity_.pulses;
    }
    s.held = true;
    s.sustained = false;
    s.sounding = true;
    s.fade = -1;
    s.age = ++clock_;
}

void Instrument::noteOn(int note, double velocity, int channel)
{
    if (pack_ == nullptr)
        return;
    if (!(velocity > 0.0))
    {
        noteOff(note, channel);
        return;
    }
    velocity = std::min(velocity, 1.0);
    if (note < 0 || note >= kMidiNotes || !std::isfinite(target_.keyPitches[size_t(note)]))
        return;  // a key the tuning leaves unmapped
    // The same note rings on its own string: pluck it again (a string can be re-plucked while sounding).
    for (int i = 0; i < kMidiVoices; ++i)
    {
        auto& s = slots_[size_t(i)];
        if (s.fade >= 0 && s.pendingNote == note && s.pendingChannel == channel)
        {
            s.pendingVelocity = velocity;
            return;
        }
        if (s.sounding && s.fade < 0 && s.note == note && s.channel == channel)
        {
            startKey(i, note, velocity, channel);
            return;
        }
    }
    for (int i = 0; i < kMidiVoices; ++i)
        if (!slots_[size_t(i)].sounding)
        {
            startKey(i, note, velocity, channel);
            return;
        }
    // Steal: the quietest released string, else the oldest held one. It fades out over 5 ms first.
    std::array<StringActivity, kMidiVoices> strings;
    for (int i = 0; i < kMidiVoices; ++i)
    {
        const auto& s = slots_[size_t(i)];
        strings[size_t(i)] = {s.fade >= 0, s.held, s.sustained, s.age, 0.0};
        if (s.fade < 0 && !s.held && !s.sustained)
            strings[size_t(i)].energy = pack_->voices[size_t(i)]->stringEnergy();
    }
    int victim = chooseStolenString(strings.data(), kMidiVoices);
    if (victim < 0)
        victim = 0;  // every string is already fading: take over the first one's pending note
    auto& s = slots_[size_t(victim)];
    if (s.fade < 0)
        s.fade = fadeLength_;
    s.pendingNote = note;
    s.pendingChannel = channel;
    s.pendingVelocity = velocity;
    s.pendingHeld = true;
    s.pendingSustained = false;
}

void Instrument::noteOff(int note, int channel)
{
    if (pack_ == nullptr)
        return;
    for (int i = 0; i < kMidiVoices; ++i)
    {
        auto& s = slots_[size_t(i)];
        if (s.fade >= 0 && s.pendingNote == note && s.pendingChannel == channel && s.pendingHeld)
        {
            s.pendingHeld = false;
            s.pendingSustained = sustain_;
        }
        if (s.note != note || s.channel != channel || !s.held)
            continue;
        s.held = false;
        if (sustain_)
            s.sustained = true;
        else if (s.fade < 0)
            pack_->voices[size_t(i)]->release();
    }
}

void Instrument::sustain(bool down)
{
    sustain_ = down;
    if (down || pack_ == nullptr)
        return;
    for (int i = 0; i < kMidiVoices; ++i)
    {
        auto& s = slots_[size_t(i)];
        s.pendingSustained = false;
        if (s.sustained)
        {
            s.sustained = false;
            if (s.fade < 0)
                pack_->voices[size_t(i)]->release();
        }
    }
}

void Instrument::pitchBend(double amount)
{
    bend_ = std::isfinite(amount) ? std::clamp(amount, -1.0, 1.0) : 0.0;
}

void Instrument::allNotesOff()
{
    sustain_ = false;
    for (int i = 0; i < kMidiVoices; ++i)
    {
        auto& s = slots_[size_t(i)];
        s.held = s.sustained = false;
        s.pendingHeld = s.pendingSustained = false;
        if (pack_ != nullptr && s.fade < 0)
            pack_->voices[size_t(i)]->release();
    }
}

double Instrument::nextRandom()
{
    // xorshift32: deterministic, so a drone renders the same every time.
    random_ ^= random_ << 13;
    random_ ^= random_ >> 17;
    random_ ^= random_ << 5;
    return double(random_) / 2147483648.0 - 1.0;
}

void Instrument::dronePluck(int string)
{
    // Sa from its frequency when one is set, else from its MIDI note; the strings below it by pure
    // intervals or equal-tempered ones, each with its own fine tuning.
    const double sa = current_.droneSaHz > 0.0 ? pitchOfFrequency(current_.droneSaHz, current_.tuningA4Hz)
                                               : double(std::clamp(current_.droneTonic, 12, 108));
    const auto first = static_cast<DroneFirstString>(std::clamp(current_.droneFirst, 0, 3));
    const double pitch =
        dronePitch(string, sa, first, current_.droneTuning) + current_.droneFineCents[size_t(string)] / 100.0;
    const int slot = kMidiVoices + string;
    const double h = std::clamp(current_.humanise, 0.0, 1.0);
    const double velocity = std::clamp(current_.droneStrength * (1.0 + 0.25 * h * nextRandom()), 0.05, 1.0);
    start(slot, static_cast<int>(std::lround(pitch)), pitch, velocity);
    ++dronePlucks_;
    ++activity_.dronePlucks;
}

void Instrument::scheduleDrone(int samples)
{
    const bool on = current_.drone;
    if (on != droneOn_)
    {
        droneOn_ = on;
        droneCountdown_ = 0.0;
        droneNext_ = 0;
        if (!on)
            for (int i = 0; i < kDroneStrings; ++i)
            {
                auto& s = slots_[size_t(kMidiVoices + i)];
                s.held = false;
                if (s.sounding)
                    pack_->voices[size_t(kMidiVoices + i)]->release();
            }
    }
    if (!on)
        return;
    while (droneCountdown_ < 0.5)  // due within this chunk's first sample
    {
        dronePluck(droneNext_);
        // One beat between plucks, two after the low Sa: the cycle breathes before it starts again.
        const double beat = 60.0 / std::clamp(current_.droneTempo, 10.0, 400.0) * pack_->structure.hostRateHz;
        const double beats = droneNext_ == kDroneStrings - 1 ? 2.0 : 1.0;
        const double h = std::clamp(current_.humanise, 0.0, 1.0);
        droneCountdown_ += beats * beat * (1.0 + 0.15 * h * nextRandom());
        droneNext_ = (droneNext_ + 1) % kDroneStrings;
    }
    droneCountdown_ -= samples;
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
        if (++chunksSinceSnapshot_ * kChunk >= rate / 30.0)
        {
            publishSnapshot();
            chunksSinceSnapshot_ = 0;
            chunkPenetration_ = 0.0;
        }
    }
    limitOutput(left, right, numSamples);
}

void Instrument::settleControls()
{
    smoothControls(1.0);
}

// The controls' targets reached over a chunk: the obstacle (its height, stiffness geometrically,
// exponent) and the gain through a 20 ms one-pole (k20 its step over the chunk; 1 reaches them),
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
    current_.bendRangeSemitones =
        std::clamp(finiteOr(target_.bendRangeSemitones, defaults.bendRangeSemitones), 0.0, 24.0);
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
    std::array<Voice*, kSlots> voices{};
    std::array<double*, kSlots> blocks{}, seconds{};
    std::array<int, kSlots> sounding{};
    int n = 0;
    const size_t chunkSteps = size_t(kChunk) * size_t(pack_->oversampling);
    for (int i = 0; i < kSlots; ++i)
        if (slots_[size_t(i)].sounding || slots_[size_t(i)].fade >= 0)
        {
            voices[size_t(n)] = pack_->voices[size_t(i)].get();
            blocks[size_t(n)] = pack_->stringBlocks.data() + size_t(i) * chunkSteps;
            seconds[size_t(n)] = pack_->secondBlocks.data() + size_t(i) * chunkSteps;
            sounding[size_t(n++)] = i;
        }
    if (scheduling_ == StringScheduling::bank)
        bank_.process(voices.data(), blocks.data(), n, count, seconds.data());
    else
        for (int k = 0; k < n; ++k)
            voices[size_t(k)]->processInternal(blocks[size_t(k)], count, seconds[size_t(k)]);
    for (int k = 0; k < n; ++k)
        mixString(sounding[size_t(k)], blocks[size_t(k)], seconds[size_t(k)], count, gainStart);
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

// The stolen string is silent: the pending note starts from rest, released at once if its key
// was let go meanwhile.
void Instrument::startPendingNote(int slot)
{
    auto& s = slots_[size_t(slot)];
    auto& voice = *pack_->voices[size_t(slot)];
    voice.silence();
    s.sounding = false;
    startKey(slot, s.pendingNote, s.pendingVelocity, s.pendingChannel);
    s.pendingNote = -1;
    if (!s.pendingHeld)
    {
        s.held = false;
        s.sustained = s.pendingSustained;
        if (!s.sustained)
            voice.release();
    }
}

// Nothing non-finite and nothing beyond full scale reaches the host.
void Instrument::limitOutput(float* left, float* right, int numSamples)
{
    for (int n = 0; n < numSamples; ++n)
    {
        left[n] = std::isfinite(left[n]) ? std::clamp(left[n], -1.0f, 1.0f) : 0.0f;
        right[n] = std::isfinite(right[n]) ? std::clamp(right[n], -1.0f, 1.0f) : 0.0f;
    }
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
    std::array<double, kDrawPoints> u{};
    if (loudest >= 0)
        pack_->voices[size_t(loudest)]->solver().displacementAt(pack_->drawShapes.data(), kDrawPoints, u.data());
    for (int k = 0; k < kDrawPoints; ++k)
    {
        snap.shape[size_t(k)] = static_cast<float>(u[size_t(k)]);
        snap.obstacle[size_t(k)] = static_cast<float>(pack_->drawObstacle[size_t(k)] + current_.obstacleHeight);
    }
    snap.energy = static_cast<float>(total);
    snap.penetration = static_cast<float>(chunkPenetration_);
    snap.maxIterations = maxIterations_;
    snap.activeStrings = activeStrings();
    snap.blowUps = blowUps();
    snap.sequence = ++snapshotSequence_;
    snapshots_.publish();
}

}  // namespace jawari
