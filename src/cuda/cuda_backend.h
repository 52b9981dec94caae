// CUDA backend on one GPU: the device interface of src/core/backend.h with every model feature of
// the CPU reference, in fp32 or fp64. Kernels (kernels/*.cu) call the same __host__ __device__
// physics as the CPU backend. Particle rows are owned through a DevicePartition (one slice here).
// This library does not link GL: CUDA-GL interop lives in gl_buffer_interop.* (its own library),
// which hands writeInstances a mapped device pointer.
#pragma once

#include <memory>
#include <string>

#include "backend.h"

namespace corebox {

struct CudaBackendOptions {
    Precision precision = Precision::Fp64;
    int device = 0;  // the first GPU: it renders, resolves collisions and holds the whole state
    int gpus = 1;    // GPUs device, device + 1, ...: each owns a contiguous slice of the particles
    Exchange exchange = Exchange::Auto;  // how the slices share positions (Auto: fastestExchange)
    // All pairs: evaluate each pair once with Newton's third law where it pays, on one GPU or shared by
    // several with peer access (kernels/pairs_once_kernels.cu); false: every ordered pair (the
    // report's kernel, for comparison).
    bool pairsOnce = true;
    // One GPU: a Verlet step's launches fused and its screened collision stage decided on the device,
    // with one host wait a step (cuda_device.h, the one-wait step); any GPU count: each listing's
    // contact sweeps in one launch that checks its own residual (cuda_collisions.cpp: relaxListing),
    // and without pair forces the impact rounds queued in batches (runImpactRounds);
    // false: every operation on its own (the same bits, for comparison and tests).
    bool fusedSteps = true;
    // With fusedSteps, one GPU and Verlet on screened lists: the next step's kick-drift and force pass
    // queued behind a device-side gate before the host waits for this step's stage, into buffers of
    // their own (cuda_device.h: running ahead); false: after the wait (the same bits, for comparison).
    bool runAhead = true;
    // Tests only: the columns that the lists a step building ahead start from (0: the home lists'), so
    // that a few make them overflow and the step is done again (cuda_step.cpp: redoOverflowedPass).
    int aheadListColumns = 0;
    // The contact phase's sweeps: Gauss-Seidel in colours (kernels/contact_gauss_seidel.cu), as the
    // CPU relaxes contacts; false: accelerated Jacobi sweeps (contact_relaxation.h: relaxParticle), for
    // comparison and tests. A listing whose contacts need more than gpu::kMaxContactColours colours is
    // relaxed with Jacobi sweeps either way.
    bool gaussSeidelContacts = true;
    // Tests only: at most this many blocks for a listing's Gauss-Seidel sweeps in one launch (0: as many
    // as fit), so that a small listing's colours hold more rows than the launch has threads and its
    // threads take two rows at a time (contact_gauss_seidel.cu), as at 10^6 balls.
    int sweepBlocks = 0;
    // Tests only: the particle count from which the impact searches after a stage's first are narrowed
    // to the particles near the last round's active ones (cuda_collisions.cpp: narrowSearch); -1: the
    // default (kNarrowedSearchMin), 0: always, a huge count: never (the same bits, for comparison).
    int64_t narrowedSearchFrom = -1;
    // A round of fp32 impact searches that would be narrowed (narrowedSearchFrom) and walks a thread a
    // particle (more than 32,768 particles) is made by the last round's active particles alone, which
    // offer their inactive neighbours the pairs' events (cuda_collisions.cpp: searchRound); false:
    // narrowed searches (the same bits, for comparison and tests).
    bool scatteredSearch = true;
    // A scattered round (scatteredSearch) whose last round left at most this many active particles (and at
    // most one in gpu::kListedScatterShare) is searched from their list, a warp a particle; where every
    // particle searches the rounds (below narrowedSearchFrom, fp32, more than 32,768 particles), such a
    // round is scattered that way too (cuda_collisions.cpp: searchRound). -1: the default, 0: never (the
    // same bits, for comparison and tests).
    int64_t listedScatterMax = -1;
    // A stage's first impact round searches from the particles fast enough for an impact
    // (collision_resolution.h: startsActive), scattered where the later rounds are; false: every
    // particle searches (the same bits, for comparison and tests).
    bool moversFirst = true;
    // The impact rounds queued in batches (fusedSteps) skip a round's cell-list build where the rounds
    // since the last build moved no particle out of its cell (cuda_collisions.cpp: runImpactRounds);
    // false: every round builds (the same bits, for comparison and tests).
    bool skipUnmovedCellBuilds = true;
    // The batched impact rounds (fusedSteps) of more than 32,768 particles read candidate rows, a Verlet
    // list made when some particle has moved half its margin since the last (gpu_launch.h CandidateRows),
    // instead of walking cells built again each round; false: cells (the same bits, for comparison and
    // tests).
    bool impactCandidates = true;
    // Tests only: slots in a candidate row (0: gpu::kCandidateSlots); a particle with more candidates
    // walks the cells of the rows' build, so that a few make rows overflow.
    int candidateSlots = 0;
    // Tests only: the particle count from which the rounds read candidate rows (-1: more than 32,768;
    // never at 4,096 or fewer, whose cell builds do not gate themselves).
    int64_t candidateRowsFrom = -1;
    // Tests only: take every pair of GPUs to have no peer access (peer_exchange.h), so that corebox's
    // decisions for machines without it run where the GPUs have it: DA refused, no peer access enabled
    // by corebox, no pass shared across GPUs, auto never DA. The copies themselves are not forced through
    // host memory: peer access enabled earlier in the process stays, and NCCL picks its own transport.
    bool peerAccessDenied = false;
};

// Number of usable CUDA devices; 0 when there is no driver or no GPU (never throws).
int cudaDeviceCount();
// "NVIDIA H200 (driver 580.xx, CUDA runtime 13.0)" for logs and benchmark records.
std::string cudaDeviceDescription(int device);

// The GPU count `--gpus auto` picks for n particles out of `visible` GPUs: the measured crossover
// (docs/multi_gpu.md), one GPU where splitting costs more than it saves.
int gpusFor(int64_t n, int visible);
// What Exchange::Auto means for `gpus` GPUs, with or without peer access between every pair: the
// fastest method measured by `corebox bench table1`.
Exchange fastestExchange(int gpus, bool peerAccess);

// Throws DeviceError when the device cannot be used (a device missing, more GPUs asked for than
// exist, DA between GPUs without peer access), naming the devices found.
std::unique_ptr<Backend> makeCudaBackend(const CudaBackendOptions& options);

}  // namespace corebox
