// jawari-render: renders a jawari-scene/1 file, or a MIDI file through the plugin, to a WAV
// (docs/scenes.md).
//
//   jawari-render SCENE.json -o OUT.wav [--method reference] [--modes M] [--rate HZ]
//                 [--duration S] [--output-rate HZ] [--format int24|float] [--raw] [--energy FILE.csv]
//                 [--quiet]
//   jawari-render --midi SONG.mid -o OUT.wav [--preset NAME | --state FILE] [--duration S]
//                 [--output-rate HZ] [--format int24|float] [--quiet]
//   jawari-render --preset NAME -o OUT.wav --duration S [--output-rate HZ] [--quiet]   (the drone alone)
//
// Exit status: 0 done, 2 bad input or arguments (the message names the problem), 1 anything else.
// Samples a 24-bit file clips are a warning on stderr (status 0). Files are written to a temporary
// beside the target and moved into place only when complete.

#include "MidiRender.h"
#include "MidiScore.h"
#include "Parameters.h"
#include "PluginProcessor.h"
#include "Presets.h"
#include "RenderUsage.h"
#include "WavOutput.h"
#include "offline/OfflineRender.h"
#include "offline/Scene.h"

#include <juce_audio_formats/juce_audio_formats.h>
#include <juce_core/juce_core.h>
#include <juce_events/juce_events.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <string>

namespace
{

struct UsageError : std::runtime_error
{
    using std::runtime_error::runtime_error;
};

// The value of an option given as `--name value` or `--name=value` (JUCE's ArgumentList tokenises).
std::optional<juce::String> optionValue(juce::ArgumentList& args, juce::StringRef names)
{
    const int index = args.indexOfOption(names);
    if (index < 0)
        return std::nullopt;
    const auto arg = args[index];
    if (arg.isLongOption() && arg.text.contains("="))
    {
        args.arguments.remove(index);
        return arg.getLongOptionValue();
    }
    if (index + 1 >= args.size())
        throw UsageError(arg.text.toStdString() + ": needs a value");
    const auto value = args[index + 1].text;
    args.arguments.removeRange(index, 2);
    return value;
}

double parseNumber(const juce::String& option, const juce::String& text)
{
    const std::string s = text.trim().toStdString();
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v))
        throw UsageError(option.toStdString() + ": '" + s + "' is not a finite number");
    return v;
}

long long parseWhole(const juce::String& option, const juce::String& text)
{
    const double v = parseNumber(option, text);
    if (v != std::floor(v) || std::abs(v) > 1e15)
        throw UsageError(option.toStdString() + ": '" + text.toStdString() + "' is not a whole number");
    return static_cast<long long>(v);
}

// A scene's pickup signal as a mono WAV: normalised to a -1 dBFS peak (so a 24-bit file never
// clips), or raw in SI units. Returns the signal's peak before normalising.
double writeWav(const juce::File& target, const std::vector<double>& samples, int rate, bool raw,
                jawari::render::SampleFormat format)
{
    double peak = 0.0;
    for (double v : samples)
        peak = std::max(peak, std::abs(v));
    const double gain = raw ? 1.0 : (peak > 0.0 ? std::pow(10.0, -1.0 / 20.0) / peak : 0.0);
    std::vector<float> mono(samples.size());
    for (size_t i = 0; i < samples.size(); ++i)
        mono[i] = static_cast<float>(samples[i] * gain);
    jawari::render::WavOutput out(target, rate, 1, format);
    const float* channels[] = {mono.data()};
    out.write(channels, static_cast<int>(mono.size()));
    out.finish();
    return peak;
}

void writeEnergy(const juce::File& target, const std::vector<jawari::EnergySample>& energy)
{
    juce::TemporaryFile temp(target);
    {
        juce::FileOutputStream out(temp.getFile());
        if (!out.openedOk())
            throw std::runtime_error("cannot write '" + temp.getFile().getFullPathName().toStdString() + "'");
        out << "time_s,energy_J,contact_energy_J,newton_iterations,newton_max_per_step\n";
        char line[256];
        for (const auto& e : energy)
        {
            std::snprintf(line, sizeof line, "%.9g,%.17g,%.17g,%ld,%d\n", e.timeSeconds, e.energy, e.contactEnergy,
                          e.newtonIterations, e.newtonMaxPerStep);
            out << line;
        }
        out.flush();
        // A write cut short (a full disk) leaves the status clean: the size on disk tells.
        if (out.getStatus().failed() || temp.getFile().getSize() < out.getPosition())
            throw std::runtime_error("writing the energy log failed: "
                                     + (out.getStatus().failed() ? out.getStatus().getErrorMessage().toStdString()
                                                                 : std::string("the data did not all reach the disk")));
    }
    if (!temp.overwriteTargetFileWithTemporary())
        throw std::runtime_error("cannot move the finished energy log to '" + target.getFullPathName().toStdString()
                                 + "'");
}

