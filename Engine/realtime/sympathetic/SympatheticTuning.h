#pragma once
// How the sitar's sympathetic strings (taraf) are tuned: to the notes of a raga's parent scale (a
// thaat), upwards from the Pa below the upper Sa, or to Sa and Pa alone for a drone. Pitches are
// fractional MIDI notes (Tuning.h). RT: plain arithmetic on tables.
//
// A player tunes the taraf by ear to pure intervals above Sa (the ratios below), or, with the
// keyboard's intonation, to the pitch the keyboard plays for the same note (equal temperament or a
// Scala scale: the taraf then agree with the keys that make them ring).

#include "realtime/playing/Tuning.h"

namespace jawari
{

inline constexpr int kMaxSympatheticStrings = 13;

// The ten thaats of Hindustani music (Bhatkhande), and Sa-Pa.
enum class SympatheticScale
{
    saPa,
    bilaval,
    khamaj,
    kafi,
    asavari,
    bhairavi,
    bhairav,
    kalyan,
    marva,
    purvi,
    todi
};
inline constexpr const char* kSympatheticScaleNames[] = {"Sa-Pa",    "Bilaval", "Khamaj", "Kafi",  "Asavari", "Bhairavi",
                                                         "Bhairav", "Kalyan",  "Marva",  "Purvi", "Todi"};
inline constexpr int kSympatheticScaleCount = static_cast<int>(sizeof(kSympatheticScaleNames) / sizeof(const char*));

enum class SympatheticIntonation
{
    just,     // pure intervals above Sa
    keyboard  // the keyboard's pitch for the note (equal temperament or its Scala scale)
};

// The semitones above Sa (0..11, or 12 and more in higher octaves) string k of the taraf sounds,
// the upper Sa being 12. A thaat's seven notes run upwards from the Pa below the upper Sa (7, 9,
// 11, 12, 14, ... for Bilaval); Sa-Pa repeats Pa, Sa, Pa, Sa' in turn.
int sympatheticSemitones(int k, SympatheticScale scale);

// The pitch of string k for Sa at saPitch: sympatheticSemitones as a pure ratio above Sa (just), or
// the keyboard's pitch for the key saKey + semitones (keyboard; equal temperament where that key is
// unmapped).
double sympatheticPitch(int k, SympatheticScale scale, SympatheticIntonation intonation, double saPitch, int saKey,
                        const KeyboardPitches& keys);

}  // namespace jawari
