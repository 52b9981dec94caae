#include "scene_validation.h"

#include <algorithm>

#include "errors.h"
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
        check("init.temperature", scene.init.temperature >= 0, "must be >= 0");
        if (const std::optional<PackingProblem> problem = packingProblem(scene)) m_where.fail(problem->key, problem->message);
    }

private:
    void check(const std::string& key, bool ok, const std::string& message) const {
        if (!ok) m_where.fail(key, message);
    }
    void checkUnitInterval(const std::string& key, double value) const { check(key, value >= 0 && value <= 1, "must be in [0, 1]"); }

    void checkSpecies(const std::vector<SpeciesDef>& species) const {
        check("species", !species.empty(), "at least one [[species]] is required");
        for (size_t i = 0; i < species.size(); ++i) {
            const SpeciesDef& s = species[i];
            const std::string path = "species[" + std::to_string(i) + "]";
            check(path + ".name", !s.name.empty(), "must not be empty");
            check(path + ".count", s.count >= 0, "must be >= 0");
            check(path + ".mass", s.mass > 0, "must be > 0");
            check(path + ".radius", s.radius > 0, "must be > 0");
            check(path + ".sigma", s.sigma > 0, "must be > 0");
            check(path + ".epsilon", s.epsilon >= 0, "must be >= 0");
        }
        for (size_t i = 0; i < species.size(); ++i) {
            for (size_t j = 0; j < i; ++j) {
                check("species[" + std::to_string(i) + "].name", species[i].name != species[j].name,
                      "duplicate species name '" + species[i].name + "' (also species[" + std::to_string(j) + "])");
            }
        }
        int64_t total = 0;
        for (const SpeciesDef& s : species) total += s.count;
        check("species", total > 0, "total particle count is 0; give some species a count > 0");
    }

    void checkBox(const BoxDef& box) const {
        check("box.size", std::all_of(box.size.begin(), box.size.end(), [](double l) { return l > 0; }), "must be 3 positive numbers");
        checkUnitInterval("box.wall_restitution", box.wallRestitution);
    }

    void checkInteraction(const InteractionDef& in) const {
        for (size_t i = 0; i < in.mixing.size(); ++i) {
            for (size_t j = 0; j < in.mixing[i].size(); ++j) {
                const std::string key = "interaction.mixing[" + std::to_string(i) + "][" + std::to_string(j) + "]";
                check(key, in.mixing[i][j] >= 0, "must be >= 0");
                if (j < i) {
                    check(key, in.mixing[i][j] == in.mixing[j][i],
                          "must equal interaction.mixing[" + std::to_string(j) + "][" + std::to_string(i) +
                              "]: the mixing matrix is symmetric");
                }
            }
        }
        check("interaction.cutoff", in.cutoff >= 0, "must be >= 0 (0: all pairs)");
        checkUnitInterval("interaction.restitution", in.restitution);
        check("interaction.elastic_below_speed", in.elasticBelowSpeed >= 0, "must be >= 0");
        check("interaction.max_collision_rounds", in.maxCollisionRounds >= 1, "must be >= 1");
    }

    void checkIntegrator(const IntegratorDef& integrator) const {
        check("integrator.dt", integrator.dt > 0, "must be > 0");
        check("integrator.adaptive", !integrator.adaptive || integrator.method == Method::Dp5,
              std::string("needs method = \"dp5\" (the only method with an error estimate), not \"") + methodName(integrator.method) +
                  "\"");
        check("integrator.tolerance", integrator.tolerance > 0, "must be > 0");
    }

    void checkThermostat(const ThermostatDef& thermostat) const {
        check("thermostat.temperature", thermostat.temperature >= 0, "must be >= 0");
        check("thermostat.tau", thermostat.tau > 0, "must be > 0");
    }

    const SceneLocations& m_where;
};

}  // namespace

void validateScene(const Scene& scene, const SceneLocations& where) { SceneValidator(where).validate(scene); }

}  // namespace corebox
