#include "scene_validation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "errors.h"
#include "memory_estimate.h"
#include "packing.h"

namespace corebox {

long SceneLocations::line(const std::string& key) const {
    const auto found = m_lines.find(key);
    return found == m_lines.end() ? 0 : found->second;
}

void SceneLocations::fail(const std::string& key, const std::string& message) const {
    throw InputError(locatedMessage(m_file, line(key), key, message));
}

namespace {

class SceneValidator {
public:
    explicit SceneValidator(const SceneLocations& where) : m_where(where) {}

    void validate(const Scene& scene) {
        checkSpecies(scene.species);
        checkBox(scene.box);
        checkInteraction(scene.interaction);
        checkIntegrator(scene.integrator);
        checkThermostat(scene.thermostat);
        check("init.temperature", finite(scene.init.temperature) && scene.init.temperature >= 0, "must be a finite number >= 0");
        checkScales(scene);
        if (const std::optional<PackingProblem> problem = packingProblem(scene)) m_where.fail(problem->key, problem->message);
    }

private:
    void check(const std::string& key, bool ok, const std::string& message) const {
        if (!ok) m_where.fail(key, message);
    }
    // Every comparison below fails for NaN; finite() keeps +inf from passing "> 0" and ">= 0".
    static bool finite(double v) { return std::isfinite(v); }
    void checkPositive(const std::string& key, double value) const { check(key, finite(value) && value > 0, "must be a finite number > 0"); }
    void checkNonNegative(const std::string& key, double value) const {
        check(key, finite(value) && value >= 0, "must be a finite number >= 0");
    }
    void checkUnitInterval(const std::string& key, double value) const { check(key, value >= 0 && value <= 1, "must be in [0, 1]"); }

    void checkSpecies(const std::vector<SpeciesDef>& species) const {
        check("species", !species.empty(), "at least one [[species]] is required");
        for (size_t i = 0; i < species.size(); ++i) {
            const SpeciesDef& s = species[i];
            const std::string path = "species[" + std::to_string(i) + "]";
            check(path + ".name", !s.name.empty(), "must not be empty");
            check(path + ".count", s.count >= 0, "must be >= 0");
            checkPositive(path + ".mass", s.mass);
            checkPositive(path + ".radius", s.radius);
            checkPositive(path + ".sigma", s.sigma);
            checkNonNegative(path + ".epsilon", s.epsilon);
            check(path + ".acceleration", std::all_of(s.acceleration.begin(), s.acceleration.end(), [](double g) { return finite(g); }),
                  "must be 3 finite numbers");
        }
        for (size_t i = 0; i < species.size(); ++i) {
            for (size_t j = 0; j < i; ++j) {
                check("species[" + std::to_string(i) + "].name", species[i].name != species[j].name,
                      "duplicate species name '" + species[i].name + "' (also species[" + std::to_string(j) + "])");
            }
        }
        int64_t total = 0;
        for (const SpeciesDef& s : species) {
            // Counts are >= 0 here; the sum must not wrap around int64.
            check("species", s.count <= std::numeric_limits<int64_t>::max() - total, "total particle count overflows a 64-bit integer");
            total += s.count;
        }
        check("species", total > 0, "total particle count is 0; give some species a count > 0");
    }

    void checkBox(const BoxDef& box) const {
        check("box.size", std::all_of(box.size.begin(), box.size.end(), [](double l) { return finite(l) && l > 0; }),
              "must be 3 finite positive numbers");
        checkUnitInterval("box.wall_restitution", box.wallRestitution);
    }

