// Reductions on the GPU (energies, health); only small results go to the host. Sums are made per block
// in a fixed tree and the block partials are added on the host in block order, so they do not
// depend on scheduling.
#include "gpu_common.cuh"
#include "gpu_launch.h"
#include "energy_terms.h"
#include "step_check.cuh"
#include "block_sums.cuh"

namespace corebox::gpu {
namespace {

__global__ void blockSumsKernel(const double* values, int64_t n, double* partials, int blocks, const char* mask, int maskedRows) {
    blockSum(BlockSumArgs{values, n, partials, blocks, mask, maskedRows}, int(blockIdx.x), int(blockIdx.y));
}

template <class Real>
__global__ void energyRowsKernel(EnergyArgs<Real> a) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    const int64_t n = a.p.n;
    if (i >= n) return;
    const int s = a.p.species[i];
    const double m = double(a.table.mass[s]);
    const Vec3<double> v = vec3Cast<double>(a.p.v[i]);
    const Vec3<double> x = vec3Cast<double>(a.p.x[i]);
    const int species = a.table.count;
    for (int k = 0; k < species; ++k) a.rows[size_t(k) * size_t(n) + size_t(i)] = k == s ? kineticEnergyOf(m, v) : 0.0;
    const double pair = a.pairEnergy ? 0.5 * a.pairEnergy[i] : 0.0;  // each pair counted from both sides
    a.rows[size_t(species) * size_t(n) + size_t(i)] = pair + gravityPotentialOf(m, vec3Cast<double>(a.table.field[s]), x);
    a.rows[size_t(species + 1) * size_t(n) + size_t(i)] = m * v.x;
    a.rows[size_t(species + 2) * size_t(n) + size_t(i)] = m * v.y;
    a.rows[size_t(species + 3) * size_t(n) + size_t(i)] = m * v.z;
}

template <class Real>
__global__ void kineticRowKernel(ParticleArrays<Real> p, SpeciesTable<Real> table, double* row) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= p.n) return;
    row[i] = kineticEnergyOf(double(table.mass[p.species[i]]), vec3Cast<double>(p.v[i]));
}

template <class Real>
__global__ void healthKernel(HealthArgs<Real> a) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i < a.p.n) countIfUnhealthy(a, i);
}

}  // namespace

int blockSumBlocks(int64_t n) { return int((n + int64_t(kReduceBlock) * kItemsPerThread - 1) / (int64_t(kReduceBlock) * kItemsPerThread)); }

int launchBlockSums(const double* values, int rows, int64_t n, double* partials, cudaStream_t stream, const char* mask, int maskedRows) {
    const int blocks = std::max(blockSumBlocks(n), 1);
    blockSumsKernel<<<dim3(unsigned(blocks), unsigned(rows)), kReduceBlock, 0, stream>>>(values, n, partials, blocks, mask, maskedRows);
    checkLaunch("block sums kernel");
    return blocks;
}

template <class Real>
void launchEnergyRows(const EnergyArgs<Real>& a, cudaStream_t stream) {
    energyRowsKernel<Real><<<blocksFor(a.p.n), kBlock, 0, stream>>>(a);
    checkLaunch("energy rows kernel");
}

template <class Real>
void launchKineticRow(const ParticleArrays<Real>& p, SpeciesTable<Real> table, double* row, cudaStream_t stream) {
    kineticRowKernel<Real><<<blocksFor(p.n), kBlock, 0, stream>>>(p, table, row);
    checkLaunch("kinetic row kernel");
}

template <class Real>
void launchHealth(const HealthArgs<Real>& a, cudaStream_t stream) {
    healthKernel<Real><<<blocksFor(a.p.n), kBlock, 0, stream>>>(a);
    checkLaunch("health kernel");
}

#define COREBOX_INSTANTIATE(Real)                                                                      \
    template void launchEnergyRows<Real>(const EnergyArgs<Real>&, cudaStream_t);                       \
    template void launchKineticRow<Real>(const ParticleArrays<Real>&, SpeciesTable<Real>, double*, cudaStream_t); \
    template void launchHealth<Real>(const HealthArgs<Real>&, cudaStream_t);
COREBOX_INSTANTIATE(float)
COREBOX_INSTANTIATE(double)
#undef COREBOX_INSTANTIATE

}  // namespace corebox::gpu
