#pragma once

namespace jawari
{

// What the instrument did since clearActivity(): what can make a block slow (jawari-soak attributes
// its slowest blocks with it). RT: plain counters.
struct InstrumentActivity
{
    int notesStarted = 0;  // strings started from rest (a held shape, or a soft pluck's push)
    int pulses = 0;        // strings re-plucked while sounding (a force pulse)
    int dronePlucks = 0;
    int retunes = 0;  // strings retuned (a note's start, a bend, new damping)
    int packsInstalled = 0;
    long newtonIterations = 0;  // contact solve iterations, all strings
    int mostIterations = 0;     // the most in one step
    long workerStrings = 0;     // string chunks the second core stepped
    long workerRevoked = 0;     // string chunks taken back from the second core, late
    long workerUnstarted = 0;   // string chunks the second core had not started when collected
    long limitedSamples = 0;    // output samples the guard changed (guardOutput)
    long bodySteps = 0;         // internal steps of the strings on the body (SharedBody::step)
    long bodySolves = 0;        // their contact solves of every played string, summed over the steps
    long bodyTrials = 0;        // their trials (SharedBody::lastTrials), likewise
    long bodyResolves = 0;      // steps solved again with every point live (SharedBody::lastResolved)
    long bodyLivePoints = 0;    // the played strings' live contact points, summed over the steps (BodyReach)
    long bodyContactPoints = 0; // their contact points, likewise
};

}  // namespace jawari
