// A corpus of malformed and extreme scenes (Tests/scenes/corpus, expectations in
// corpus-expectations.json): each gives a clear error naming its field, or a finite, bounded render.

#include "offline/OfflineRender.h"
#include "offline/Scene.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <string>

using namespace jawari;

TEST_CASE("every scene of the malformed and extreme corpus is rejected by name or renders finite and bounded")
{
    const std::string dir = std::string(JAWARI_TESTS_DIR) + "/scenes/";
    std::ifstream manifestFile(dir + "corpus-expectations.json");
    REQUIRE(manifestFile.good());
    const auto manifest = nlohmann::json::parse(manifestFile);
    REQUIRE(manifest.size() >= 50);
    int errors = 0, renders = 0;
    for (const auto& [file, expectation] : manifest.items())
    {
        const std::string expect = expectation.get<std::string>();
        INFO(file << ": expected " << expect);
        if (expect.rfind("error:", 0) == 0)
        {
            std::string message;
            try
            {
                loadSceneFile(dir + "corpus/" + file);
            }
            catch (const SceneError& e)
            {
                message = e.what();
            }
            INFO("message: " << message);
            CHECK_THAT(message, Catch::Matchers::Contains(expect.substr(6)));
            ++errors;
            continue;
        }
        const auto scene = loadSceneFile(dir + "corpus/" + file);
        const auto result = renderScene(scene);
        double peak = 0.0;
        bool finite = true;
        for (double v : result.output)
        {
            finite = finite && std::isfinite(v);
            peak = std::max(peak, std::abs(v));
        }
        const double bound = scene.pickup.quantity == PickupQuantity::force ? 1e5 : 1.0;  // N, else m
        INFO("peak " << peak << " " << quantityUnit(scene.pickup.quantity) << ", Newton max "
                     << result.stats.newtonIterationsMax);
        CHECK(finite);
        CHECK(peak < bound);
        CHECK(result.output.size()
              == size_t(std::llround(scene.simulation.durationSeconds * scene.simulation.outputRateHz)));
        ++renders;
    }
    CHECK(errors >= 40);
    CHECK(renders >= 10);
}
