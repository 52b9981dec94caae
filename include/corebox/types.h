// Choices shared by the corebox library's public API and its internals: the floating-point precision
// of a simulation, which compute backend runs it, and how several GPUs share positions. The internal
// vocabulary (src/core/vocabulary.h) names them; the public API (world.h) takes them in its WorldDef.
#pragma once

namespace corebox {

// Precision of the state and every force pass: fp64 (double) or fp32 (float, about twice as fast on a
// GPU; state errors floor near 1e-6 of a length). Energies are always summed in double.
enum class Precision { Fp32, Fp64 };

// Cpu: every core of this machine (OpenMP). Cuda: NVIDIA GPUs. Auto: CUDA when this build has it and a
// GPU is present, else the CPU.
enum class BackendKind { Cpu, Cuda, Auto };

// How several GPUs share positions before each force pass (DESIGN.md sec. 4): synchronous peer copies
// (DT-S), asynchronous peer copies (DT-A), direct access (DA), or an NCCL all-gather; Auto: the fastest
// measured for the device count.
enum class Exchange { Auto, Dts, Dta, Da, Nccl };

}  // namespace corebox
