#include "realtime/sympathetic/SympatheticTuning.h"

#include <algorithm>
#include <cmath>

namespace jawari
{
namespace
{
// Each thaat's seven notes in semitones above Sa (Sa Re Ga Ma Pa Dha Ni).
constexpr int kThaats[10][7] = {
    {0, 2, 4, 5, 7, 9, 11},  // Bilaval
    {0, 2, 4, 5, 7, 9, 10},  // Khamaj
    {0, 2, 3, 5, 7, 9, 10},  // Kafi
    {0, 2, 3, 5, 7, 8, 10},  // Asavari
    {0, 1, 3, 5, 7, 8, 10},  // Bhairavi
    {0, 1, 4, 5, 7, 8, 11},  // Bhairav
    {0, 2, 4, 6, 7, 9, 11},  // Kalyan
    {0, 1, 4, 6, 7, 9, 11},  // Marva
    {0, 1, 4, 6, 7, 8, 11},  // Purvi
    {0, 1, 3, 6, 7, 8, 11},  // Todi
};

// The pure interval of each semitone above Sa (5-limit just intonation).
constexpr double kJustRatios[12] = {1.0,       16.0 / 15.0, 9.0 / 8.0, 6.0 / 5.0, 5.0 / 4.0, 4.0 / 3.0,
                                    45.0 / 32.0, 3.0 / 2.0, 8.0 / 5.0, 5.0 / 3.0, 9.0 / 5.0, 15.0 / 8.0};
}  // namespace

int sympatheticSemitones(int k, SympatheticScale scale)
{
    k = std::max(k, 0);
    if (scale == SympatheticScale::saPa)
    {
        constexpr int kCycle[4] = {7, 12, 19, 24};  // Pa, Sa', Pa', Sa''
        return kCycle[k % 4];
    }
    const int thaat = std::clamp(static_cast<int>(scale) - 1, 0, 9);
    const int step = k + 4;  // string 0 is the fifth degree (Pa) of the octave below the upper Sa
    return 12 * (step / 7) + kThaats[thaat][step % 7];
}

double sympatheticPitch(int k, SympatheticScale scale, SympatheticIntonation intonation, double saPitch, int saKey,
                        const KeyboardPitches& keys)
{
    const int semitones = sympatheticSemitones(k, scale);
    if (intonation == SympatheticIntonation::keyboard)
    {
        const int key = saKey + semitones;
        if (key >= 0 && key < kMidiNotes && std::isfinite(keys[size_t(key)]))
            return keys[size_t(key)];
        return saPitch + semitones;
    }
    return saPitch + 12.0 * (semitones / 12) + 12.0 * std::log2(kJustRatios[semitones % 12]);
}

}  // namespace jawari
