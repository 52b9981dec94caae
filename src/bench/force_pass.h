// The force pass on its own, as both benchmarks time it: a backend holding a scene's initial state,
// and one all-pairs acceleration pass waited for (the device interface's computeAccelerations plus
// finish, so a GPU pass is timed to completion).
#pragma once

#include <cstdint>
#include <memory>

#include "backend_factory.h"
#include "device_model.h"
#include "initial_conditions.h"

namespace corebox {

inline std::unique_ptr<Backend> forcePassBackend(const BackendChoice& choice, const Scene& scene) {
    std::unique_ptr<Backend> backend = makeBackend(choice);
    backend->setModel(deviceModelOf(stepParametersOf(scene)));
    backend->setState(makeInitialState(scene));
    return backend;
}

// Returns the pair interactions evaluated: every ordered pair, N(N-1).
inline int64_t runForcePass(Backend& backend, int64_t n) {
    backend.computeAccelerations();
    backend.finish();
    return n * (n - 1);
}

}  // namespace corebox
