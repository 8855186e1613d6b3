// jawari-soak: the tanpura drone rendered offline through the real AudioProcessor for a long time
// (an hour by default), then a report: non-finite samples, peak level, each block's processing time
// against its real-time budget (mean, percentiles, the worst) and the slowest blocks with what the
// instrument did in them, Newton iterations, and what the guards did. Measures and reports; exits 1
// if either guard acted: the output guard (a non-finite sample, or one beyond +12 dBFS: counted by
// Instrument::limitedSamples) or the voices' blow-up guard (a string that ran away, restarted from
// rest: Instrument::blowUps), or if a non-finite sample came out all the same.
//
//   jawari-soak [--minutes 60] [--quality draft|standard|high] [--rate 48000] [--block 512]
//               [--polyphony N]   (N held MIDI notes on top of the drone; default 0)
//               [--drone 0|1]     (default 1; 0 with --polyphony 8 measures eight MIDI strings)
//               [--preset NAME]   (a factory preset, by its name or the part before the parenthesis,
//                                  in any case; default "Tanpura drone")
//               [--replay S]      (every S seconds one held note is plucked again, in turn; default 0: held)
//               [--csv FILE]      (appends one line of the figures to FILE)
//               [--second-core 0|1] (the plugin's "use a second core"; default 0. With it the audio
//                                  thread's CPU time leaves out the worker's: read the wall time)
//               [--polarisations 1|2] (the strings' polarisations; default 1)
//               [--body none|tanpura|sitar] (the body; default: the preset's)
//               [--sympathetic N] (the sympathetic strings on the body, 0..13; default: the preset's)
//               [--one-way 0|1]   (1: the body driven one way, the strings on rigid supports; default 0)
//               [--sympathetic-jawari 0|1] (1: the sympathetic strings on their jawari; default: the preset's)

#include "BlockLoad.h"
#include "offline/CpuClock.h"
#include "PluginProcessor.h"
#include "Presets.h"

#include <juce_events/juce_events.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

