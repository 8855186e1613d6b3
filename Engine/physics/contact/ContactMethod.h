#pragma once
// How the contact force of a step is found (docs/design.md section 4, the methods charted), and
// the names each method goes by: in scene files and on the renderer's command line, and in the
// plugin. Every list of methods (the scene parser, the renderer, the plugin's parameter) reads
// this table.

#include <optional>
#include <string_view>

namespace jawari
{

enum class ContactMethod
{
    energyConserving,  // the paper's discrete gradient, solved by Newton (the default)
    quadratised,       // energy quadratisation (scalar auxiliary variable): one linear solve, no Newton
    penalty,           // explicit penalty force at u^n: cheap, unstable when K dt^2 is large
    quadraticSpline    // the discrete gradient of a quadratic-spline potential: closed form, no Newton
};

struct ContactMethodName
{
    ContactMethod method;
    const char* sceneName;   // "method" in a scene file, --method of jawari-render
    const char* playerName;  // the plugin's choice; nullptr: offline only
};

inline constexpr ContactMethodName kContactMethods[] = {
    {ContactMethod::energyConserving, "realtime", "energy-conserving"},
    {ContactMethod::quadratised, "quadratised", "quadratised"},
    {ContactMethod::penalty, "penalty", "penalty"},
    {ContactMethod::quadraticSpline, "spline", "quadratic spline"},
};

// The plugin offers the methods with a player's name, the first entries of the table.
constexpr int playerContactMethodCount()
{
    int n = 0;
    for (const auto& m : kContactMethods)
        n += m.playerName != nullptr ? 1 : 0;
    return n;
}

constexpr const ContactMethodName& contactMethodName(ContactMethod method)
{
    for (const auto& m : kContactMethods)
        if (m.method == method)
            return m;
    return kContactMethods[0];
}

constexpr std::optional<ContactMethod> contactMethodFromSceneName(std::string_view name)
{
    for (const auto& m : kContactMethods)
        if (name == m.sceneName)
            return m.method;
    return std::nullopt;
}

}  // namespace jawari
