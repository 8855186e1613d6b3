#pragma once
// Notes played in the editor (its on-screen keyboard, the computer keyboard through it, the Pluck
// button) go to a MidiKeyboardState; from there they reach the audio thread through a lock-free
// queue. MidiKeyboardState::processNextMidiBuffer would take the state's lock on the audio thread
// and add events to the host's MidiBuffer, which allocates when the buffer is full.

#include <juce_audio_basics/juce_audio_basics.h>

#include <array>

namespace jawari::plugin
{

class KeyboardInput : private juce::MidiKeyboardState::Listener
{
public:
    struct Event
    {
        int note = 0;
        float velocity = 0.0f;
        bool on = false;
    };

    KeyboardInput() { state_.addListener(this); }
    ~KeyboardInput() override { state_.removeListener(this); }
    KeyboardInput(const KeyboardInput&) = delete;
    KeyboardInput& operator=(const KeyboardInput&) = delete;

    // CT: the state the editor's keyboard shows and presses.
    juce::MidiKeyboardState& state() { return state_; }

    // RT: hands every queued event to `play`, oldest first. No allocation, no lock.
    template <typename Play>
    void drain(Play&& play)
    {
        const auto scope = fifo_.read(fifo_.getNumReady());
        scope.forEach([&](int i) { play(events_[size_t(i)]); });
    }

private:
    // Called by the thread that presses a key, under the state's lock: one producer at a time.
    void handleNoteOn(juce::MidiKeyboardState*, int, int note, float velocity) override
    {
        push({note, velocity, true});
    }
    void handleNoteOff(juce::MidiKeyboardState*, int, int note, float) override { push({note, 0.0f, false}); }
    // A full queue (audio not running) drops the event.
    void push(Event e)
    {
        const auto scope = fifo_.write(1);
        scope.forEach([&](int i) { events_[size_t(i)] = e; });
    }

    static constexpr int kCapacity = 256;
    juce::MidiKeyboardState state_;
    juce::AbstractFifo fifo_{kCapacity};
    std::array<Event, kCapacity> events_{};
};

}  // namespace jawari::plugin