    void checkInteraction(const InteractionDef& in) const {
        for (size_t i = 0; i < in.mixing.size(); ++i) {
            for (size_t j = 0; j < in.mixing[i].size(); ++j) {
                const std::string key = "interaction.mixing[" + std::to_string(i) + "][" + std::to_string(j) + "]";
                checkNonNegative(key, in.mixing[i][j]);
                if (j < i) {
                    check(key, in.mixing[i][j] == in.mixing[j][i],
                          "must equal interaction.mixing[" + std::to_string(j) + "][" + std::to_string(i) +
                              "]: the mixing matrix is symmetric");
                }
            }
        }
        check("interaction.cutoff", finite(in.cutoff) && in.cutoff >= 0, "must be a finite number >= 0 (0: all pairs)");
        check("interaction.gravity", std::all_of(in.gravity.begin(), in.gravity.end(), [](double g) { return finite(g); }),
              "must be 3 finite numbers");
        checkUnitInterval("interaction.restitution", in.restitution);
        checkNonNegative("interaction.elastic_below_speed", in.elasticBelowSpeed);
        const int roundsLimit = InteractionDef::kMaxCollisionRoundsLimit;
        check("interaction.max_collision_rounds", in.maxCollisionRounds >= 1 && in.maxCollisionRounds <= roundsLimit,
              "must be >= 1 and <= " + std::to_string(roundsLimit));
        check("interaction.contact_sweeps", in.contactSweeps >= 0, "must be >= 0 (0: the backend's own cap)");
        check("interaction.contact_listings",
              in.contactListings >= 0 && in.contactListings <= InteractionDef::kMaxContactListings,
              "must be 0 to " + std::to_string(InteractionDef::kMaxContactListings) + " (0: corebox's own cap, " +
                  std::to_string(InteractionDef::kMaxContactListings) + ")");
        // A zero skin would rebuild the lists whenever anything moves, i.e. every step.
        check("interaction.skin", finite(in.skin) && in.skin > 0,
              "must be a finite number > 0 (neighbour lists reach r_c + skin and are rebuilt when a particle has moved skin / 2; 0.3 is typical)");
        check("interaction.forces", in.forces != ForceModel::None, "must be auto, all_pairs or neighbour_list");
        check("interaction.forces", in.forces != ForceModel::NeighbourList || in.cutoff > 0,
              "neighbour_list needs a cutoff > 0 (without one every pair interacts: use all_pairs or auto)");
    }

    void checkIntegrator(const IntegratorDef& integrator) const {
        checkPositive("integrator.dt", integrator.dt);
        check("integrator.adaptive", !integrator.adaptive || integrator.method == Method::Dp5,
              std::string("needs method = \"dp5\" (the only method with an error estimate), not \"") + methodName(integrator.method) +
                  "\"");
        checkPositive("integrator.tolerance", integrator.tolerance);
        check("integrator.adaptive", !(integrator.automatic && integrator.adaptive),
              "cannot be true with method = \"auto\" (the choice is among fixed-step methods)");
    }

    void checkThermostat(const ThermostatDef& thermostat) const {
        checkNonNegative("thermostat.temperature", thermostat.temperature);
        checkPositive("thermostat.tau", thermostat.tau);
    }

