// Builds a backend by name for the command line and the window app: "cpu", "cuda", or "auto"
// (CUDA when this build has it and a GPU is present, else CPU).
#pragma once

#include <memory>
#include <string>

#include "backend.h"

namespace corebox {

struct BackendChoice {
    std::string name = "auto";
    Precision precision = Precision::Fp64;
    int threads = 0;  // CPU threads; 0: all
    int device = 0;   // first CUDA device ordinal
    int gpus = 0;     // CUDA devices used; 0: auto (the measured crossover for particleCount)
    Exchange exchange = Exchange::Auto;
    int64_t particleCount = 0;  // what gpus = auto decides on
    bool pairsOnce = true;      // CUDA all pairs: each pair once (Newton's third law) where it pays; false: every ordered pair
};

// True when this build has the CUDA backend and a GPU is present.
bool cudaAvailable();

// The choice for running `scene`: its precision, its [devices] (GPU count and exchange) and its
// particle count (what gpus = auto decides on), on the backend, threads and device of `choice`.
BackendChoice backendChoiceFor(const Scene& scene, BackendChoice choice);

// Throws InputError for an unknown name and DeviceError when the device cannot be used.
std::unique_ptr<Backend> makeBackend(const BackendChoice& choice);

}  // namespace corebox
