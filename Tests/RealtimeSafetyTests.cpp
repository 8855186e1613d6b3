// The audio thread never allocates: every allocation made while a test holds the guard is counted
// (global operator new replaced in this test binary only).

#include "TestSupport.h"
#include "offline/Scene.h"
#include "realtime/Voice.h"

#include <catch2/catch.hpp>

#include "AllocationCounter.h"

#include <atomic>

using namespace jawari;
using test::allocations;
using test::CountAllocations;

TEST_CASE("the allocation counter sees allocations")
{
    long seen = 0;
    {
        CountAllocations guard;
        auto* v = new std::vector<double>(100);
        delete v;
        seen = allocations;
    }
    CHECK(seen == 2);
}

TEST_CASE("Voice process and pluck and release and takeMotionFrom never allocate")
{
    // Every contact path the voice can take: one point (paired), a sampled profile (decoupled
    // scalar solves), and two close off-grid points (the coupled P x P Newton with Eigen's LU).
    std::vector<std::vector<Obstacle>> sets(3);
    sets[0] = {test::pointObstacle(0.006)};
    Obstacle profile;
    profile.type = ObstacleType::profile;
    profile.profileX = {0.0, 0.01, 0.02};
    profile.profileHeight = {-2e-5, 0.0, -2e-5};
    sets[1] = {profile};
    sets[2] = {test::pointObstacle(0.30017, -2e-5, 2e-3, 1e11, 1.5),
               test::pointObstacle(0.30391, -2e-5, 2e-3, 1e11, 1.5)};
    for (const auto& obstacles : sets)
    {
        VoiceConfig config;
        config.obstacles = obstacles;
        config.modes = 150;
        config.oversampling = 8;
        Voice voice(config);
        config.obstacles = sets[0];
        Voice other(config);  // built off the audio thread, as a new obstacle would be
        std::vector<double> block(256);
        long counted = 0;
        int maxIterations = 0;
        {
            CountAllocations guard;
            voice.pluckWithPulse(1.0);
            for (int b = 0; b < 200; ++b)
            {
                voice.process(block.data(), 256);
                maxIterations = std::max(maxIterations, voice.takeMaxIterations());
                if (b == 50)
                    voice.pluckWithPulse(0.7);  // again while sounding
                if (b == 120)
                    voice.release();
                if (b == 150)
                {
                    voice.cancelRelease();
                    other.takeMotionFrom(voice);
                    other.process(block.data(), 256);
                }
            }
            counted = allocations;
        }
        INFO(voice.contactPoints() << " contact points, most Newton iterations " << maxIterations);
        CHECK(counted == 0);
        CHECK(maxIterations > 0);  // the contact was exercised
        for (double v : block)
            REQUIRE(std::isfinite(v));
    }
}

#include "realtime/LockFreeExchange.h"

#include <thread>