// What the command line asks for (the options as given; checked when applied).
struct Request
{
    juce::String scenePath;
    std::optional<juce::String> output, method, modes, rate, duration, outputRate, format, energyPath;
    std::optional<juce::String> midiPath, preset, statePath;
    juce::StringArray settings;  // --set ID=VALUE, in order
    bool raw = false, quiet = false, secondCore = false;
    bool throughPlugin = false;  // --midi, or the drone alone: no scene file
};

// A render through the plugin: a MIDI file, or a preset or state alone (its drone).
bool playsPlugin(const Request& q, int positionals)
{
    return q.midiPath || ((q.preset || q.statePath) && positionals == 0);
}

// Options that belong to one kind of render: a scene file's, or the plugin's.
void checkOptionsFit(const Request& q, int positionals)
{
    if (!playsPlugin(q, positionals))
    {
        if (q.preset || q.statePath || q.secondCore || !q.settings.isEmpty())
            throw UsageError(std::string(q.preset       ? "--preset"
                                         : q.statePath  ? "--state"
                                         : q.secondCore ? "--second-core"
                                                        : "--set")
                             + " applies to renders through the plugin (--midi, or the drone alone), not to "
                               "scene files");
        return;
    }
    if (positionals > 0)
        throw UsageError("give a scene file or --midi, not both ('" + q.scenePath.toStdString() + "' and --midi "
                         + q.midiPath->toStdString() + ")");
    const std::pair<bool, const char*> sceneOnly[] = {{q.method.has_value(), "--method"},
                                                      {q.modes.has_value(), "--modes"},
                                                      {q.rate.has_value(), "--rate"},
                                                      {q.energyPath.has_value(), "--energy"},
                                                      {q.raw, "--raw"}};
    for (const auto& [given, name] : sceneOnly)
        if (given)
            throw UsageError(std::string(name) + " applies to scene files, not to --midi");
    if (q.preset && q.statePath)
        throw UsageError("give --preset or --state, not both");
}

Request parseArguments(int argc, char* argv[])
{
    juce::ArgumentList args(argc, argv);
    Request q;
    q.output = optionValue(args, "--output|-o");
    q.method = optionValue(args, "--method");
    q.modes = optionValue(args, "--modes");
    q.rate = optionValue(args, "--rate");
    q.duration = optionValue(args, "--duration");
    q.outputRate = optionValue(args, "--output-rate");
    q.format = optionValue(args, "--format");
    q.energyPath = optionValue(args, "--energy");
    q.midiPath = optionValue(args, "--midi");
    q.preset = optionValue(args, "--preset");
    q.statePath = optionValue(args, "--state");
    while (const auto setting = optionValue(args, "--set"))
        q.settings.add(*setting);
    q.raw = args.removeOptionIfFound("--raw");
    q.quiet = args.removeOptionIfFound("--quiet");
    q.secondCore = args.removeOptionIfFound("--second-core");
    juce::StringArray positional;
    for (const auto& a : args.arguments)
    {
        if (a.isOption())
            throw UsageError("unknown option '" + a.text.toStdString() + "' (see --help)");
        positional.add(a.text);
    }
    if (!positional.isEmpty())
        q.scenePath = positional[0];
    checkOptionsFit(q, positional.size());
    q.throughPlugin = playsPlugin(q, positional.size());
    if (!q.throughPlugin && positional.size() != 1)
        throw UsageError(positional.isEmpty() ? "no scene file given (see --help)" : "give exactly one scene file");
    if (!q.output)
        throw UsageError("no output file: give -o OUT.wav");
    return q;
}

