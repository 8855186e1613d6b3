#pragma once
// What pitch each key and each drone string plays. Pitches are fractional MIDI note numbers
// (69 = A4 at the instrument's reference, 12 per octave), so a tuning never depends on the
// reference frequency and a pitch bend adds to it.
//
// The tanpura's drone is tuned by ear to pure intervals below Sa: Pa 3/4, Ma 2/3, Ni 15/16, low Sa
// 1/2. Equal temperament puts Ni 11.7 cents and Pa 2 cents off those, so their partials beat
// against Sa's where a real tanpura's lock.
//
// The keyboard plays equal temperament, or a Scala scale (.scl) with an optional keyboard map
// (.kbm), both in the format of the Scala program (huygens-fokker.org/scala). Parsing is OFF;
// the resulting table is plain data the audio thread reads.

#include <array>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace jawari
{

inline constexpr int kMidiNotes = 128;
using KeyboardPitches = std::array<double, kMidiNotes>;  // per MIDI note; NaN: the key is unmapped

constexpr KeyboardPitches equalTemperament()
{
    KeyboardPitches p{};
    for (int n = 0; n < kMidiNotes; ++n)
        p[size_t(n)] = n;
    return p;
}

enum class DroneTuning
{
    just,  // pure intervals (the default: how a tanpura is tuned)
    equal  // equal temperament
};

enum class DroneFirstString
{
    pa,  // a fifth below Sa: 3/4
    ma,  // a fourth below Sa: 2/3 (an octave below the fourth above)
    ni,  // a semitone below Sa: 15/16
    sa   // Sa itself
};

inline constexpr int kDroneStringCount = 4;  // the first string, Sa, Sa, low Sa

// The pitch of drone string k (0: the first string, 1 and 2: Sa, 3: low Sa) for Sa at saPitch,
// before any fine tuning. RT.
double dronePitch(int k, double saPitch, DroneFirstString first, DroneTuning tuning);

// 69 + 12 log2(f / a4Hz): the pitch of a frequency. RT.
inline double pitchOfFrequency(double hz, double a4Hz)
{
    return 69.0 + 12.0 * std::log2(hz / a4Hz);
}

// a4Hz 2^((pitch - 69) / 12): the frequency of a pitch. RT.
inline double frequencyOfPitch(double pitch, double a4Hz)
{
    return a4Hz * std::pow(2.0, (pitch - 69.0) / 12.0);
}

class TuningError : public std::runtime_error
{
public:
    using std::runtime_error::runtime_error;
};

// A Scala scale: the pitches of its degrees 1..N in cents above degree 0 (the last is the period,
// usually 1200 cents).
struct ScalaScale
{
    std::string description;
    std::vector<double> cents;
};

// A Scala keyboard map. Without one: degree 0 on middle C (60) at its equal-tempered pitch, every
// key mapped in order. Frequencies are those at A4 = 440 Hz; the instrument's A4 reference scales
// them all.
struct KeyboardMap
{
    int size = 0;  // keys in one repetition of the mapping; 0: every key to the next degree
    int firstNote = 0, lastNote = 127;
    int middleNote = 60;                              // the key of degree 0
    int referenceNote = 60;                           // the key whose frequency is given
    double referenceHz = 440.0 * 0.5946035575013605;  // middle C, equal-tempered: 440 * 2^(-9/12)
    int octaveDegree = 0;      // the degree one repetition of the mapping moves by (0: the scale's size)
    std::vector<int> degrees;  // per key of a repetition: its degree, or -1 (unmapped)
};

// OFF: parse .scl / .kbm text. Throws TuningError naming the line and what is wrong.
ScalaScale parseScalaScale(const std::string& text);
KeyboardMap parseKeyboardMap(const std::string& text);

// OFF: every MIDI note's pitch under a scale and map (NaN where a key is unmapped or outside the
// map's range).
KeyboardPitches keyboardPitches(const ScalaScale& scale, const KeyboardMap& map);

}  // namespace jawari
