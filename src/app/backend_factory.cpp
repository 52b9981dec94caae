#include "backend_factory.h"

#include "cpu_backend.h"
#include "errors.h"

namespace corebox {

std::unique_ptr<Backend> makeBackend(const BackendChoice& choice) {
    if (choice.name == "cpu" || choice.name == "auto") return makeCpuBackend(CpuBackendOptions{choice.precision, choice.threads});
    if (choice.name == "cuda") throw DeviceError("--backend cuda: this build of corebox has no CUDA backend yet; use --backend cpu");
    throw InputError("--backend: unknown backend '" + choice.name + "' (expected cpu, cuda or auto)");
}

}  // namespace corebox