// --format, and --raw's float: int24 unless asked otherwise.
jawari::render::SampleFormat sampleFormatFor(const Request& q)
{
    using jawari::render::SampleFormat;
    const auto format = q.format ? jawari::render::sampleFormatNamed(*q.format) : SampleFormat::int24;
    if (!format)
        throw UsageError("--format: unknown format '" + q.format->toStdString() + "' (expected int24 or float)");
    if (q.raw && q.format && *format != SampleFormat::float32)
        throw UsageError("--raw writes SI units, which only --format float holds");
    return q.raw ? SampleFormat::float32 : *format;
}

// --method: the reference or a voice's contact method. The scene's modes and rate were chosen for
// its own solver: switching between the reference and the voice drops them (the new solver's
// defaults or automatic choice apply) unless the command line gives them too.
void applyMethod(jawari::Scene& scene, const Request& q)
{
    jawari::Simulation chosen = scene.simulation;
    if (!jawari::setMethodByName(chosen, q.method->toStdString()))
    {
        std::string names = "reference";
        for (const auto& m : jawari::kContactMethods)
            names += std::string(", ") + m.sceneName;
        throw UsageError("--method: unknown method '" + q.method->toStdString() + "' (expected: " + names + ")");
    }
    const bool switchesSolver = chosen.reference != scene.simulation.reference;
    if (switchesSolver && !q.quiet && (scene.simulation.modes || scene.simulation.rateHz) && !(q.modes && q.rate))
        std::fprintf(stderr, "note: --method %s: the scene's modes/rate were set for its %s method and are not used\n",
                     jawari::methodName(chosen), jawari::methodName(scene.simulation));
    if (switchesSolver)
        scene.simulation.forgetConfiguration();
    scene.simulation.reference = chosen.reference;
    scene.simulation.contact = chosen.contact;
}

// The scene file with the command line's overrides, checked as the parser checks a scene.
jawari::Scene sceneFor(const Request& q)
{
    auto scene = jawari::loadSceneFile(
        juce::File::getCurrentWorkingDirectory().getChildFile(q.scenePath).getFullPathName().toStdString());
    if (q.method)
        applyMethod(scene, q);
    if (q.modes)
    {
        const auto m = parseWhole("--modes", *q.modes);
        if (m < 1 || m > jawari::kMaxModes)
            throw UsageError("--modes: must be between 1 and " + std::to_string(jawari::kMaxModes));
        scene.simulation.modes = static_cast<int>(m);
    }
    if (q.rate)
        scene.simulation.rateHz = parseNumber("--rate", *q.rate);
    if (q.duration)
        scene.simulation.durationSeconds = parseNumber("--duration", *q.duration);
    if (q.outputRate)
    {
        const auto r = parseWhole("--output-rate", *q.outputRate);
        if (r < 8000 || r > 384000)
            throw UsageError("--output-rate: must be between 8000 and 384000 Hz");
        scene.simulation.outputRateHz = static_cast<int>(r);
    }
    jawari::validateScene(scene);
    return scene;
}

// A file the command line names, in a folder that must exist.
juce::File outputFile(const juce::String& path, const char* option)
{
    const juce::File file = juce::File::getCurrentWorkingDirectory().getChildFile(path);
    if (!file.getParentDirectory().isDirectory())
        throw UsageError(std::string(option) + ": the folder '"
                         + file.getParentDirectory().getFullPathName().toStdString() + "' does not exist");
    return file;
}

// A progress bar on stderr.
bool showProgress(double fraction)
{
    const int width = 40;
    const int filled = static_cast<int>(fraction * width);
    std::fprintf(stderr, "\r[%s%s] %3d%%", std::string(size_t(filled), '#').c_str(),
                 std::string(size_t(width - filled), '.').c_str(), static_cast<int>(fraction * 100.0));
    std::fflush(stderr);
    return true;
}

