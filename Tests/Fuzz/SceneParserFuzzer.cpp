// libFuzzer target for the scene parser: any bytes either parse into a scene that passes
// validation or throw SceneError; nothing else (no crash, no other exception, no sanitizer report).
//
//   bash tools/fuzz.sh [seconds]

#include "offline/Scene.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::string text(reinterpret_cast<const char*>(data), size);
    try
    {
        const auto scene = jawari::parseScene(text);
        // What parses is valid: positive length, points on the string, finite numbers.
        if (!(scene.string.lengthMetres > 0.0) || !std::isfinite(scene.string.tensionNewtons)
            || !(scene.excitation.position > 0.0 && scene.excitation.position < scene.string.lengthMetres))
            std::abort();
    }
    catch (const jawari::SceneError&)
    {}
    return 0;
}
