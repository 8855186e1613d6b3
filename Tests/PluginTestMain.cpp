// The plugin tests' main: JUCE's message manager lives for the whole run and is shut down before
// static destruction (a function-local static initialiser crashes at exit).
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include <juce_events/juce_events.h>

int main(int argc, char* argv[])
{
    juce::ScopedJuceInitialiser_GUI juce;
    return Catch::Session().run(argc, argv);
}