void printSummary(const jawari::Scene& scene, const jawari::RenderResult& result, const juce::File& wavFile,
                  const std::optional<juce::File>& energyFile, bool raw, jawari::render::SampleFormat format,
                  double peak)
{
    const auto& st = result.stats;
    std::printf("wrote %s: %zu samples at %d Hz (%s, %s), peak %.6g %s%s\n", wavFile.getFullPathName().toRawUTF8(),
                result.output.size(), result.outputRateHz, jawari::render::formatDescription(format),
                raw ? "SI units" : "-1 dBFS peak", peak, jawari::quantityUnit(scene.pickup.quantity),
                (" " + std::string(jawari::quantityName(scene.pickup.quantity))).c_str());
    std::printf(
        "%s: %d modes at %.6g Hz (%s path), %lld steps in %.3f s CPU (%.3gx real time), Newton max %d per step, "
        "max penetration %.3g m\n",
        jawari::methodName(scene.simulation), st.modes, st.internalRateHz, st.transformPath ? "DST-I" : "projection",
        st.steps, st.cpuSeconds, scene.simulation.durationSeconds / std::max(st.cpuSeconds, 1e-9),
        st.newtonIterationsMax, st.maxPenetrationMetres);
    if (st.splitSteps > 0)
        std::printf("split steps: %lld of %lld, %.2f contact points solved per step, %lld engaged afresh, %lld solved "
                    "again\n",
                    st.splitSteps, st.steps, double(st.splitEngaged) / double(st.splitSteps), st.splitJoins,
                    st.splitResolves);
    if (energyFile)
        std::printf("energy log: %s (%zu rows)\n", energyFile->getFullPathName().toRawUTF8(), result.energy.size());
}

// --preset: a factory preset by its name or the part before its parenthesis, in any case.
int factoryPresetNamed(const juce::String& wanted)
{
    if (const int index = jawari::plugin::factoryPresetByShortName(wanted); index >= 0)
        return index;
    juce::StringArray names;
    for (const auto& preset : jawari::plugin::factoryPresets())
        names.add("'" + juce::String(preset.name) + "'");
    throw UsageError("--preset: no factory preset '" + wanted.toStdString()
                     + "' (the presets: " + names.joinIntoString(", ").toStdString() + ")");
}

// The sound the score is played with: a factory preset, a saved state (read as the plugin reads
// a user preset, with the same checks), or the plugin's defaults. Returns what it is.
juce::String chooseSound(jawari::plugin::JawariAudioProcessor& processor, const Request& q)
{
    if (q.preset)
    {
        const int index = factoryPresetNamed(*q.preset);
        processor.setCurrentProgram(index);
        return "preset '" + processor.getProgramName(index) + "'";
    }
    if (q.statePath)
    {
        const auto file = juce::File::getCurrentWorkingDirectory().getChildFile(*q.statePath);
        if (const auto loaded = processor.loadUserPreset(file); loaded.failed())
            throw UsageError("--state " + loaded.getErrorMessage().toStdString());
        return "state '" + file.getFileName() + "'";
    }
    return "the plugin's defaults";
}

// --set ID=VALUE: a parameter of the plugin set after the preset or state, in its own units (the
// value the editor shows: 0 or 1 for a switch, a choice's index counted from 0).
void applySettings(jawari::plugin::JawariAudioProcessor& processor, const juce::StringArray& settings)
{
    for (const auto& setting : settings)
    {
        const auto id = setting.upToFirstOccurrenceOf("=", false, false).trim();
        auto* parameter = processor.parameters().getParameter(id);
        if (!setting.containsChar('=') || parameter == nullptr)
            throw UsageError("--set " + setting.toStdString() + ": give ID=VALUE with a parameter's id (Source/Parameters.h)");
        const double value = parseNumber("--set " + id.toStdString(), setting.fromFirstOccurrenceOf("=", false, false));
        const auto& range = parameter->getNormalisableRange();
        if (value < range.start || value > range.end)
            throw UsageError("--set " + id.toStdString() + ": must be between " + std::to_string(range.start) + " and "
                             + std::to_string(range.end));
        parameter->setValueNotifyingHost(parameter->convertTo0to1(float(value)));
    }
}

jawari::midi::MidiRenderSettings midiSettings(const Request& q)
{
    jawari::midi::MidiRenderSettings s;
    if (q.outputRate)
    {
        const auto r = parseWhole("--output-rate", *q.outputRate);
        if (r < 22050 || r > 192000)
            throw UsageError("--output-rate: the plugin runs at 22050 to 192000 Hz");
        s.rateHz = static_cast<double>(r);
    }
    if (q.duration)
    {
        const double seconds = parseNumber("--duration", *q.duration);
        if (!(seconds > 0.0 && seconds <= jawari::midi::kMaxScoreSeconds) || std::llround(seconds * s.rateHz) < 1)
            throw UsageError("--duration: must be at least one sample and at most "
                             + std::to_string(int(jawari::midi::kMaxScoreSeconds)) + " s");
        s.lengthSamples = std::llround(seconds * s.rateHz);
    }
    return s;
}

