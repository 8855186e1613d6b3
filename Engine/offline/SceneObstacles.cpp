// A scene's obstacles: points, profiles, parabolas and threads (docs/scenes.md, "obstacles").
#include "offline/SceneReader.h"

#include <cmath>

namespace jawari::scene_reading
{
namespace
{
ContactLaw readContactLaw(ObjectReader& r)
{
    ContactLaw law;
    law.stiffness = r.positive("stiffness", law.stiffness);
    law.exponent = r.number("exponent", law.exponent);
    if (!(law.exponent >= 1.0 && law.exponent <= 10.0))
        throw SceneError(r.at("exponent"), "must be between 1 and 10 (got " + show(law.exponent) + ")");
    return law;
}

// The thread's model and its law: "spring_damper" (the default: width, and stiffness N/m and
// damping kg/s in all, by DAFx-16's rule from the width unless given) or "contact" (a contact law).
Thread readThreadModel(ObjectReader& r)
{
    Thread thread;
    const auto model = r.string("model", "spring_damper", {"spring_damper", "contact"});
    if (model == "contact")
    {
        thread.model = ThreadModel::contact;
        thread.law = readContactLaw(r);
        return thread;
    }
    thread.model = ThreadModel::springDamper;
    if (r.has("exponent"))
        throw SceneError(r.at("exponent"), "has no meaning for a spring_damper thread (it is linear); "
                                           "\"model\": \"contact\" takes a contact law");
    thread.width = r.positive("width", thread.width);
    thread.stiffness = r.positive("stiffness", threadStiffnessForWidth(thread.width));
    thread.damping = r.nonNegative("damping", threadDampingForStiffness(thread.stiffness));
    return thread;
}

// A distributed obstacle's contact spacing (m), 0 (the default grid) when not given.
double readSpacing(ObjectReader& r, double L)
{
    if (!r.has("spacing"))
        return 0.0;
    const double spacing = r.positive("spacing", 0.0);
    if (!(spacing <= 0.5 * L && spacing >= L * 1e-6))
        throw SceneError(r.at("spacing"), "must be between L/1e6 and L/2 (" + show(L * 1e-6) + " to " + show(0.5 * L)
                                              + " m), got " + show(spacing));
    return spacing;
}

// A thread standing alone at `position`, its top at `height` (DAFx-16's, between the string's end
// and its bridge).
Obstacle readFreeThread(ObjectReader& r, double L)
{
    Thread thread = readThreadModel(r);
    const double position = r.number("position", 0.0);
    requireOnString(r.at("position"), position, L);
    const double height = r.number("height", 0.0);
    if (thread.model == ThreadModel::contact)
        thread.diameter = r.positive("diameter", thread.diameter);
    const double spacing = readSpacing(r, L);
    r.rejectUnknown();
    return threadObstacle(thread, position, height, spacing);
}

// A thread across an earlier bridge (obstacles[bridge]), which it moves so that the string rests
// on the thread (layThread). One thread per bridge.
Obstacle readThread(const json& j, const std::string& path, std::vector<Obstacle>& before,
                    std::vector<bool>& threaded, double L)
{
    ObjectReader r(j, path);
    r.string("type", "thread", {"thread"});
    if (r.has("position") && !r.has("bridge"))
        return readFreeThread(r, L);
    const auto index = r.integer("bridge");
    if (!index || *index < 0 || *index >= static_cast<long long>(before.size())
        || !before[size_t(*index)].isDistributed() || before[size_t(*index)].type == ObstacleType::band)
        throw SceneError(r.at("bridge"), "must be the index of a bridge (a parabola or a profile) earlier in obstacles");
    if (threaded[size_t(*index)])
        throw SceneError(r.at("bridge"), "already has a thread");
    Obstacle& bridge = before[size_t(*index)];
    Thread thread = readThreadModel(r);
    thread.offset = r.nonNegative("offset", thread.offset);
    thread.diameter = r.positive("diameter", thread.diameter);
    if (!threadFitsBridge(bridge, thread.offset))
        throw SceneError(r.at("offset"), "puts the thread off its bridge, which is "
                                             + show(bridge.supportEnd() - bridge.supportBegin()) + " m long (got "
                                             + show(thread.offset) + " m)");
    r.rejectUnknown();
    threaded[size_t(*index)] = true;
    return layThread(bridge, thread);
}

Obstacle readObstacle(const json& j, const std::string& path, double L)
{
    ObjectReader r(j, path);
    Obstacle ob;
    const auto type = r.string("type", "point", {"point", "profile", "parabola", "thread"});
    ob.law = readContactLaw(r);
    if (type == "point")
    {
        ob.type = ObstacleType::point;
        ob.position = r.number("position", ob.position);
        requireOnString(r.at("position"), ob.position, L);
        ob.height = r.number("height", ob.height);
        ob.width = r.positive("width", ob.width);
    }
    else if (type == "parabola")
    {
        ob.type = ObstacleType::parabola;
        ob.position = r.number("position", 0.003);
        ob.height = r.number("height", 0.0);
        ob.width = r.positive("width", 0.006);
        ob.curvature = r.nonNegative("curvature", 1.0);
        if (!(ob.supportBegin() >= 0.0 && ob.supportEnd() <= L))
            throw SceneError(r.at("width"), "the parabola [position - width/2, position + width/2] = ["
                                                + show(ob.supportBegin()) + ", " + show(ob.supportEnd())
                                                + "] m must lie on the string [0, " + show(L) + "]");
    }
    else
    {
        ob.type = ObstacleType::profile;
        if (!r.has("x"))
            throw SceneError(r.at("x"), "is required for a profile");
        if (!r.has("height"))
            throw SceneError(r.at("height"), "is required for a profile (an array of heights)");
        ob.profileX = r.numbers("x");
        ob.profileHeight = r.numbers("height");
        if (ob.profileX.size() < 2)
            throw SceneError(r.at("x"), "needs at least 2 points");
        if (ob.profileX.size() != ob.profileHeight.size())
            throw SceneError(r.at("height"), "must have as many entries as x (" + std::to_string(ob.profileX.size())
                                                 + "), got " + std::to_string(ob.profileHeight.size()));
        for (size_t i = 0; i < ob.profileX.size(); ++i)
        {
            const std::string here = r.at("x") + "[" + std::to_string(i) + "]";
            if (!(ob.profileX[i] >= 0.0 && ob.profileX[i] <= L))
                throw SceneError(here,
                                 "must lie on the string [0, " + show(L) + "] m (got " + show(ob.profileX[i]) + ")");
            if (i > 0 && !(ob.profileX[i] > ob.profileX[i - 1]))
                throw SceneError(here, "must be greater than the previous x (x must increase strictly)");
        }
    }
    if (ob.isDistributed())
        ob.spacing = readSpacing(r, L);
    r.rejectUnknown();
    return ob;
}

}  // namespace

void requireOnString(const std::string& path, double x, double L)
{
    if (!(x > 0.0 && x < L))
        throw SceneError(path, "must lie on the string, strictly between 0 and length " + show(L) + " m (got " + show(x)
                                   + ")");
}

void readObstacles(const json& obs, Scene& scene)
{
    if (!obs.is_array())
        throw SceneError("obstacles", "must be an array, got " + typeName(obs));
    std::vector<bool> threaded;
    for (size_t i = 0; i < obs.size(); ++i)
    {
        const std::string path = "obstacles[" + std::to_string(i) + "]";
        const bool thread = obs[i].is_object() && obs[i].contains("type") && obs[i]["type"] == "thread";
        scene.obstacles.push_back(thread ? readThread(obs[i], path, scene.obstacles, threaded, scene.string.lengthMetres)
                                         : readObstacle(obs[i], path, scene.string.lengthMetres));
        threaded.push_back(false);
    }
}

}  // namespace jawari::scene_reading
