#pragma once
// How parameter values read as text, in the units a player reads (docs/plugin.md "Parameters"),
// and how typed text reads back. Each text carries its unit; each parser accepts what the text
// shows and a bare number in the same unit. Pure functions: any thread.

#include <juce_core/juce_core.h>

namespace jawari::plugin::text
{

// `value` with `decimals` decimals; a value that rounds to zero reads "0", never "-0.00".
juce::String fixed(double value, int decimals);
// The first number in `text` ("  -1.5e3 mm" reads -1500); 0 when there is none.
double leadingNumber(const juce::String& text);

// A point on the string, `fraction` of its length from the bridge end (x = 0), in mm: one
// decimal below 100 mm ("6.0 mm"), whole millimetres above ("501 mm").
juce::String position(double fraction, double lengthMetres);
// "6 mm" or a bare "6" is millimetres, "50 %" a percentage of the length; returns the fraction.
double parsePosition(const juce::String& text, double lengthMetres);

// The obstacle stiffness K = 10^log10K in its unit N/m^(1+alpha): "1.0e13 N/m^2.3".
juce::String stiffness(double log10K, double alpha);
// "1e13" (K) or "13" (log10 K: every K in range exceeds 16); returns log10 K.
double parseStiffness(const juce::String& text);

// A small number in scientific notation with `decimals` decimals: "1.78e-5"; zero reads "0".
juce::String scientific(double value, int decimals);

// A fraction as a percentage, "20 %"; "20 %", "20" and "0.2" all read 0.2.
juce::String percent(double fraction);
double parsePercent(const juce::String& text);

// A multiplier, "x1.00"; "x2", "2" read 2.
juce::String multiplier(double value, int decimals);

// A MIDI note by name and octave (middle C = C4), "C#3"; "C#3", "db3" and "49" read 49; -1 when
// the text is neither.
juce::String noteName(int midiNote);
int parseNote(const juce::String& text);

}  // namespace jawari::plugin::text