// The score to play: the --midi file's, or none (the drone alone).
jawari::midi::MidiScore scoreFor(const Request& q)
{
    if (!q.midiPath)
        return {};
    const auto file = juce::File::getCurrentWorkingDirectory().getChildFile(*q.midiPath);
    try
    {
        return jawari::midi::loadMidiScore(file);
    }
    catch (const jawari::midi::MidiFileError& e)
    {
        throw UsageError("--midi " + file.getFullPathName().toStdString() + ": " + e.what());
    }
}

// The level of what was written, for the summary: the true peak of the samples given to the file,
// and those at or beyond full scale, clipped (24-bit) or kept (float).
std::string levelText(const jawari::render::WavOutput& out)
{
    const auto& level = out.level();
    std::string text = "peak " + jawari::render::dbfsText(level.peak);
    if (level.atOrBeyondFull > 0)
        text += ", " + std::to_string(level.atOrBeyondFull) + " samples at or beyond full scale "
                + (out.clipped() ? "clipped" : "kept as given");
    return text;
}

// A 24-bit file that clipped: how many samples, by how much, and how to avoid it.
void warnOfClipping(const jawari::render::Level& level)
{
    const std::string peak = jawari::render::dbfsText(level.peak);
    if (level.peak > 1.0)
        std::fprintf(stderr,
                     "warning: the 24-bit file clipped %lld samples at or beyond full scale (left and right counted "
                     "apart); their peak was %s (%.4g x full scale). To avoid it, lower the sound's Output gain by "
                     "more than %.2f dB (in a --state file), or write --format float, which keeps every sample\n",
                     level.atOrBeyondFull, peak.c_str(), level.peak, 20.0 * std::log10(level.peak));
    else
        std::fprintf(stderr,
                     "warning: the 24-bit file holds %lld samples at full scale (left and right counted apart), peak "
                     "%s: the plugin gave them already limited to +-1, as --format float would show too. To avoid "
                     "it, lower the sound's Output gain (in a --state file)\n",
                     level.atOrBeyondFull, peak.c_str());
}

void printMidiSummary(const jawari::midi::MidiScore& score, const juce::String& sound,
                      const jawari::midi::MidiRenderStats& st, const jawari::midi::MidiRenderSettings& s,
                      const jawari::render::WavOutput& out, const juce::File& wavFile, double wallSeconds)
{
    const double seconds = static_cast<double>(st.samples) / s.rateHz;
    std::printf("wrote %s: %lld samples (%.3f s) at %.0f Hz, stereo %s, %s\n", wavFile.getFullPathName().toRawUTF8(),
                st.samples, seconds, s.rateHz, jawari::render::formatDescription(out.format()), levelText(out).c_str());
    const int events = score.events.getNumEvents();
    if (events == 0)
        std::printf("the drone alone, no MIDI events; %s; latency %d samples removed\n", sound.toRawUTF8(),
                    st.latencySamples);
    else
        std::printf("MIDI type %d, %d track%s, %d event%s, the last at %.3f s; %s; latency %d samples removed\n",
                    score.fileType, score.tracks, score.tracks == 1 ? "" : "s", events, events == 1 ? "" : "s",
                    score.lastEventSeconds, sound.toRawUTF8(), st.latencySamples);
    if (!s.lengthSamples)
        std::printf("ended %.3f s after the last event: %s\n", seconds - score.lastEventSeconds,
                    st.tailCapped ? "the cap (the output never fell silent)" : "below -100 dBFS for 0.5 s");
    std::printf("rendered in %.2f s (%.3gx real time)\n", wallSeconds, seconds / std::max(wallSeconds, 1e-9));
}

// A score without events plays only the drone: the sound must have it on, and the length must be
// given (a drone never falls silent).
void checkDroneAlone(jawari::plugin::JawariAudioProcessor& processor, const Request& q, const juce::String& sound)
{
    const std::string nothing =
        q.midiPath ? "the MIDI file holds no notes, controllers or other channel events" : "no --midi file is given";
    if (processor.parameters().getRawParameterValue(jawari::plugin::ids::drone)->load() < 0.5f)
        throw UsageError(nothing + ", and " + sound.toStdString()
                         + " has the drone off: nothing would sound (choose a sound with the drone on, such as "
                           "--preset \"Tanpura drone\")");
    if (!q.duration)
        throw UsageError(nothing + ": the drone alone plays for ever, so give its length with --duration S");
}

