// The real-time threads, the audio thread and the second core's worker, never allocate and never
// lock: every allocation and every lock taken on a thread a test marks real-time is counted (the
// global operator new, glibc's allocator and pthread's lock functions replaced in this test binary
// only: AllocationCounter.h, LockCounter.h).

#include "TestSupport.h"
#include "offline/Scene.h"
#include "physics/string/StringDiscretisation.h"
#include "realtime/voice/Voice.h"

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

TEST_CASE("A solver with the static-exact forcing retunes and steps without allocating")
{
    // Its retune forms the gains again: the state, shapes, pickups and the coupling A follow them.
    auto s = test::paperString(DampingLaw::valette);
    const int M = 197;
    auto config = stringSolverConfig(s, {test::sitarLikeBridge()}, M, 288000.0, 0.992, PickupQuantity::displacement);
    config.staticExactForcing = true;
    ModalSolver solver(config);
    solver.setInitialDisplacement(pluckModalShape(s.lengthMetres, M, 0.18, 1e-3));
    auto omega = config.modes.omega;
    long counted = 0;
    double energyBefore = 0.0, energyAfter = 0.0;
    {
        CountAllocations guard;
        for (const double ratio : {1.05, 0.9, 1.0})
        {
            for (size_t p = 0; p < omega.size(); ++p)
                omega[p] = ratio * config.modes.omega[p];
            solver.retune(omega.data(), config.modes.sigma.data(), 1.0);
            for (int n = 0; n < 2000; ++n)
                solver.step();
        }
        counted = allocations;
    }
    energyBefore = solver.energy().total;
    for (int n = 0; n < 2000; ++n)
        solver.step();
    energyAfter = solver.energy().total;
    INFO("allocations " << counted << ", energy " << energyBefore << " then " << energyAfter);
    CHECK(counted == 0);
    CHECK(energyAfter <= energyBefore);
    CHECK(energyAfter > 0.5 * energyBefore);
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

#include "realtime/instrument/LockFreeExchange.h"

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

#include "realtime/instrument/Instrument.h"

namespace
{
// Draft quality on `shape` (a point at 0.3 or a 20 mm parabola at 0.01, of the string's length),
// solved by `method`, in two polarisations with a thread across a parabola (`twoAndThread`), the
// thread a contact (`rigidThread`: its strings take the static-exact forcing) or a spring and damper.
InstrumentStructure draftStructure(ObstacleShape shape, ContactMethod method, bool twoAndThread, bool rigidThread)
{
    InstrumentStructure s;
    s.quality = 0;
    s.shape = shape;
    s.method = method;
    s.obstaclePosition = shape == ObstacleShape::parabola ? 0.01 : 0.3;
    s.obstacleWidth = shape == ObstacleShape::parabola ? 0.02 : 1e-3;
    s.polarisations = twoAndThread ? 2 : 1;
    s.thread = twoAndThread;  // across the parabola; a point has none
    s.threadModel = rigidThread ? ThreadModel::contact : ThreadModel::springDamper;
    return s;
}

// 120 blocks of 512 and 37 samples, allocations counted: ten notes (the ninth and tenth steal), at
// block 20 a bend, new contact, damping and drone controls and the sustain pedal, at 40 a new pack
// (`second`, taking `first`'s motion), at 60 the notes released.
long allocationsOverPerformance(Instrument& instrument, VoicePack& first, VoicePack& second, std::vector<float>& left,
                                std::vector<float>& right)
{
    InstrumentControls c;
    CountAllocations guard;
    for (int b = 0; b < 120; ++b)
    {
        if (b < 10)
            instrument.noteOn(50 + 2 * b, 0.9);
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
            instrument.install(&second, &first);
        if (b == 60)
        {
            for (int n = 0; n < 10; ++n)
                instrument.noteOff(50 + 2 * n);
            instrument.sustain(false);
        }
        instrument.render(left.data(), right.data(), b % 2 == 0 ? 512 : 37);
    }
    return allocations;
}
}  // namespace

TEST_CASE("The instrument plays notes and drone and takes automation and new packs without allocating")
{
    // Every obstacle shape (one point, a parabolic bridge, five frets), the point and the bridge
    // with its thread also in two polarisations, and every method, each played by one of three
    // steppings: each voice alone, the string bank, and each voice alone with a second core (whose
    // clones the audio thread copies every chunk). The stepping rotates with the shape and the
    // method, (shape + method) mod 3, so that every pair of shape and method, of shape and
    // stepping, and of method and stepping is played (a pairwise cover: 24 performances, not 72). The
    // bridge with a rigid thread takes the static-exact forcing, whose pitch bend forms its gains again.
    struct Stepping
    {
        StringScheduling scheduling;
        bool secondCore;
    };
    struct Strings
    {
        ObstacleShape shape;
        bool twoPolarisationsAndThread;
        bool rigidThread = false;  // the contact thread, whose strings take the static-exact forcing
    };
    const Strings strings[] = {{ObstacleShape::point, false},    {ObstacleShape::point, true},
                               {ObstacleShape::parabola, false}, {ObstacleShape::parabola, true},
                               {ObstacleShape::frets, false},    {ObstacleShape::parabola, true, true}};
    const ContactMethod methods[] = {ContactMethod::energyConserving, ContactMethod::quadratised, ContactMethod::penalty,
                                     ContactMethod::quadraticSpline};
    const Stepping steppings[] = {{StringScheduling::lone, false}, {StringScheduling::bank, false},
                                  {StringScheduling::lone, true}};
    for (size_t shapeIndex = 0; shapeIndex < std::size(strings); ++shapeIndex)
        for (size_t methodIndex = 0; methodIndex < std::size(methods); ++methodIndex)
        {
            const auto [shape, twoAndThread, rigidThread] = strings[shapeIndex];
            const auto method = methods[methodIndex];
            const auto [scheduling, secondCore] = steppings[(shapeIndex + methodIndex) % std::size(steppings)];
            auto s = draftStructure(shape, method, twoAndThread, rigidThread);
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
            const long counted = allocationsOverPerformance(instrument, *first, *second, left, right);
            INFO("shape " << int(shape) << " two polarisations and thread " << twoAndThread << " method " << int(method)
                          << " scheduling " << int(scheduling) << " second core " << secondCore);
            CHECK(counted == 0);
            CHECK(instrument.snapshots().read(snapshot));
            CHECK(snapshot.sequence > 0);
            for (float v : left)
                REQUIRE(std::isfinite(v));
        }
}

#include "LockCounter.h"
#include "realtime/instrument/StringWorker.h"

#include <mutex>

namespace
{
// One allocation, kept until the next, so that it cannot be optimised away.
std::atomic<int*> kept{nullptr};
void allocateOnce()
{
    delete kept.exchange(new int(1));
}

// The second core's worker marked real-time by its task hook, in each task it claims; on request it
// also allocates and locks there once, a fault the counters must see.
struct WorkerMark
{
    test::RealtimeCounts counts;  // declared before the worker it marks: it outlives its thread
    std::atomic<long> tasks{0};
    bool misbehave = false;
    std::mutex mutex;

    static void inTask(void* self)
    {
        auto& mark = *static_cast<WorkerMark*>(self);
        test::countOnThisThread(&mark.counts);
        ++mark.tasks;
        if (mark.misbehave)
        {
            allocateOnce();
            const std::lock_guard<std::mutex> lock(mark.mutex);
        }
    }
};

// A job of one string posted straight to the worker, collected once the worker has finished it.
void stepOnWorker(StringWorker& worker, const VoicePack& pack)
{
    Voice& voice = *pack.voices[0];
    std::vector<double> block(32 * size_t(pack.oversampling)), second(block.size());
    worker.post(1, 32);
    worker.offer(0, {&voice, block.data(), second.data()});
    worker.waitForJobs(worker.postedJobs());
    worker.collect(0, std::chrono::steady_clock::now());
}

InstrumentStructure draftPoint()
{
    InstrumentStructure s;
    s.quality = 0;
    s.shape = ObstacleShape::point;
    s.obstaclePosition = 0.3;
    s.obstacleWidth = 1e-3;
    return s;
}
}  // namespace

TEST_CASE("The counters see an allocation and a lock on a thread marked real-time, the worker's too")
{
    test::RealtimeCounts here;
    std::mutex mutex;
    test::countOnThisThread(&here);
    allocateOnce();
    {
        const std::lock_guard<std::mutex> lock(mutex);
    }
    test::countOnThisThread(nullptr);
    CHECK(here.allocations == 1);
    if (test::kCountsLocks)
        CHECK(here.locks == 1);  // std::mutex reaches pthread_mutex_lock, counted

    auto pack = buildVoicePack(draftPoint());
    WorkerMark mark;
    StringWorker worker;
    worker.setTaskHookForTesting(&WorkerMark::inTask, &mark);
    worker.start();
    stepOnWorker(worker, *pack);  // marks the worker
    const long allocationsMarked = mark.counts.allocations, locksMarked = mark.counts.locks;
    mark.misbehave = true;
    stepOnWorker(worker, *pack);
    INFO("the worker's allocations " << mark.counts.allocations << ", locks " << mark.counts.locks);
    CHECK(mark.tasks == 2);
    CHECK(allocationsMarked == 0);
    CHECK(locksMarked == 0);
    CHECK(mark.counts.allocations == 1);
    if (test::kCountsLocks)
        CHECK(mark.counts.locks == 1);
    else
        WARN("locks are not counted in this build (LockCounter.h)");
}

namespace
{
// Block b's events of the twelve strings' performance: eight notes, the drone from 20 (twelve strings),
// the bend at 60 and 200, new damping and height at 100, a new pack at 150, the notes released at
// 250, one plucked again at 320.
void twelveStringsEvent(Instrument& instrument, InstrumentControls& c, VoicePack& first, VoicePack& second, int b)
{
    if (b < 8)
        instrument.noteOn(45 + 3 * b, 0.6);
    if (b == 20)
    {
        c.drone = true;  // four strings more: twelve
        c.droneTempo = 240.0;
        instrument.setControls(c);
    }
    if (b == 60 || b == 200)
        instrument.pitchBend(b == 60 ? 0.5 : -0.3);  // every string retuned
    if (b == 100)
    {
        c.decayScale = 2.0;  // retuned again: new damping
        c.obstacleHeight = 2e-4;
        instrument.setControls(c);
    }
    if (b == 150)
        instrument.install(&second, &first);
    if (b == 250)
        for (int n = 0; n < 8; ++n)
            instrument.noteOff(45 + 3 * n);
    if (b == 320)
        instrument.noteOn(60, 0.8);  // a string released, plucked again
}
}  // namespace

TEST_CASE("Neither the audio thread nor the worker allocates or locks, twelve strings on two cores through notes, "
          "retunes, releases and a new pack")
{
    auto structure = draftPoint();
    auto first = buildVoicePack(structure);
    structure.pluckPosition = 0.3;
    auto second = buildVoicePack(structure);
    WorkerMark mark;
    StringWorker worker;
    // The hook marks the worker; in step, the worker steps every string it is handed, whatever the load.
    worker.setTaskHookForTesting(&WorkerMark::inTask, &mark);
    worker.setPaceForTesting(StringWorker::Pace::inStep);
    worker.start();
    Instrument instrument;
    instrument.setWorker(&worker);
    InstrumentControls c;
    instrument.setControls(c);
    instrument.install(first.get(), nullptr);
    instrument.clearActivity();
    std::vector<float> left(128), right(128);
    test::RealtimeCounts audio;
    int mostStrings = 0;
    const uint32_t jobsBefore = worker.postedJobs();
    test::countOnThisThread(&audio);
    for (int b = 0; b < 400; ++b)
    {
        twelveStringsEvent(instrument, c, *first, *second, b);
        instrument.render(left.data(), right.data(), b % 7 == 3 ? 37 : 128);
        mostStrings = std::max(mostStrings, instrument.activeStrings());
        // Between blocks the worker finishes what it was late with: each block posts it a job.
        test::countOnThisThread(nullptr);
        worker.waitForJobs(worker.postedJobs());
        test::countOnThisThread(&audio);
    }
    test::countOnThisThread(nullptr);
    worker.waitForJobs(worker.postedJobs());
    worker.setPaceForTesting(StringWorker::Pace::free);
    worker.setTaskHookForTesting(nullptr, nullptr);
    const auto& activity = instrument.activity();
    const long jobs = long(worker.postedJobs() - jobsBefore);
    INFO("jobs " << jobs << ", strings the worker claimed " << mark.tasks << ", stepped " << activity.workerStrings
                 << "; retunes " << activity.retunes << ", packs " << activity.packsInstalled << ", most strings "
                 << mostStrings);
    CHECK(audio.allocations == 0);
    CHECK(audio.locks == 0);
    CHECK(mark.counts.allocations == 0);
    CHECK(mark.counts.locks == 0);
    // The worker stepped strings all along: those of each job.
    CHECK(jobs >= 399);  // every block but the first, which sounds one string
    CHECK(activity.workerStrings >= jobs);
    CHECK(mark.tasks == activity.workerStrings);
    CHECK(activity.workerRevoked + activity.workerUnstarted == 0);
    CHECK(mostStrings == 12);
    CHECK(activity.retunes > 24);
    CHECK(activity.packsInstalled == 1);
}
