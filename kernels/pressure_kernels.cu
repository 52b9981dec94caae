// The pair-force virial of the pressure observables (src/core/pressure.h) on the GPU: one warp per
// particle strides over all partners (the all-pairs sum of the force pass, at observation time
// only), a warp sum in a fixed tree, and a per-particle row that the caller reduces in block order.
#include "gpu_common.cuh"
#include "gpu_launch.h"

namespace corebox::gpu {
namespace {

template <class Real>
__global__ void pairVirialRowKernel(ParticleArrays<Real> p, SpeciesTable<Real> table, double* row) {
    const int64_t warp = (int64_t(blockIdx.x) * blockDim.x + threadIdx.x) / 32;
    const int lane = threadIdx.x & 31;
    if (warp >= p.n) return;
    const int64_t i = warp;
    const Vec3<Real> xi = p.x[i];
    const PairCoefficients<Real>* pairs = table.pairs + p.species[i] * table.count;
    double w = 0;
    for (int64_t j = lane; j < p.n; j += 32) {
        const Real r2 = norm2(xi - p.x[j]);
        if (j == i || r2 == Real(0)) continue;
        w += double(pairForceOverR(pairs[p.species[j]], r2, static_cast<Real*>(nullptr))) * double(r2);
    }
    for (int offset = 16; offset > 0; offset /= 2) w += __shfl_down_sync(0xffffffffu, w, offset);
    if (lane == 0) row[i] = 0.5 * w;  // every pair is visited from both sides
}

}  // namespace

template <class Real>
void launchPairVirialRow(const ParticleArrays<Real>& p, SpeciesTable<Real> table, double* row, cudaStream_t stream) {
    if (p.n == 0) return;
    pairVirialRowKernel<Real><<<blocksFor(p.n * 32), kBlock, 0, stream>>>(p, table, row);
    checkLaunch("pair virial kernel");
}

template void launchPairVirialRow<float>(const ParticleArrays<float>&, SpeciesTable<float>, double*, cudaStream_t);
template void launchPairVirialRow<double>(const ParticleArrays<double>&, SpeciesTable<double>, double*, cudaStream_t);

}  // namespace corebox::gpu