// --midi (or the drone alone): the score played through the plugin's AudioProcessor, written as it
// renders.
int runMidi(const Request& q)
{
    auto settings = midiSettings(q);
    const auto format = sampleFormatFor(q);
    const auto score = scoreFor(q);
    const juce::File wavFile = outputFile(*q.output, "-o");
    const juce::ScopedJuceInitialiser_GUI juceRuntime;  // the processor's parameters run a timer
    jawari::plugin::JawariAudioProcessor processor;
    const juce::String sound = chooseSound(processor, q);
    applySettings(processor, q.settings);
    if (q.secondCore)
        processor.parameters().getParameter(jawari::plugin::ids::secondCore)->setValueNotifyingHost(1.0f);
    if (score.events.getNumEvents() == 0)
        checkDroneAlone(processor, q, sound);
    const bool bar = !q.quiet && isatty(STDERR_FILENO);
    if (bar)
        settings.progress = [](double fraction) { showProgress(fraction); };

    jawari::render::WavOutput out(wavFile, settings.rateHz, 2, format);
    const auto start = std::chrono::steady_clock::now();
    const auto stats =
        jawari::midi::renderScore(processor, score, settings, [&out](const float* left, const float* right, int count) {
            const float* channels[] = {left, right};
            out.write(channels, count);
        });
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (bar)
        std::fprintf(stderr, "\n");
    out.finish();
    if (!q.quiet && stats.tailCapped)
        std::fprintf(stderr,
                     "note: the output was still above -100 dBFS %.0f s after the last event (a drone or a "
                     "held note): it stops there; --duration sets the length\n",
                     settings.tailCapSeconds);
    if (out.clipped())
        warnOfClipping(out.level());
    if (!q.quiet)
        printMidiSummary(score, sound, stats, settings, out, wavFile, wall);
    return 0;
}

int run(int argc, char* argv[])
{
    if (juce::ArgumentList(argc, argv).containsOption("--help|-h"))
    {
        std::cout << kRenderUsage;
        return 0;
    }
    const Request q = parseArguments(argc, argv);
    if (q.throughPlugin)
        return runMidi(q);
    const jawari::Scene scene = sceneFor(q);
    const auto format = sampleFormatFor(q);
    const juce::File wavFile = outputFile(*q.output, "-o");
    std::optional<juce::File> energyFile;
    if (q.energyPath)
        energyFile = outputFile(*q.energyPath, "--energy");

    jawari::RenderOptions options;
    options.logEnergy = energyFile.has_value();
    const bool bar = !q.quiet && isatty(STDERR_FILENO);
    if (bar)
        options.progress = showProgress;
    const auto result = jawari::renderScene(scene, options);
    if (bar)
        std::fprintf(stderr, "\n");
    if (!q.quiet && result.stats.initialContactEnergy > 0.5 * result.stats.initialEnergy)
        std::fprintf(stderr,
                     "warning: the initial shape starts inside an obstacle: %.3g J of the %.3g J at t = 0 is contact "
                     "energy, which launches the string (check obstacle heights against the pluck)\n",
                     result.stats.initialContactEnergy, result.stats.initialEnergy);
    const double peak = writeWav(wavFile, result.output, result.outputRateHz, q.raw, format);
    if (energyFile)
        writeEnergy(*energyFile, result.energy);
    if (!q.quiet)
        printSummary(scene, result, wavFile, energyFile, q.raw, format, peak);
    return 0;
}

}  // namespace

int main(int argc, char* argv[])
{
    try
    {
        return run(argc, argv);
    }
    catch (const UsageError& e)
    {
        std::cerr << "jawari-render: error: " << e.what() << "\n";
        return 2;
    }
    catch (const jawari::SceneError& e)
    {
        std::cerr << "jawari-render: error in scene: " << e.what() << "\n";
        return 2;
    }
    catch (const std::exception& e)
    {
        std::cerr << "jawari-render: failed: " << e.what() << "\n";
        return 1;
    }
}