TEST_CASE("new voices built on a control thread reach the audio thread lock-free and are freed off it")
{
    // The control thread builds voices with the obstacle moving along the string and offers them;
    // the audio thread processes blocks, takes the newest at block boundaries and carries the
    // sounding string over. The audio thread counts its own allocations: there must be none.
    LockFreeExchange<Voice> exchange;
    VoiceConfig config;
    config.modes = 120;
    config.oversampling = 4;
    config.obstacles = {test::pointObstacle(0.006)};
    exchange.offer(std::make_unique<Voice>(config));
    std::atomic<bool> done{false};
    std::atomic<int> taken{0};
    long audioAllocations = -1;
    bool finite = true;
    long freed = 0;

    std::thread audio([&] {
        std::vector<double> block(128);
        Voice* voice = exchange.take();
        {
            CountAllocations guard;  // this thread only
            voice->pluckWithPulse(1.0);
            for (int b = 0; b < 3000; ++b)
            {
                Voice* previous = nullptr;
                if (Voice* fresh = exchange.take(&previous))
                {
                    fresh->takeMotionFrom(*previous);  // previous is still alive until retire()
                    exchange.retire();
                    voice = fresh;
                    ++taken;
                }
                voice->process(block.data(), 128);
                for (double v : block)
                    finite = finite && std::isfinite(v);
                if (b % 500 == 0)
                    voice->pluckWithPulse(0.8);
            }
            audioAllocations = allocations;
        }
        done = true;
    });
    for (int k = 0; !done; ++k)
    {
        config.obstacles = {test::pointObstacle(0.006 + 0.0005 * (k % 40))};
        exchange.offer(std::make_unique<Voice>(config));
        freed += exchange.collect();
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    audio.join();
    freed += exchange.collect();
    INFO("voices handed over " << taken << ", freed on the control thread " << freed << ", audio-thread allocations "
                               << audioAllocations);
    CHECK(audioAllocations == 0);
    CHECK(finite);
    CHECK(taken > 5);
    CHECK(freed == taken);  // every voice the audio thread replaced came back and was freed here
}

#include "realtime/Instrument.h"

TEST_CASE("The instrument plays notes and drone and takes automation and new packs without allocating")
{
    // Every obstacle shape (one point, a parabolic bridge, five frets), the point and the bridge
    // with its thread also in two polarisations, and every method. Each voice alone, the string
    // bank, and each voice alone with a second core (whose clones the audio thread copies every
    // chunk).
    struct Stepping
    {
        StringScheduling scheduling;
        bool secondCore;
    };
    struct Strings
    {
        ObstacleShape shape;
        bool twoPolarisationsAndThread;
    };
    for (const auto [shape, twoAndThread] : {Strings{ObstacleShape::point, false}, Strings{ObstacleShape::point, true},
                                             Strings{ObstacleShape::parabola, false},
                                             Strings{ObstacleShape::parabola, true}, Strings{ObstacleShape::frets, false}})
        for (const auto method : {ContactMethod::energyConserving, ContactMethod::quadratised, ContactMethod::penalty,
                                  ContactMethod::quadraticSpline})
            for (const auto [scheduling, secondCore] : {Stepping{StringScheduling::lone, false},
                                                        Stepping{StringScheduling::bank, false},
                                                        Stepping{StringScheduling::lone, true}})
        {
            InstrumentStructure s;
            s.quality = 0;
            s.shape = shape;
            s.method = method;
            s.obstaclePosition = shape == ObstacleShape::parabola ? 0.01 : 0.3;
            s.obstacleWidth = shape == ObstacleShape::parabola ? 0.02 : 1e-3;
            s.polarisations = twoAndThread ? 2 : 1;
            s.thread = twoAndThread;  // across the parabola; a point has none
            auto first = buildVoicePack(s);
            s.obstaclePosition += 0.01;
            auto second = buildVoicePack(s);  // built off the audio thread, as the plugin's builder does
            StringWorker worker;  // after the packs: stopped before they are freed
            if (secondCore)
                worker.start();
            Instrument instrument;
            instrument.setScheduling(scheduling);
            instrument.setWorker(secondCore ? &worker : nullptr);
            InstrumentControls c;
            instrument.setControls(c);
            instrument.install(first.get(), nullptr);
            std::vector<float> left(512), right(512);
            InstrumentSnapshot snapshot;
            long counted = 0;
            {
                CountAllocations guard;
                for (int b = 0; b < 120; ++b)
                {
                    if (b < 10)
                        instrument.noteOn(50 + 2 * b, 0.9);  // the ninth and tenth steal
                    if (b == 20)
                    {
                        instrument.pitchBend(0.7);
                        c.obstacleHeight = 2e-4;
                        c.stiffness = 1e10;
                        c.exponent = 2.0;
                        c.dampingCurve[3] = 4.0;
                        c.decayScale = 2.0;
                        c.drone = true;
                        c.droneTempo = 300.0;
                        instrument.setControls(c);
                        instrument.sustain(true);
                    }
                    if (b == 40)
                        instrument.install(second.get(), first.get());
                    if (b == 60)
                    {
                        for (int n = 0; n < 10; ++n)
                            instrument.noteOff(50 + 2 * n);
                        instrument.sustain(false);
                    }
                    instrument.render(left.data(), right.data(), b % 2 == 0 ? 512 : 37);
                }
                counted = allocations;
            }
            INFO("shape " << int(shape) << " two polarisations and thread " << twoAndThread << " method " << int(method)
                          << " scheduling " << int(scheduling) << " second core " << secondCore);
            CHECK(counted == 0);
            CHECK(instrument.snapshots().read(snapshot));
            CHECK(snapshot.sequence > 0);
            for (float v : left)
                REQUIRE(std::isfinite(v));
        }
}