int main(int argc, char* argv[])
{
    juce::ScopedJuceInitialiser_GUI juce;
    double minutes = 60.0, rate = 48000.0;
    double replay = 0.0;
    int block = 512, quality = 1, polyphony = 0, drone = 1, secondCore = 0, polarisations = 1, sympathetic = -1,
        oneWay = 0, sympatheticJawari = -1;
    std::string preset = "Tanpura drone", csv, body;
    const char* usage = "usage: jawari-soak [--minutes 60] [--quality draft|standard|high] [--rate 48000] "
                        "[--block 512] [--polyphony N] [--drone 0|1] [--preset NAME] [--replay S] [--csv FILE] "
                        "[--second-core 0|1] [--polarisations 1|2] [--body none|tanpura|sitar] [--sympathetic N] [--one-way "
                        "0|1] [--sympathetic-jawari 0|1]\n";
    for (int i = 1; i < argc; i += 2)
    {
        const std::string key = argv[i];
        if (key == "-h" || key == "--help")
        {
            std::fputs(usage, stdout);
            return 0;
        }
        if (i + 1 >= argc)
        {
            std::fprintf(stderr, "jawari-soak: %s needs a value\n%s", key.c_str(), usage);
            return 2;
        }
        const std::string value = argv[i + 1];
        try
        {
            if (key == "--minutes")
                minutes = std::stod(value);
            else if (key == "--rate")
                rate = std::stod(value);
            else if (key == "--block")
                block = std::stoi(value);
            else if (key == "--polyphony")
                polyphony = std::clamp(std::stoi(value), 0, 8);
            else if (key == "--preset")
                preset = value;
            else if (key == "--csv")
                csv = value;
            else if (key == "--replay" && std::stod(value) >= 0.0)
                replay = std::stod(value);
            else if (key == "--drone")
                drone = std::stoi(value) != 0 ? 1 : 0;
            else if (key == "--second-core")
                secondCore = std::stoi(value) != 0 ? 1 : 0;
            else if (key == "--body" && (value == "none" || value == "tanpura" || value == "sitar"))
                body = value;
            else if (key == "--one-way")
                oneWay = std::stoi(value) != 0 ? 1 : 0;
            else if (key == "--sympathetic-jawari")
                sympatheticJawari = std::stoi(value) != 0 ? 1 : 0;
            else if (key == "--sympathetic")
                sympathetic = std::clamp(std::stoi(value), 0, jawari::kMaxSympatheticStrings);
            else if (key == "--polarisations" && (value == "1" || value == "2"))
                polarisations = std::stoi(value);
            else if (key == "--quality" && (value == "draft" || value == "standard" || value == "high"))
                quality = value == "draft" ? 0 : value == "high" ? 2 : 1;
            else
            {
                std::fprintf(stderr, "jawari-soak: unknown option or value %s %s\n%s", key.c_str(), value.c_str(),
                             usage);
                return 2;
            }
        }
        catch (const std::exception&)
        {
            std::fprintf(stderr, "jawari-soak: %s takes a number, got '%s'\n", key.c_str(), value.c_str());
            return 2;
        }
    }
    if (!(minutes > 0.0 && minutes <= 24 * 60.0) || !(rate >= 22050.0 && rate <= 192000.0) || block < 1 || block > 8192)
    {
        std::fprintf(stderr, "jawari-soak: --minutes must be in (0, 1440], --rate in [22050, 192000] and --block in "
                             "[1, 8192]\n");
        return 2;
    }
    jawari::plugin::JawariAudioProcessor p;
    const int presetIndex = jawari::plugin::factoryPresetByShortName(preset);
    if (presetIndex < 0)
    {
        std::fprintf(stderr, "jawari-soak: --preset: no factory preset '%s'\n", preset.c_str());
        return 2;
    }
    p.setCurrentProgram(presetIndex);
    auto set = [&](const char* id, float v) {
        auto* param = p.parameters().getParameter(id);
        param->setValueNotifyingHost(param->convertTo0to1(v));
    };
    set(jawari::plugin::ids::quality, float(quality));
    // Every held note sounds: the preset's voice limit raised to the polyphony asked for.
    auto* voices = p.parameters().getParameter(jawari::plugin::ids::voices);
    const int presetVoices = int(std::lround(voices->convertFrom0to1(voices->getValue())));
    set(jawari::plugin::ids::voices, float(std::max(presetVoices, polyphony)));
    set(jawari::plugin::ids::drone, float(drone));
    set(jawari::plugin::ids::secondCore, float(secondCore));
    set(jawari::plugin::ids::polarisations, float(polarisations - 1));
    if (!body.empty())
        set(jawari::plugin::ids::body, body == "sitar" ? 2.0f : body == "tanpura" ? 1.0f : 0.0f);
    if (sympathetic >= 0)
        set(jawari::plugin::ids::sympathetic, float(sympathetic));
    if (sympatheticJawari >= 0)
        set(jawari::plugin::ids::sympatheticJawari, float(sympatheticJawari));
    p.setBodyOneWayForTesting(oneWay != 0);
    p.prepareToPlay(rate, block);
    if (!p.waitForBuilds(120000))
    {
        std::fprintf(stderr, "jawari-soak: the instrument was not built within two minutes\n");
        return 1;
    }
    juce::AudioBuffer<float> buffer(2, block);
    const long blocks = std::lround(minutes * 60.0 * rate / block);
    const double budget = block / rate;
    double worst = 0.0, total = 0.0, peak = 0.0;
    // Per block, in the thread's CPU time (without the machine's preemptions) and in wall time.
    jawari::BlockLoad cpuLoad, wallLoad;
    long iterations = 0;
    long workerStrings = 0, workerRevoked = 0, workerUnstarted = 0;  // all blocks': a slow block's own count against the mean says whether it had more work
    long bodySteps = 0, bodySolves = 0, bodyTrials = 0, bodyResolves = 0, bodyLive = 0, bodyPoints = 0;  // all blocks': the body's secant
    const long replayBlocks = replay > 0.0 ? std::max(1L, std::lround(replay * rate / block)) : 0;
    long nonFinite = 0, beyond = 0;
    for (long b = 0; b < blocks; ++b)
    {
        juce::MidiBuffer midi;
        if (b == 0)
            for (int n = 0; n < polyphony; ++n)
                midi.addEvent(juce::MidiMessage::noteOn(1, 48 + 2 * n, juce::uint8(100)), 0);
        else if (replayBlocks > 0 && polyphony > 0 && b % replayBlocks == 0)
        {
            // A player plucking the held notes again, one at a time.
            const int note = 48 + 2 * int((b / replayBlocks) % polyphony);
            midi.addEvent(juce::MidiMessage::noteOff(1, note), 0);
            midi.addEvent(juce::MidiMessage::noteOn(1, note, juce::uint8(100)), 0);
        }
        buffer.clear();
        p.instrument().clearActivity();
        const auto start = std::chrono::steady_clock::now();
        const double startCpu = jawari::threadCpuSeconds();
        p.processBlock(buffer, midi);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const double cpu = jawari::threadCpuSeconds() - startCpu;
        cpuLoad.add(b, cpu / budget, p.instrument().activity());
        iterations += p.instrument().activity().newtonIterations;
        workerStrings += p.instrument().activity().workerStrings;
        workerRevoked += p.instrument().activity().workerRevoked;
        workerUnstarted += p.instrument().activity().workerUnstarted;
        bodySteps += p.instrument().activity().bodySteps;
        bodySolves += p.instrument().activity().bodySolves;
        bodyTrials += p.instrument().activity().bodyTrials;
        bodyResolves += p.instrument().activity().bodyResolves;
        bodyLive += p.instrument().activity().bodyLivePoints;
        bodyPoints += p.instrument().activity().bodyContactPoints;
        wallLoad.add(b, seconds / budget, p.instrument().activity());
        worst = std::max(worst, seconds);
        total += seconds;
        for (int c = 0; c < 2; ++c)
            for (int i = 0; i < block; ++i)
            {
                const float v = buffer.getSample(c, i);
                if (!std::isfinite(v))
                    ++nonFinite;
                else
                {
                    peak = std::max(peak, double(std::abs(v)));
                    beyond += std::abs(v) > 1.0f ? 1 : 0;
                }
            }
        if (b % long(60.0 * rate / block) == 0 && b > 0)
            std::fprintf(stderr, "\r%.0f of %.0f minutes", b * budget / 60.0, minutes);
    }
    const auto* pack = p.instrument().pack();
    std::printf("\njawari-soak: %.1f minutes of preset '%s', %s (%s quality, %d modes x%d, %d contact points, %.0f "
                "Hz, %d-sample blocks, %d held notes%s%s)\n",
                minutes, jawari::plugin::factoryPresets()[size_t(presetIndex)].name,
                drone != 0 ? "drone on" : "drone off",
                quality == 0   ? "draft"
                : quality == 2 ? "high"
                               : "standard",
                pack->modes, pack->voices[0]->oversampling(), pack->voices[0]->contactPoints(), rate, block,
                polyphony, secondCore != 0 ? ", a second core" : "", polarisations == 2 ? ", two polarisations" : "");
    if (bodySteps > 0)
        std::printf("  on the body: %ld internal steps, %.3f contact solves and %.3f trials a step (SharedBody); %ld "
                    "solved again with every point, %.1f %% of the played strings' points live (BodyReach)\n",
                    bodySteps, double(bodySolves) / double(bodySteps), double(bodyTrials) / double(bodySteps),
                    bodyResolves, bodyPoints > 0 ? 100.0 * double(bodyLive) / double(bodyPoints) : 100.0);
    if (secondCore != 0)
        std::printf("  the second core stepped %ld string chunks; %ld taken back late, %ld not started\n",
                    workerStrings, workerRevoked, workerUnstarted);
    std::printf("  drone plucks %ld, non-finite samples %ld, samples beyond full scale %ld (let through: "
                "the guard's ceiling is +12 dBFS), peak %.4f (%.1f dBFS)\n",
                p.instrument().dronePlucks(), nonFinite, beyond, peak, 20.0 * std::log10(std::max(peak, 1e-12)));
    const double mean = total / (blocks * budget);
    std::printf("  worst block %.3f ms = %.1f %% of its %.3f ms budget (in CPU time %.1f %%); mean %.1f %% (%.1fx real "
                "time)\n",
                worst * 1e3, 100.0 * worst / budget, budget * 1e3, 100.0 * cpuLoad.most(), 100.0 * mean,
                blocks * budget / total);
    std::printf("  per block, CPU time: p50 %.1f %%, p99 %.1f %%, p99.9 %.1f %%, max %.1f %%; wall time: p50 %.1f %%, "
                "p99 %.1f %%, p99.9 %.1f %%, max %.1f %%\n",
                100.0 * cpuLoad.percentile(0.5), 100.0 * cpuLoad.percentile(0.99), 100.0 * cpuLoad.percentile(0.999),
                100.0 * cpuLoad.most(), 100.0 * wallLoad.percentile(0.5), 100.0 * wallLoad.percentile(0.99),
                100.0 * wallLoad.percentile(0.999), 100.0 * wallLoad.most());
    // A slow block with no event and no more iterations than the mean block did no more work than
    // any other: the machine took the time (a preemption, another process), not the engine.
    const double meanIterations = double(iterations) / double(blocks);
    // With a second core the audio thread's CPU time leaves the worker's out: its wall time counts.
    const auto& slowest = secondCore != 0 ? wallLoad : cpuLoad;
    std::printf("  the slowest blocks (%s time; Newton iterations against the mean block's %.0f):\n",
                secondCore != 0 ? "wall" : "CPU", meanIterations);
    for (const auto& slow : slowest.slowest())
        std::printf("    %.1f %% at %.3f s: %s; %.2fx the mean block's iterations\n", 100.0 * slow.share,
                    slow.index * budget, jawari::BlockLoad::describe(slow.activity).c_str(),
                    meanIterations > 0.0 ? double(slow.activity.newtonIterations) / meanIterations : 0.0);
    const long limited = p.instrument().limitedSamples(), blowUps = p.instrument().blowUps();
    std::printf("  most Newton iterations in a step %d\n", p.instrument().maxIterations());
    std::printf("  guards: the output guard changed %ld samples (non-finite, or beyond +12 dBFS), the blow-up guard "
                "restarted %ld strings%s\n",
                limited, blowUps, limited == 0 && blowUps == 0 ? ": neither acted" : "");
    if (!csv.empty())
    {
        // preset, quality, rate, block, polyphony, drone, replay, minutes, mean, CPU p50, p99, p99.9, max, wall max
        if (FILE* f = std::fopen(csv.c_str(), "a"))
        {
            std::fseek(f, 0, SEEK_END);
            if (std::ftell(f) == 0)
                std::fputs("preset,quality,rate,block,polyphony,drone,replay,minutes,mean,p50,p99,p999,max,wall_max,"
                           "second_core,wall_p999\n",
                           f);
            std::fprintf(f, "%s,%d,%.0f,%d,%d,%d,%g,%g,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%d,%.4f\n", preset.c_str(), quality,
                         rate, block, polyphony, drone, replay, minutes, mean, cpuLoad.percentile(0.5),
                         cpuLoad.percentile(0.99), cpuLoad.percentile(0.999), cpuLoad.most(), wallLoad.most(),
                         secondCore, wallLoad.percentile(0.999));
            std::fclose(f);
        }
        else
        {
            std::fprintf(stderr, "jawari-soak: cannot append to %s\n", csv.c_str());
            return 2;
        }
    }
    if (limited != 0 || blowUps != 0 || nonFinite != 0)
    {
        std::string why = limited != 0 ? "the output guard acted" : "";
        if (blowUps != 0)
            why += std::string(why.empty() ? "" : ", ") + "the blow-up guard acted";
        if (nonFinite != 0)
            why += std::string(why.empty() ? "" : ", ") + "non-finite output";
        std::printf("jawari-soak: FAILED (exit 1): %s\n", why.c_str());
        return 1;
    }
    return 0;
}
