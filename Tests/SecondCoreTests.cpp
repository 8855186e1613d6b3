// The second core (Engine/realtime/instrument/StringWorker.h): a voice's copy steps as the voice, and the
// instrument's output is the same bit for bit with the worker on, late, or stopped mid-play. Its own
// binary, linking the real-time engine only, so that tools/tsan.sh can build it under
// ThreadSanitizer.

#include "realtime/instrument/Instrument.h"
#include "realtime/instrument/StringWorker.h"
#include "realtime/voice/Voice.h"

#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <cstring>
#include <functional>
#include <thread>
#include <vector>

using namespace jawari;

namespace
{
// Under ThreadSanitizer (tools/tsan.sh) everything runs many times slower: a shorter performance.
#ifdef __SANITIZE_THREAD__
constexpr int kBlocks = 64;
#else
constexpr int kBlocks = 300;
#endif

InstrumentStructure structureFor(ObstacleShape shape)
{
    InstrumentStructure s;
    s.quality = 0;  // draft: quick
    s.shape = shape;
    s.obstaclePosition = shape == ObstacleShape::parabola ? 0.03 : 0.006;
    s.obstacleWidth = shape == ObstacleShape::parabola ? 0.02 : 1e-3;
    return s;
}

struct Performance
{
    std::vector<float> left, right;
    InstrumentActivity activity;
};

// Eight notes, the drone, a bend, the bridge automated, a new pack, the notes released: kBlocks
// blocks of 128 samples (and of 37 now and then; 0.7 s in all without a sanitizer), with the second
// core if one is given, and `afterBlock` called between blocks if given.
Performance perform(ObstacleShape shape, StringWorker* worker, const std::function<void()>& afterBlock = {})
{
    auto structure = structureFor(shape);
    auto first = buildVoicePack(structure);
    structure.pluckPosition = 0.3;
    auto second = buildVoicePack(structure);
    Instrument instrument;
    instrument.setWorker(worker);
    // The bridge held lower than the point: a string pressed deep along a bridge costs many times
    // real time at draft.
    const double height = shape == ObstacleShape::parabola ? 2e-5 : 1e-4;
    InstrumentControls c;
    c.obstacleHeight = height;
    instrument.setControls(c);
    instrument.install(first.get(), nullptr);
    instrument.settleControls();
    instrument.clearActivity();
    Performance out;
    std::vector<float> l(128), r(128);
    for (int b = 0; b < kBlocks; ++b)
    {
        if (b < 8)
            instrument.noteOn(45 + 3 * b, 0.5 + 0.05 * b);
        if (b == kBlocks / 8)
        {
            instrument.pitchBend(0.5);
            c.drone = true;
            c.droneTempo = 240.0;
            c.obstacleHeight = 3.0 * height;
            c.decayScale = 1.5;
            instrument.setControls(c);
        }
        if (b == kBlocks / 3)
            instrument.install(second.get(), first.get());
        if (b == 2 * kBlocks / 3)
            for (int n = 0; n < 8; ++n)
                instrument.noteOff(45 + 3 * n);
        const int count = b % 7 == 3 ? 37 : 128;
        instrument.render(l.data(), r.data(), count);
        out.left.insert(out.left.end(), l.begin(), l.begin() + count);
        out.right.insert(out.right.end(), r.begin(), r.begin() + count);
        if (afterBlock)
            afterBlock();
    }
    out.activity = instrument.activity();
    if (worker != nullptr)
        worker->waitForJobs(worker->postedJobs());  // the packs die here: nothing may still step them
    return out;
}

bool sameBits(const std::vector<float>& a, const std::vector<float>& b)
{
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// The worker's task hook: counts the tasks it claims.
void countTask(void* tasks)
{
    ++*static_cast<std::atomic<long>*>(tasks);
}

double peak(const std::vector<float>& y)
{
    double m = 0.0;
    for (float v : y)
        m = std::max(m, double(std::abs(v)));
    return m;
}
}  // namespace

TEST_CASE("A voice copied into another built alike steps exactly as the original", "[second core]")
{
    auto pack = buildVoicePack(structureFor(ObstacleShape::parabola));
    Voice& voice = *pack->voices[0];
    Voice& clone = *pack->backups[0];
    voice.setContactLaw(ContactLaw{1e13, 1.3}, 1e-4);  // the bridge pushed into the string
    voice.pluckFromShape(2e-3);
    std::vector<double> a(64 * size_t(pack->oversampling)), b(a.size()), a2(a.size()), b2(a.size());
    for (int k = 0; k < 20; ++k)  // into contact with the bridge, out of reach points refreshed
        voice.processInternal(a.data(), 64, a2.data());
    clone.processInternal(b.data(), 64, b2.data());  // the clone elsewhere: overwritten next
    clone = voice;
    for (int k = 0; k < 50; ++k)
    {
        voice.processInternal(a.data(), 64, a2.data());
        clone.processInternal(b.data(), 64, b2.data());
        REQUIRE(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
        REQUIRE(std::memcmp(a2.data(), b2.data(), a2.size() * sizeof(double)) == 0);
    }
    CHECK(voice.stringEnergy() == clone.stringEnergy());
    CHECK(voice.stringEnergy() > 0.0);
}

TEST_CASE("A backup copied before every chunk steps as its voice, through retunes, plucks, releases and new laws",
          "[second core]")
{
    // The copy skips the tables the backup holds already (StampedVector.h, ModalState): each
    // change to the voice's tables must reach the backup, and a backup swapped in for its voice (a
    // revoked task) must be copied back from correctly. The point (the spline) and the parabola
    // (the Newton over several points), each chunk compared bit for bit.
    for (const auto shape : {ObstacleShape::point, ObstacleShape::parabola})
    {
        auto pack = buildVoicePack(structureFor(shape));
        Voice* voice = pack->voices[0].get();
        Voice* backup = pack->backups[0].get();
        voice->setContactLaw(ContactLaw{1e13, 1.3}, shape == ObstacleShape::parabola ? 1e-4 : 5e-4);
        voice->pluckFromShape(2e-3);
        const std::vector<double> sigma = voice->solver().sigma();
        std::vector<double> a(32 * size_t(pack->oversampling)), b(a.size()), a2(a.size()), b2(a.size());
        int differ = 0;
        for (int k = 0; k < 120; ++k)
        {
            if (k % 7 == 2)
                voice->retune(1.0 + 0.004 * (k % 5), sigma.data());
            if (k % 13 == 5)
                voice->pluckWithPulse(0.6);
            if (k % 11 == 4)
                voice->setContactLaw(ContactLaw{k % 2 == 0 ? 1e12 : 1e13, 1.3}, 1e-4 * (k % 3));
            if (k == 60)
                voice->release();
            if (k == 90)
                voice->cancelRelease();
            *backup = *voice;
            voice->processInternal(a.data(), 32, a2.data());
            backup->processInternal(b.data(), 32, b2.data());
            differ += std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) != 0
                      || std::memcmp(a2.data(), b2.data(), a2.size() * sizeof(double)) != 0
                      || voice->stringEnergy() != backup->stringEnergy();  // the energy reads the tables
            if (k % 9 == 8)
                std::swap(voice, backup);  // the backup becomes the string
        }
        INFO("shape " << int(shape) << ": " << differ << " of 120 chunks differ");
        CHECK(differ == 0);
        CHECK(voice->stringEnergy() > 0.0);
    }
}

TEST_CASE("With a second core the instrument's output is the same bit for bit, on time or late",
          "[second core]")
{
    for (const auto shape : {ObstacleShape::point, ObstacleShape::parabola})
    {
        INFO("shape " << int(shape));
        const Performance alone = perform(shape, nullptr);
        REQUIRE(peak(alone.left) > 0.01);

        StringWorker worker;
        worker.start();
        // As in a performance: which strings the worker steps depends on the machine's load.
        const Performance shared = perform(shape, &worker);
        CHECK(sameBits(shared.left, alone.left));
        CHECK(sameBits(shared.right, alone.right));
        CHECK(shared.activity.newtonIterations == alone.activity.newtonIterations);

        // Each block, the worker claims and finishes every string it is handed (the audio thread waits
        // for it), after the one before has finished its job: each block but the first (one string
        // sounds) hands it one job or more.
        std::atomic<long> claimed{0};
        worker.setTaskHookForTesting(&countTask, &claimed);
        worker.setPaceForTesting(StringWorker::Pace::inStep);
        uint32_t jobsBefore = worker.postedJobs();
        const Performance inStep = perform(shape, &worker, [&] { worker.waitForJobs(worker.postedJobs()); });
        const long inStepJobs = long(worker.postedJobs() - jobsBefore);
        const long inStepClaimed = claimed.exchange(0);

        // A worker the system keeps preempting: it holds the first string of each job until the block
        // is over, so the audio thread revokes that string and steps the rest of the block alone; the
        // test lets it finish between blocks.
        worker.setPaceForTesting(StringWorker::Pace::held);
        jobsBefore = worker.postedJobs();
        const Performance late = perform(shape, &worker, [&] {
            worker.setPaceForTesting(StringWorker::Pace::free);
            worker.waitForJobs(worker.postedJobs());
            worker.setPaceForTesting(StringWorker::Pace::held);
        });
        worker.setPaceForTesting(StringWorker::Pace::free);
        worker.setTaskHookForTesting(nullptr, nullptr);
        const long lateJobs = long(worker.postedJobs() - jobsBefore);
        INFO("as in a performance: " << shared.activity.workerStrings << " strings by the worker, "
                                     << shared.activity.workerRevoked << " taken back; in step: " << inStepJobs
                                     << " jobs, " << inStep.activity.workerStrings << " strings by the worker; late: "
                                     << lateJobs << " jobs, " << late.activity.workerRevoked << " strings taken back");
        CHECK(sameBits(inStep.left, alone.left));
        CHECK(sameBits(inStep.right, alone.right));
        CHECK(inStepJobs >= kBlocks - 1);
        CHECK(inStep.activity.workerStrings >= inStepJobs);
        CHECK(inStep.activity.workerStrings == inStepClaimed);
        CHECK(inStep.activity.workerRevoked + inStep.activity.workerUnstarted == 0);

        CHECK(sameBits(late.left, alone.left));
        CHECK(sameBits(late.right, alone.right));
        CHECK(lateJobs == kBlocks - 1);  // one a block
        CHECK(claimed == lateJobs);
        CHECK(late.activity.workerRevoked == lateJobs);
        CHECK(late.activity.workerStrings == 0);
    }
}

TEST_CASE("A worker never started, or stopped and started again, changes nothing", "[second core]")
{
    const Performance alone = perform(ObstacleShape::point, nullptr);
    StringWorker worker;
    // Stopped before it ever runs: every task posted is taken back (none is), nothing waits.
    const Performance never = perform(ObstacleShape::point, &worker);
    CHECK(sameBits(never.left, alone.left));
    CHECK(never.activity.workerStrings == 0);
    worker.start();
    worker.stop();
    worker.start();
    const Performance again = perform(ObstacleShape::point, &worker);
    CHECK(sameBits(again.left, alone.left));
    CHECK(sameBits(again.right, alone.right));

    // The restarted worker takes a job: one string, collected once the job is finished (a second at
    // most; whether it wins the race with the audio thread depends on the machine's load, so the
    // instrument's count of the worker's strings would not say).
    auto pack = buildVoicePack(structureFor(ObstacleShape::point));
    Voice& voice = *pack->voices[0];
    voice.pluckFromShape(1e-3);
    std::vector<double> block(32 * size_t(pack->oversampling)), second(block.size());
    REQUIRE(worker.idle());
    worker.post(1, 32);
    worker.offer(0, {&voice, block.data(), second.data()});
    const auto patience = std::chrono::steady_clock::now() + std::chrono::seconds(1);
    while (!worker.jobFinished() && std::chrono::steady_clock::now() < patience)
        std::this_thread::sleep_for(std::chrono::microseconds(100));
    CHECK(worker.collect(0, std::chrono::steady_clock::now()) == StringWorker::Outcome::worker);
    CHECK(voice.stringEnergy() > 0.0);
    worker.waitForJobs(worker.postedJobs());
}
