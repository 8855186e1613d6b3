#pragma once
// The editor's colours, shared by its views and panels.

#include <juce_graphics/juce_graphics.h>

namespace jawari::plugin
{

inline const juce::Colour kBackground{0xff15171c}, kPanel{0xff1f232b}, kString{0xfff2c14e}, kObstacle{0xff6fb3d2},
    kGrid{0xff343a46}, kText{0xffd8dde6};

}  // namespace jawari::plugin
