#include "ParameterText.h"

#include <juce_audio_basics/juce_audio_basics.h>

#include <cmath>

namespace jawari::plugin::text
{
namespace
{
constexpr double kMillimetresPerMetre = 1e3;
// Every obstacle stiffness in range (K from 1e6) is larger than any log10 K (at most 16).
constexpr double kLargestLog10K = 16.0;

bool hasPercent(const juce::String& text)
{
    return text.containsChar('%');
}

// At most `decimals` decimals, no trailing zeros: 2.3, 2.25, 2.
juce::String shortest(double value, int decimals)
{
    auto s = fixed(value, decimals);
    if (s.containsChar('.'))
        s = s.trimCharactersAtEnd("0").trimCharactersAtEnd(".");
    return s;
}
}  // namespace

juce::String fixed(double value, int decimals)
{
    const double half = 0.5 * std::pow(10.0, -decimals);
    return juce::String(std::abs(value) < half ? 0.0 : value, decimals);
}

double leadingNumber(const juce::String& text)
{
    const auto start = text.indexOfAnyOf("+-.0123456789");
    return start < 0 ? 0.0 : text.substring(start).getDoubleValue();
}

juce::String position(double fraction, double lengthMetres)
{
    const double mm = fraction * lengthMetres * kMillimetresPerMetre;
    return fixed(mm, mm < 99.95 ? 1 : 0) + " mm";
}

double parsePosition(const juce::String& text, double lengthMetres)
{
    const double number = leadingNumber(text);
    return hasPercent(text) ? number / 100.0 : number / (lengthMetres * kMillimetresPerMetre);
}

juce::String stiffness(double log10K, double alpha)
{
    return scientific(std::pow(10.0, log10K), 1) + " N/m^" + shortest(1.0 + alpha, 2);
}

double parseStiffness(const juce::String& text)
{
    const double number = leadingNumber(text);
    return number > kLargestLog10K ? std::log10(number) : number;
}

juce::String scientific(double value, int decimals)
{
    if (std::abs(value) < 1e-30)
        return "0";
    const auto e = juce::String::formatted("%.*e", decimals, value);
    // "1.78e-05" -> "1.78e-5", "1.0e+13" -> "1.0e13".
    const auto mantissa = e.upToFirstOccurrenceOf("e", false, false);
    const int exponent = e.fromFirstOccurrenceOf("e", false, false).getIntValue();
    return mantissa + "e" + juce::String(exponent);
}

juce::String percent(double fraction)
{
    return fixed(fraction * 100.0, 0) + " %";
}

double parsePercent(const juce::String& text)
{
    const double number = leadingNumber(text);
    return hasPercent(text) || number > 1.0 ? number / 100.0 : number;
}

juce::String multiplier(double value, int decimals)
{
    return "x" + fixed(value, decimals);
}

juce::String noteName(int midiNote)
{
    return juce::MidiMessage::getMidiNoteName(midiNote, true, true, 4);
}

int parseNote(const juce::String& text)
{
    const auto t = text.trim().toLowerCase();
    if (t.isEmpty())
        return -1;
    if (juce::CharacterFunctions::isDigit(t[0]))
        return t.getIntValue();
    static constexpr int kSemitones[] = {9, 11, 0, 2, 4, 5, 7};  // a b c d e f g
    if (t[0] < 'a' || t[0] > 'g')
        return -1;
    int note = kSemitones[t[0] - 'a'];
    int next = 1;
    if (t[1] == '#')
        ++note, ++next;
    else if (t[1] == 'b')
        --note, ++next;
    const auto octave = t.substring(next).trim();
    if (octave.isEmpty() || !(juce::CharacterFunctions::isDigit(octave[0]) || octave[0] == '-'))
        return -1;
    return (octave.getIntValue() + 1) * 12 + note;
}

}  // namespace jawari::plugin::text