    // Values each finite and in range can still overflow once the step multiplies them: 1e300 is a
    // fine double, but 4 eps (sigma/r)^12 summed over pairs, m g L or N kT are not. The rule: every
    // energy, squared speed and acceleration the step forms from the scene's scales stays below
    // B = sqrt(largest number of the precision) -- 1e150 in fp64, 1e18 in fp32 -- so one more
    // product (a square, a sum over particles) is still finite; and every length, mass and time
    // stays above 1/B, so its reciprocal does too. A scene outside these bounds would only blow up
    // at step 0 and be reported as "dt too large", which it is not; rescaling the units fixes it.
    void checkScales(const Scene& scene) const {
        const bool fp32 = scene.integrator.precision == Precision::Fp32;
        const double bound = fp32 ? 1e18 : 1e150;
        const char* precision = fp32 ? "fp32" : "fp64";
        auto fail = [&](const std::string& key, const std::string& what, double value) {
            char text[320];
            std::snprintf(text, sizeof text, "%s is %.3g, beyond what %s can carry through a step (|value| < %.0e); rescale the units%s",
                          what.c_str(), value, precision, bound, fp32 ? " or use precision = \"fp64\"" : "");
            m_where.fail(key, text);
        };
        // Masses and lengths are inverted (1/m, 1/sigma, cells per length), so they have a floor;
        // energies are not, so a tiny epsilon or temperature is fine.
        auto inRange = [&](const std::string& key, const std::string& what, double value) {
            if (value > 0 && !(value >= 1.0 / bound && value <= bound)) fail(key, what, value);
        };
        auto below = [&](const std::string& key, const std::string& what, double value) {
            if (!(value <= bound)) fail(key, what, value);
        };
        double massMin = std::numeric_limits<double>::infinity(), massMax = 0, sigmaMin = massMin, epsMax = 0;
        for (size_t i = 0; i < scene.species.size(); ++i) {
            const SpeciesDef& s = scene.species[i];
            const std::string path = "species[" + std::to_string(i) + "]";
            inRange(path + ".mass", "the mass", s.mass);
            inRange(path + ".radius", "the radius", s.radius);
            inRange(path + ".sigma", "sigma", s.sigma);
            below(path + ".epsilon", "epsilon", s.epsilon);
            massMin = std::min(massMin, s.mass);
            massMax = std::max(massMax, s.mass);
            sigmaMin = std::min(sigmaMin, s.sigma);
            epsMax = std::max(epsMax, s.epsilon);
        }
        for (int a = 0; a < 3; ++a) inRange("box.size", "a box edge", scene.box.size[size_t(a)]);
        inRange("integrator.dt", "dt", scene.integrator.dt);
        const double lengthMax = std::max({scene.box.size[0], scene.box.size[1], scene.box.size[2]});
        const double n = double(std::max<int64_t>(scene.particleCount(), 1));
        // The largest field any species feels: the global gravity plus its own acceleration.
        double g = 0;
        for (const SpeciesDef& s : scene.species) {
            g = std::max(g, std::hypot(scene.interaction.gravity[0] + s.acceleration[0], scene.interaction.gravity[1] + s.acceleration[1],
                                       scene.interaction.gravity[2] + s.acceleration[2]));
        }
        if (!(g <= bound)) fail("interaction.gravity", "|g|", g);
        below("init.temperature", "kT", scene.init.temperature);
        below("thermostat.temperature", "kT", scene.thermostat.temperature);
        // Energies summed over the system: pair wells, thermal energy, the height of the box in a field.
        const struct {
            const char* key;
            const char* what;
            double value;
        } energies[] = {
            {"species", "N times 4 epsilon (the pair energy scale of the system)", n * 4 * epsMax},
            {"init.temperature", "N times kT (the thermal energy of the system)", n * 1.5 * scene.init.temperature},
            {"thermostat.temperature", "N times kT (the thermal energy of the system)", n * 1.5 * scene.thermostat.temperature},
            {"interaction.gravity", "N m |g| L (the potential energy across the box)", n * massMax * g * lengthMax},
        };
        for (const auto& e : energies) {
            if (!(e.value <= bound)) fail(e.key, e.what, e.value);
        }
        // Squared speeds and accelerations per particle.
        const double kT = std::max(scene.init.temperature, scene.thermostat.temperature);
        if (!(kT / massMin <= bound)) fail("init.temperature", "kT / m (the squared thermal speed)", kT / massMin);
        if (!(g * lengthMax <= bound)) fail("interaction.gravity", "|g| L (the squared speed of a fall across the box)", g * lengthMax);
        // The lattice placement counts its sites in int64 (packing.cpp): a box whose one edge is
        // astronomically longer than the others would overflow that count before any memory check.
        const double sites = latticeSiteCount(scene);
        if (!(sites <= 1e15)) {
            char text[320];
            std::snprintf(text, sizeof text,
                          "the lattice placement would need %.3g sites for %.0f particles in this box (one edge much longer than the "
                          "others); use placement = \"random\" or a box closer to a cube",
                          sites, n);
            m_where.fail("box.size", text);
        }
        const double pairAcceleration = 24 * epsMax / (sigmaMin * massMin);
        if (!(pairAcceleration <= bound)) {
            fail("species", "24 epsilon / (sigma m) (the pair acceleration at r = sigma)", pairAcceleration);
        }
    }

    const SceneLocations& m_where;
};

}  // namespace

void validateScene(const Scene& scene, const SceneLocations& where) { SceneValidator(where).validate(scene); }

}  // namespace corebox
