#include "scene.h"

namespace corebox {

int64_t Scene::particleCount() const {
    int64_t n = 0;
    for (const SpeciesDef& s : species) n += s.count;
    return n;
}

double Scene::mixing(size_t i, size_t j) const {
    if (interaction.mixing.empty()) return 1.0;
    return interaction.mixing.at(i).at(j);
}

StepParameters stepParametersOf(const Scene& scene) {
    return StepParameters{scene.integrator, scene.interaction, scene.box, scene.species};
}

const char* methodName(Method method) {
    switch (method) {
        case Method::Euler: return "euler";
        case Method::Rk2: return "rk2";
        case Method::Rk4: return "rk4";
        case Method::Dp5: return "dp5";
        case Method::Hairer10: return "hairer10";
        case Method::Verlet: return "verlet";
    }
    return "?";
}

bool parseMethod(const std::string& text, Method* method) {
    for (Method m : {Method::Euler, Method::Rk2, Method::Rk4, Method::Dp5, Method::Hairer10, Method::Verlet}) {
        if (text == methodName(m)) {
            *method = m;
            return true;
        }
    }
    return false;
}

const char* precisionName(Precision precision) { return precision == Precision::Fp32 ? "fp32" : "fp64"; }

const char* thermostatName(ThermostatKind kind) {
    switch (kind) {
        case ThermostatKind::Bussi: return "bussi";
        case ThermostatKind::Rescale: return "rescale";
        case ThermostatKind::None: return "none";
    }
    return "?";
}

const char* shiftName(CutoffShift shift) {
    switch (shift) {
        case CutoffShift::None: return "none";
        case CutoffShift::Energy: return "energy";
        case CutoffShift::Force: return "force";
    }
    return "?";
}

}  // namespace corebox
