// The scene's "body" object (docs/scenes.md): a factory body by name, or its modes listed; the
// obstacles that stand on it; its coupling.
#include "offline/SceneReader.h"

#include "physics/body/FactoryBodies.h"
#include "realtime/sympathetic/SympatheticStrings.h"

#include <algorithm>
#include <stdexcept>

namespace jawari
{
int pickupListener(const Scene& scene)
{
    if (!scene.body || scene.pickup.listener.empty())
        return 0;
    return listenerIndex(scene.body->body, scene.pickup.listener);  // -1 for a name a valid scene has not
}

std::vector<char> obstaclesOnBody(size_t obstacleCount, const std::optional<SceneBody>& body)
{
    std::vector<char> on(obstacleCount, body ? 0 : 1);
    if (body)
        for (const int i : body->obstacles)
            on[size_t(i)] = 1;
    return on;
}
}  // namespace jawari

namespace jawari::scene_reading
{
namespace
{
// A mode's "radiation": one weight (a body with one listener), or one per listener.
void readRadiation(ObjectReader& r, size_t listeners, BodyMode& m)
{
    if (!r.has("radiation"))
        return;
    if (listeners == 1 && !r.raw("radiation").is_array())
    {
        m.radiation[0] = r.number("radiation", 0.0);
        return;
    }
    const auto weights = r.numbers("radiation");
    if (weights.size() != listeners)
        throw SceneError(r.at("radiation"), "needs one weight per listener (" + std::to_string(listeners) + "), got "
                                                + std::to_string(weights.size()));
    std::copy(weights.begin(), weights.end(), m.radiation.begin());
}

BodyMode readBodyMode(const json& value, const std::string& path, size_t listeners)
{
    ObjectReader r(value, path);
    BodyMode m;
    for (const char* key : {"frequency", "mass"})
        if (!r.has(key))
            throw SceneError(r.at(key), "is required");
    m.frequencyHz = r.positive("frequency", 0.0);
    m.sigma = r.nonNegative("damping", 0.0);
    m.massKg = r.positive("mass", 0.0);
    readRadiation(r, listeners, m);
    r.rejectUnknown();
    return m;
}

std::vector<BodyMode> readBodyModes(const json& modes, const std::string& path, size_t listeners)
{
    if (!modes.is_array() || modes.empty())
        throw SceneError(path, "must be a non-empty array of modes, got " + typeName(modes));
    std::vector<BodyMode> out;
    for (size_t k = 0; k < modes.size(); ++k)
        out.push_back(readBodyMode(modes[k], path + "[" + std::to_string(k) + "]", listeners));
    return out;
}

// A listed body's "listeners": 1 to kMostListeners names ("centre" alone without them).
std::vector<std::string> readListeners(ObjectReader& r)
{
    if (!r.has("listeners"))
        return {"centre"};
    const json& names = r.raw("listeners");
    if (!names.is_array() || names.empty() || names.size() > size_t(kMostListeners))
        throw SceneError(r.at("listeners"), "must be an array of 1 to " + std::to_string(kMostListeners) + " names, got "
                                                + (names.is_array() ? std::to_string(names.size()) : typeName(names)));
    std::vector<std::string> out;
    for (size_t l = 0; l < names.size(); ++l)
    {
        const std::string here = r.at("listeners") + "[" + std::to_string(l) + "]";
        if (!names[l].is_string() || names[l].get<std::string>().empty())
            throw SceneError(here, "must be a name, got " + typeName(names[l]));
        if (std::find(out.begin(), out.end(), names[l].get<std::string>()) != out.end())
            throw SceneError(here, "names a listener twice ('" + names[l].get<std::string>() + "')");
        out.push_back(names[l].get<std::string>());
    }
    return out;
}

// Another string on the body, read as a scene of its own ("string", "obstacles", "excitation"; at rest
// without an excitation), its errors named under `path`.
BodyString readBodyString(const json& value, const std::string& path)
{
    ObjectReader r(value, path);
    json sub = {{"format", "jawari-scene/1"}};
    for (const char* key : {"string", "obstacles", "excitation"})
        if (r.has(key))
            sub[key] = r.raw(key);
    r.rejectUnknown();
    try
    {
        const Scene scene = parseScene(sub.dump());
        BodyString s{scene.string, scene.obstacles, scene.excitation};
        if (!value.contains("excitation"))
            s.excitation.amplitude = 0.0;
        if (s.excitation.force)
            throw SceneError("excitation.type", "a string on the body starts from its shape (\"pluck\")");
        return s;
    }
    catch (const SceneError& e)
    {
        const std::string what = e.what();
        throw SceneError(path + "." + e.path(), what.substr(std::min(what.size(), e.path().size() + 2)));
    }
}

// The sympathetic strings (SympatheticStrings.h): "count" of them, tuned from "sa" (Hz) to a "scale"
// (a thaat, or Sa-Pa) in pure intervals, each at rest on its bridge's spring, and with "jawari" on
// the curved top beyond it too.
std::vector<BodyString> readSympatheticStrings(const json& value, const std::string& path)
{
    ObjectReader r(value, path);
    const auto count = r.integer("count");
    if (!count || *count < 1 || *count > kMaxSympatheticStrings)
        throw SceneError(r.at("count"), "must be a whole number from 1 to " + std::to_string(kMaxSympatheticStrings));
    if (!r.has("sa"))
        throw SceneError(r.at("sa"), "is required (Sa's frequency, Hz)");
    const double sa = r.positive("sa", 0.0);
    if (sa < 20.0 || sa > 1000.0)
        throw SceneError(r.at("sa"), "must be between 20 and 1000 Hz (got " + show(sa) + ")");
    const std::vector<const char*> names(std::begin(kSympatheticScaleNames), std::end(kSympatheticScaleNames));
    const auto scaleName = r.string("scale", "Kafi", names);
    const bool jawari = r.boolean("jawari", false);
    r.rejectUnknown();
    const auto scale = static_cast<SympatheticScale>(
        std::find_if(names.begin(), names.end(), [&](const char* n) { return scaleName == n; }) - names.begin());
    std::vector<BodyString> strings;
    for (int k = 0; k < *count; ++k)
    {
        const double pitch = sympatheticPitch(k, scale, SympatheticIntonation::just, pitchOfFrequency(sa, 440.0), 0,
                                              equalTemperament());
        BodyString s;
        s.string = sympatheticStringAt(frequencyOfPitch(pitch, 440.0));
        s.obstacles = {sympatheticBridge(s.string.lengthMetres)};
        if (jawari)
            s.obstacles.push_back(sympatheticJawari(s.string.lengthMetres));
        s.excitation.amplitude = 0.0;
        strings.push_back(s);
    }
    return strings;
}

std::vector<int> readBodyObstacles(ObjectReader& r, const Scene& scene)
{
    std::vector<int> indices;
    if (!r.has("obstacles"))
    {
        for (size_t i = 0; i < scene.obstacles.size(); ++i)
            indices.push_back(int(i));
        return indices;
    }
    const auto numbers = r.numbers("obstacles");
    const double count = double(scene.obstacles.size());
    for (size_t i = 0; i < numbers.size(); ++i)
    {
        const double v = numbers[i];
        const std::string here = r.at("obstacles") + "[" + std::to_string(i) + "]";
        if (v != std::floor(v) || v < 0.0)
            throw SceneError(here, "must be an obstacle's index (a whole number >= 0), got " + show(v));
        if (v >= count)  // checked as a double: no conversion of a number beyond int's range
            throw SceneError(here, "no obstacle " + show(v) + " (the scene has " + show(count) + ")");
        indices.push_back(int(v));
    }
    return indices;
}

// The body's modes checked against their ranges (ModalBody.h), each error at the mode's field.
void checkBodyModes(const ModalBody& body)
{
    try
    {
        validateBody(body);
    }
    catch (const BodyRangeError& e)
    {
        throw SceneError("body.modes[" + std::to_string(e.mode) + "]." + e.field, e.requirement);
    }
    catch (const std::invalid_argument& e)
    {
        throw SceneError("body.listeners", e.what());
    }
}

// Every mode's damping scaled (0: a lossless body, for the energy balance), up to critical damping.
void scaleBodyDamping(ObjectReader& r, ModalBody& body)
{
    const double scale = r.nonNegative("damping_scale", 1.0), largest = largestDampingScale(body);
    if (scale > largest)
        throw SceneError(r.at("damping_scale"), "must be within [0, " + show(largest)
                                                    + "] for this body: beyond it its most damped mode is damped "
                                                      "past critical (got " + show(scale) + ")");
    for (auto& mode : body.modes)
        mode.sigma *= scale;
}

// The body's coupling within [0, kBodyStrongestCoupling], else a SceneError at `path`.
void checkCoupling(const std::string& path, double coupling)
{
    if (!(coupling >= 0.0 && coupling <= kBodyStrongestCoupling))
        throw SceneError(path, "must be within [0, " + show(kBodyStrongestCoupling)
                                   + "]: it makes each mode coupling^2 lighter at the bridge (got " + show(coupling)
                                   + ")");
}
}  // namespace

SceneBody readBody(const json& value, const Scene& scene)
{
    ObjectReader r(value, "body");
    SceneBody body;
    const bool named = r.has("model"), listed = r.has("modes");
    if (named == listed)
        throw SceneError("body", "needs either \"model\" (a factory body) or \"modes\" (its modes listed), not both");
    if (named && r.has("listeners"))
        throw SceneError(r.at("listeners"), "go with \"modes\": a factory body has its own");
    if (named)
    {
        std::vector<const char*> names = factoryBodyNames();
        body.body = *factoryBody(r.string("model", "", names));
    }
    else
    {
        body.body.listeners = readListeners(r);
        body.body.modes = readBodyModes(r.raw("modes"), r.at("modes"), body.body.listeners.size());
    }
    checkBodyModes(body.body);
    scaleBodyDamping(r, body.body);
    body.obstacles = readBodyObstacles(r, scene);
    body.coupling = r.number("coupling", body.coupling);
    checkCoupling(r.at("coupling"), body.coupling);
    if (r.has("strings"))
    {
        const json& strings = r.raw("strings");
        if (!strings.is_array())
            throw SceneError(r.at("strings"), "must be an array of strings, got " + typeName(strings));
        for (size_t i = 0; i < strings.size(); ++i)
            body.strings.push_back(readBodyString(strings[i], r.at("strings") + "[" + std::to_string(i) + "]"));
    }
    if (r.has("sympathetic_strings"))
        for (auto& s : readSympatheticStrings(r.raw("sympathetic_strings"), r.at("sympathetic_strings")))
            body.strings.push_back(std::move(s));
    r.rejectUnknown();
    return body;
}

void validateSceneBody(const Scene& scene)
{
    if (scene.pickup.quantity == PickupQuantity::bridgeForce && !scene.simulation.reference)
        throw SceneError("pickup.quantity", "\"bridge_force\" is read by the reference only (\"method\": \"reference\")");
    if (!scene.pickup.listener.empty() && scene.pickup.quantity != PickupQuantity::pressure)
        throw SceneError("pickup.listener", "is where the \"pressure\" pickup hears the body; this pickup reads the string");
    if (!scene.body)
    {
        if (scene.pickup.quantity == PickupQuantity::pressure)
            throw SceneError("pickup.quantity", "\"pressure\" is the body's radiated sound: the scene has no \"body\"");
        return;
    }
    const auto& body = *scene.body;
    if (!scene.pickup.listener.empty() && listenerIndex(body.body, scene.pickup.listener) < 0)
    {
        std::string names;
        for (const auto& name : body.body.listeners)
            names += (names.empty() ? "'" : ", '") + name + "'";
        throw SceneError("pickup.listener", "the body has no listener '" + scene.pickup.listener + "' (it has " + names + ")");
    }
    for (size_t i = 0; i < body.obstacles.size(); ++i)
        if (body.obstacles[i] < 0 || size_t(body.obstacles[i]) >= scene.obstacles.size())
            throw SceneError("body.obstacles[" + std::to_string(i) + "]",
                             "no obstacle " + std::to_string(body.obstacles[i]) + " (the scene has "
                                 + std::to_string(scene.obstacles.size()) + ")");
    if (!body.strings.empty() && !scene.simulation.reference)
    {
        // The voices stand on the instrument's shared body: every point of theirs on its bridge,
        // solved by the scheme (the SharedBody's rules).
        const auto onBody = obstaclesOnBody(scene.obstacles.size(), scene.body);
        if (std::find(onBody.begin(), onBody.end(), 0) != onBody.end())
            throw SceneError("body.obstacles", "with other strings on the body the \"realtime\" method stands every "
                                               "obstacle on it (list them all, or use \"method\": \"reference\")");
        if (scene.simulation.contact != ContactMethod::energyConserving)
            throw SceneError("simulation.method", "other strings on the body take the default method (\"realtime\") "
                                                  "or the reference");
    }
    checkBodyModes(body.body);
    checkCoupling("body.coupling", body.coupling);
}

}  // namespace jawari::scene_reading
