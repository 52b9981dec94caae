#include "backend_factory.h"

#include <algorithm>

#include "cpu_backend.h"
#include "errors.h"
#if COREBOX_WITH_CUDA
#include "cuda_backend.h"
#endif

namespace corebox {

bool cudaAvailable() {
#if COREBOX_WITH_CUDA
    return cudaDeviceCount() > 0;
#else
    return false;
#endif
}

BackendChoice backendChoiceFor(const Scene& scene, BackendChoice choice) {
    choice.precision = scene.integrator.precision;
    choice.gpus = scene.devices.gpus;
    choice.exchange = scene.devices.exchange;
    choice.particleCount = scene.particleCount();
    return choice;
}

std::unique_ptr<Backend> makeBackend(const BackendChoice& choice) {
    if (choice.name != "cpu" && choice.name != "cuda" && choice.name != "auto") {
        throw InputError("--backend: unknown backend '" + choice.name + "' (expected cpu, cuda or auto)");
    }
    const bool cuda = choice.name == "cuda" || (choice.name == "auto" && cudaAvailable());
    if (!cuda) return makeCpuBackend(CpuBackendOptions{choice.precision, choice.threads});
#if COREBOX_WITH_CUDA
    CudaBackendOptions options;
    options.precision = choice.precision;
    options.device = choice.device;
    options.gpus = choice.gpus > 0 ? choice.gpus : gpusFor(choice.particleCount, std::max(cudaDeviceCount() - choice.device, 1));
    options.exchange = choice.exchange;
    options.pairsOnce = choice.pairsOnce;
    return makeCudaBackend(options);
#else
    throw DeviceError("--backend cuda: this build of corebox has no CUDA backend (built without nvcc); use --backend cpu");
#endif
}

}  // namespace corebox
