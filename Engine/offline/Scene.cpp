#include "offline/Scene.h"

#include "offline/SceneReader.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

namespace jawari
{
using namespace scene_reading;
namespace
{
// string.damping: the law and its constants; a constant given for a law that does not use it is an error.
void readDamping(const json& j, DampingParameters& dp)
{
    ObjectReader d(j, "string.damping");
    const auto law = d.string("law", "valette", {"valette", "none", "constant", "wavenumber"});
    dp.law = law == "none"         ? DampingLaw::none
             : law == "constant"   ? DampingLaw::constant
             : law == "wavenumber" ? DampingLaw::wavenumber
                                   : DampingLaw::valette;
    dp.etaAir = d.nonNegative("eta_air", dp.etaAir);
    dp.rhoAir = d.nonNegative("rho_air", dp.rhoAir);
    dp.deltaVe = d.nonNegative("delta_ve", dp.deltaVe);
    dp.qTeInv = d.nonNegative("q_te_inv", dp.qTeInv);
    if (d.has("sigma") && dp.law != DampingLaw::constant)
        throw SceneError(d.at("sigma"), "is only used with law 'constant'");
    dp.sigma = d.nonNegative("sigma", dp.sigma);
    for (const char* key : {"sigma0", "sigma1", "sigma3"})
        if (d.has(key) && dp.law != DampingLaw::wavenumber)
            throw SceneError(d.at(key), "is only used with law 'wavenumber'");
    dp.sigma0 = d.nonNegative("sigma0", dp.sigma0);
    dp.sigma1 = d.nonNegative("sigma1", dp.sigma1);
    dp.sigma3 = d.nonNegative("sigma3", dp.sigma3);
    d.rejectUnknown();
}

void readString(const json& j, Scene& scene)
{
    ObjectReader r(j, "string");
    auto& s = scene.string;
    s.lengthMetres = r.positive("length", s.lengthMetres);
    s.tensionNewtons = r.positive("tension", s.tensionNewtons);
    s.linearDensity = r.positive("linear_density", s.linearDensity);
    s.diameterMetres = r.nonNegative("diameter", s.diameterMetres);
    s.inharmonicity = r.nonNegative("inharmonicity", s.inharmonicity);
    if (r.has("damping"))
        readDamping(r.raw("damping"), s.damping);
    if (r.has("modes"))
    {
        const json& modes = r.raw("modes");
        if (!modes.is_array())
            throw SceneError("string.modes", "must be an array, got " + typeName(modes));
        std::set<long long> numbers;
        for (size_t i = 0; i < modes.size(); ++i)
        {
            const std::string path = "string.modes[" + std::to_string(i) + "]";
            ObjectReader m(modes[i], path);
            ModeOverride o;
            const auto n = m.integer("n");
            if (!n)
                throw SceneError(m.at("n"), "is required (the mode number, from 1)");
            if (*n < 1 || *n > kMaxModes)
                throw SceneError(m.at("n"), "must be between 1 and " + std::to_string(kMaxModes) + " (got "
                                                + std::to_string(*n) + ")");
            if (!numbers.insert(*n).second)
                throw SceneError(m.at("n"), "mode " + std::to_string(*n) + " is given twice");
            o.number = static_cast<int>(*n);
            if (m.has("frequency"))
                o.frequencyHz = m.positive("frequency", 0.0);
            if (m.has("sigma"))
                o.sigma = m.nonNegative("sigma", 0.0);
            if (!o.frequencyHz && !o.sigma)
                throw SceneError(path, "needs a frequency or a sigma to override");
            m.rejectUnknown();
            s.modeOverrides.push_back(o);
        }
    }
    r.rejectUnknown();
}

// The horizontal polarisation's detuning and damping against the vertical's, and the spring that
// couples the two (Polarisations.h).
SecondPolarisation readSecondPolarisation(const json& j)
{
    ObjectReader r(j, "second_polarisation");
    SecondPolarisation second;
    second.detuning = r.number("detuning", second.detuning);
    if (!(second.detuning > -1.0 && second.detuning < 1.0))
        throw SceneError(r.at("detuning"), "must lie between -1 and 1 (got " + show(second.detuning) + ")");
    second.dampingScale = r.nonNegative("damping_scale", second.dampingScale);
    if (r.has("coupling"))
    {
        ObjectReader c(r.raw("coupling"), r.at("coupling"));
        second.coupling.position = c.positive("position", 0.0);
        second.coupling.angle = c.number("angle", 0.0);
        second.coupling.stiffness = c.nonNegative("stiffness", 0.0);
        c.rejectUnknown();
    }
    r.rejectUnknown();
    return second;
}

}  // namespace

const char* methodName(const Simulation& simulation)
{
    return simulation.reference ? "reference" : contactMethodName(simulation.contact).sceneName;
}

bool setMethodByName(Simulation& simulation, const std::string& name)
{
    if (name == "reference")
    {
        simulation.reference = true;
        simulation.contact = ContactMethod::energyConserving;
        return true;
    }
    const auto contact = contactMethodFromSceneName(name);
    if (!contact)
        return false;
    simulation.reference = false;
    simulation.contact = *contact;
    return true;
}

const char* quantityName(PickupQuantity q)
{
    switch (q)
    {
        case PickupQuantity::displacement: return "displacement";
        case PickupQuantity::velocity: return "velocity";
        case PickupQuantity::force: return "force";
        case PickupQuantity::pressure: return "pressure";
        case PickupQuantity::bridgeForce: return "bridge_force";
    }
    return "displacement";
}

const char* quantityUnit(PickupQuantity q)
{
    switch (q)
    {
        case PickupQuantity::displacement: return "m";
        case PickupQuantity::velocity: return "m/s";
        case PickupQuantity::force: return "N";
        case PickupQuantity::pressure: return "Pa";
        case PickupQuantity::bridgeForce: return "N";
    }
    return "m";
}

namespace
{
// The pluck or the force: on the string, and a force only where it is rendered.
void validateExcitation(const Scene& scene)
{
    const double L = scene.string.lengthMetres;
    requireOnString("excitation.position", scene.excitation.position, L);
    if (const auto& force = scene.excitation.force)
    {
        if (force->position - 0.5 * force->width < 0.0 || force->position + 0.5 * force->width > L)
            throw SceneError("excitation.width", "spreads the force [position - width/2, position + width/2] = ["
                                                     + show(force->position - 0.5 * force->width) + ", "
                                                     + show(force->position + 0.5 * force->width)
                                                     + "] m off the string [0, " + show(L) + "]");
        if (!scene.simulation.reference)
            throw SceneError("excitation.type", "\"force\" is rendered by the reference only (\"method\": \"reference\")");
        if (scene.secondPolarisation)
            throw SceneError("excitation.type", "\"force\" pushes one polarisation: the scene has a second_polarisation");
    }
    if (scene.excitation.angle != 0.0 && !scene.secondPolarisation)
        throw SceneError("excitation.angle", "turns the pluck out of the vertical: it needs a second_polarisation");
}
}  // namespace

void validateScene(const Scene& scene)
{
    const auto& sim = scene.simulation;
    const double L = scene.string.lengthMetres;
    if (sim.rateHz && !(std::isfinite(*sim.rateHz) && *sim.rateHz > 0.0))
        throw SceneError("simulation.rate", "must be a finite rate > 0 Hz");
    if (sim.modes && (*sim.modes < 1 || *sim.modes > kMaxModes))
        throw SceneError("simulation.modes", "must be between 1 and " + std::to_string(kMaxModes) + " (got "
                                                 + std::to_string(*sim.modes) + ")");
    if (!(std::isfinite(sim.durationSeconds) && sim.durationSeconds > 0.0
          && sim.durationSeconds <= kMaxDurationSeconds))
        throw SceneError("simulation.duration", "must be > 0 and at most " + show(kMaxDurationSeconds) + " s (got "
                                                    + show(sim.durationSeconds) + ")");
    if (sim.outputRateHz < 8000 || sim.outputRateHz > 384000)
        throw SceneError("simulation.output_rate",
                         "must be between 8000 and 384000 Hz (got " + std::to_string(sim.outputRateHz) + ")");
    if (!sim.reference && sim.rateHz)
    {
        const double ratio = *sim.rateHz / sim.outputRateHz;
        if (std::abs(ratio - std::round(ratio)) > 1e-9 * ratio || std::round(ratio) < 1 || std::round(ratio) > 256)
            throw SceneError("simulation.rate",
                             "the voice's methods run at a whole multiple (1 to 256) of the output rate "
                                 + std::to_string(sim.outputRateHz) + " Hz (got " + show(*sim.rateHz) + " Hz)");
    }
    const double rate = sim.rateHz.value_or(!sim.reference ? sim.outputRateHz : kReferenceRateHz);
    if (rate < sim.outputRateHz)
        throw SceneError("simulation.rate", "the internal rate " + show(rate) + " Hz must be at least the output rate "
                                                + std::to_string(sim.outputRateHz) + " Hz");
    if (sim.extrapolateRate && !sim.reference)
        throw SceneError("simulation.extrapolate_rate", "applies to the reference only");
    if ((sim.extrapolateRate ? 2.0 : 1.0) * rate * sim.durationSeconds > 1e13)
        throw SceneError("simulation.duration", "rate x duration is more than 1e13 steps");
    if (const auto spacing = sim.contactSpacingMetres; spacing && !(*spacing >= L * 1e-6 && *spacing <= 0.5 * L))
        throw SceneError("simulation.contact_spacing", "must be between L/1e6 and L/2 (" + show(L * 1e-6) + " to "
                                                           + show(0.5 * L) + " m), got " + show(*spacing));
    const int modes = sim.modes.value_or(kReferenceModes);
    for (size_t i = 0; i < scene.string.modeOverrides.size(); ++i)
        if (scene.string.modeOverrides[i].number > modes)
            throw SceneError("string.modes[" + std::to_string(i) + "].n",
                             "mode " + std::to_string(scene.string.modeOverrides[i].number)
                                 + " is above the simulated modes (" + std::to_string(modes) + ")");
    validateExcitation(scene);
    if (const auto& second = scene.secondPolarisation)
    {
        if (second->coupling.stiffness > 0.0)
            requireOnString("second_polarisation.coupling.position", second->coupling.position, L);
    }
    requireOnString("pickup.position", scene.pickup.position, L);
    validateSceneBody(scene);
    for (size_t i = 0; i < scene.obstacles.size(); ++i)
    {
        const auto& ob = scene.obstacles[i];
        const std::string path = "obstacles[" + std::to_string(i) + "]";
        if (ob.type == ObstacleType::point)
            requireOnString(path + ".position", ob.position, L);
        else if (ob.supportEnd() > L || ob.supportBegin() < 0.0)
            throw SceneError(path, "lies partly off the string (length " + show(L) + " m)");
    }
}

namespace
{
void readExcitation(const json& value, Excitation& excitation)
{
    ObjectReader r(value, "excitation");
    const auto type = r.string("type", "pluck", {"pluck", "force"});
    excitation.position = r.number("position", excitation.position);
    if (type == "force")
    {
        ForcePluck force;
        force.position = excitation.position;
        force.amplitude = r.number("amplitude", force.amplitude);
        force.width = r.nonNegative("width", force.width);
        force.duration = r.positive("duration", force.duration);
        force.steepness = r.positive("steepness", force.steepness);
        force.start = r.nonNegative("start", force.start);
        excitation.force = force;
        excitation.amplitude = 0.0;  // from rest
    }
    else
        excitation.amplitude = r.number("amplitude", excitation.amplitude);
    excitation.angle = r.number("angle", excitation.angle);
    r.rejectUnknown();
}

void readPickup(const json& value, Pickup& pickup)
{
    ObjectReader r(value, "pickup");
    pickup.position = r.number("position", pickup.position);
    const auto q = r.string("quantity", "displacement", {"displacement", "velocity", "force", "pressure", "bridge_force"});
    pickup.quantity = q == "velocity"   ? PickupQuantity::velocity
                      : q == "force"    ? PickupQuantity::force
                      : q == "pressure" ? PickupQuantity::pressure
                      : q == "bridge_force" ? PickupQuantity::bridgeForce
                                        : PickupQuantity::displacement;
    if (r.has("listener"))
    {
        const json& name = r.raw("listener");
        if (!name.is_string() || name.get<std::string>().empty())
            throw SceneError(r.at("listener"), "must be the name of one of the body's listeners, got " + typeName(name));
        pickup.listener = name.get<std::string>();
    }
    r.rejectUnknown();
}

void readSimulation(const json& value, Simulation& simulation)
{
    ObjectReader r(value, "simulation");
    std::vector<const char*> methods{"reference"};
    for (const auto& m : kContactMethods)
        methods.push_back(m.sceneName);
    setMethodByName(simulation, r.string("method", "reference", methods));
    if (r.has("rate"))
        simulation.rateHz = r.positive("rate", 0.0);
    if (const auto m = r.integer("modes"))
    {
        if (*m < 1 || *m > kMaxModes)
            throw SceneError(r.at("modes"), "must be between 1 and " + std::to_string(kMaxModes) + " (got "
                                                + std::to_string(*m) + ")");
        simulation.modes = static_cast<int>(*m);
    }
    if (r.has("contact_spacing"))
        simulation.contactSpacingMetres = r.positive("contact_spacing", 0.0);
    simulation.extrapolateRate = r.boolean("extrapolate_rate", simulation.extrapolateRate);
    simulation.staticExactForcing =
        r.string("forcing", simulation.staticExactForcing ? "static-exact" : "paper", {"paper", "static-exact"})
        == "static-exact";
    simulation.durationSeconds = r.positive("duration", simulation.durationSeconds);
    simulation.residualCompliance = r.boolean("residual_compliance", simulation.residualCompliance);
    if (r.has("residual_compliance_loss"))
    {
        const double theta = r.number("residual_compliance_loss", 0.0);
        if (!(theta >= 0.0 && theta <= 1.0))
            throw SceneError(r.at("residual_compliance_loss"), "must be between 0 and 1 (got " + show(theta) + ")");
        simulation.residualComplianceLoss = theta;
    }
    simulation.staticPickup = r.boolean("static_pickup", simulation.staticPickup);
    if (const auto o = r.integer("output_rate"))
    {
        if (*o < 8000 || *o > 384000)
            throw SceneError(r.at("output_rate"), "must be between 8000 and 384000 Hz (got " + std::to_string(*o) + ")");
        simulation.outputRateHz = static_cast<int>(*o);
    }
    r.rejectUnknown();
}
}  // namespace

Scene parseScene(const std::string& jsonText)
{
    json root;
    try
    {
        root = json::parse(jsonText);
    }
    catch (const json::exception& e)  // parse errors, and numbers too large for a double
    {
        throw SceneError("(json)", std::string("malformed JSON: ") + e.what());
    }
    ObjectReader top(root, "");
    if (!top.has("format"))
        throw SceneError("format", "is required and must be \"jawari-scene/1\"");
    top.string("format", "", {"jawari-scene/1"});

    Scene scene;
    if (top.has("string"))
        readString(top.raw("string"), scene);
    if (top.has("obstacles"))
        readObstacles(top.raw("obstacles"), scene);
    if (top.has("excitation"))
        readExcitation(top.raw("excitation"), scene.excitation);
    if (top.has("pickup"))
        readPickup(top.raw("pickup"), scene.pickup);
    if (top.has("simulation"))
        readSimulation(top.raw("simulation"), scene.simulation);
    if (top.has("second_polarisation"))
        scene.secondPolarisation = readSecondPolarisation(top.raw("second_polarisation"));
    if (scene.secondPolarisation)
        scene.secondPolarisation->excitationAngle = scene.excitation.angle;
    if (top.has("body"))
        scene.body = readBody(top.raw("body"), scene);
    top.rejectUnknown();
    validateScene(scene);
    return scene;
}

Scene loadSceneFile(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    if (!in)
        throw SceneError("(file)", "cannot open scene file '" + path + "'");
    std::ostringstream text;
    text << in.rdbuf();
    return parseScene(text.str());
}

}  // namespace jawari
