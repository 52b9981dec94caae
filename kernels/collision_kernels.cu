// A posteriori collision rounds on the GPU (DESIGN.md sec. 2) with the shared event and resolution
// functions of collision_resolution.h. Contacts are found through a uniform grid (cells at least
// the largest contact distance wide) rebuilt by counting sort every round; the order of particles
// inside a cell does not matter because every choice is made by the deterministic event order.
#include <cub/device/device_scan.cuh>

#include "gpu_common.cuh"
#include "gpu_launch.h"

namespace corebox::gpu {
namespace {

template <class Real>
__device__ int cellCoord(Real p, Real inverseCell, int dim) {
    const int c = int(floor(double(p) * double(inverseCell)));
    return c < 0 ? 0 : (c >= dim ? dim - 1 : c);
}

template <class Real>
__global__ void assignCellsKernel(GridArgs<Real> g) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= g.n) return;
    const Vec3<Real> x = g.x[i];
    const int cx = cellCoord(x.x, g.inverseCell[0], g.dims[0]);
    const int cy = cellCoord(x.y, g.inverseCell[1], g.dims[1]);
    const int cz = cellCoord(x.z, g.inverseCell[2], g.dims[2]);
    const int cell = (cz * g.dims[1] + cy) * g.dims[0] + cx;
    g.cellOf[i] = cell;
    atomicAdd(&g.cellFill[cell], 1);
}

template <class Real>
__global__ void scatterKernel(GridArgs<Real> g) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= g.n) return;
    const int slot = atomicAdd(&g.cellFill[g.cellOf[i]], 1);
    g.sorted[slot] = int32_t(i);
}

template <class Real, class Fn>
__device__ void forNeighbours(const GridArgs<Real>& g, Vec3<Real> x, Fn&& fn) {
    const int c[3] = {cellCoord(x.x, g.inverseCell[0], g.dims[0]), cellCoord(x.y, g.inverseCell[1], g.dims[1]),
                      cellCoord(x.z, g.inverseCell[2], g.dims[2])};
    for (int dz = -1; dz <= 1; ++dz) {
        const int z = c[2] + dz;
        if (z < 0 || z >= g.dims[2]) continue;
        for (int dy = -1; dy <= 1; ++dy) {
            const int y = c[1] + dy;
            if (y < 0 || y >= g.dims[1]) continue;
            for (int dx = -1; dx <= 1; ++dx) {
                const int xx = c[0] + dx;
                if (xx < 0 || xx >= g.dims[0]) continue;
                const int cell = (z * g.dims[1] + y) * g.dims[0] + xx;
                for (int k = g.cellStart[cell]; k < g.cellStart[cell + 1]; ++k) fn(int64_t(g.sorted[k]));
            }
        }
    }
}

template <class Real>
__global__ void findEventsKernel(CollisionArgs<Real> a) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= a.p.n) return;
    const bool checkAll = a.active[i] != 0;
    const Vec3<Real> xi = a.p.x[i], vi = a.p.v[i];
    const Real ri = a.table.radius[a.p.species[i]];
    CollisionEvent best = noEvent();
    forNeighbours(a.grid, xi, [&](int64_t j) {
        if (j == i || !(checkAll || a.active[j])) return;
        considerPair(xi, vi, ri, a.p.x[j], a.p.v[j], a.table.radius[a.p.species[j]], j, best);
    });
    considerWalls(xi, vi, ri, a.box, best);
    a.events[i] = best;
    if (!isValid(best)) return;
    atomicAdd(&a.counters[1], 1u);  // a count: the same whatever the order
    if (!a.hasContactAcceleration[i]) {
        const unsigned slot = atomicAdd(&a.counters[0], 1u);  // list order varies, each entry's work does not
        a.needList[slot] = int32_t(i);
    }
}

// One warp per listed particle: lanes stride over all partners, then a warp sum.
template <class Real>
__global__ void contactAccelerationKernel(CollisionArgs<Real> a, ForceArgs<Real> f, int count) {
    const int warp = int((int64_t(blockIdx.x) * blockDim.x + threadIdx.x) / 32);
    const int lane = threadIdx.x & 31;
    if (warp >= count) return;
    const int64_t i = a.needList[warp];
    const Vec3<Real> xi = a.p.x[i];
    const int si = a.p.species[i];
    Vec3<Real> force{0, 0, 0};
    if (f.anyPairForce) {
        const PairCoefficients<Real>* row = f.table.pairs + si * f.table.count;
        for (int64_t j = lane; j < a.p.n; j += 32) {
            const Vec3<Real> r = xi - a.p.x[j];
            const Real r2 = norm2(r);
            if (r2 == Real(0)) continue;
            force += pairForceOverR(row[a.p.species[j]], r2, static_cast<Real*>(nullptr)) * r;
        }
        for (int offset = 16; offset > 0; offset /= 2) {
            force.x += __shfl_down_sync(0xffffffffu, force.x, offset);
            force.y += __shfl_down_sync(0xffffffffu, force.y, offset);
            force.z += __shfl_down_sync(0xffffffffu, force.z, offset);
        }
    }
    if (lane == 0) {
        a.contactAcceleration[i] = f.table.invMass[si] * force + f.gravity;
        a.hasContactAcceleration[i] = 1;
    }
}

template <class Real>
__global__ void resolveKernel(CollisionArgs<Real> a) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= a.p.n) return;
    const CollisionEvent e = a.events[i];
    if (!isValid(e)) return;
    const int si = a.p.species[i];
    int kind = kNoCollision;
    double loss = 0;
    if (e.partner >= 0) {
        const int64_t j = e.partner;
        if (j > i && a.events[j].partner == i) {
            const int sj = a.p.species[j];
            Vec3<Real> xi = a.p.x[i], vi = a.p.v[i], xj = a.p.x[j], vj = a.p.v[j];
            kind = resolvePairEvent(xi, vi, a.contactAcceleration[i], a.table.mass[si], xj, vj, a.contactAcceleration[j],
                                    a.table.mass[sj], a.table.radius[si] + a.table.radius[sj], e.key, a.restitution,
                                    a.elasticBelow, &loss);
            a.p.x[i] = xi;
            a.p.v[i] = vi;
            a.p.x[j] = xj;
            a.p.v[j] = vj;
        }
    } else {
        const int code = int(-1 - e.partner), axis = code / 2;
        Vec3<Real> x = a.p.x[i], v = a.p.v[i];
        kind = resolveWallEvent(x[axis], v[axis], a.contactAcceleration[i][axis], a.table.mass[si], a.table.radius[si],
                                a.box[axis], code % 2, e.key, a.wallRestitution, a.elasticBelow, &loss);
        a.p.x[i] = x;
        a.p.v[i] = v;
    }
    if (kind != kNoCollision) {
        a.loss[i] += loss;
        atomicAdd(&a.kindCounts[kind - 1], 1ull);
    }
}

// After resolution: a particle stays active when it had an event (resolved now or still pending).
template <class Real>
__global__ void updateActiveKernel(CollisionArgs<Real> a) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= a.p.n) return;
    a.active[i] = isValid(a.events[i]);
}

}  // namespace

size_t gridScanScratchBytes(int cells) {
    size_t bytes = 0;
    cub::DeviceScan::ExclusiveSum(nullptr, bytes, static_cast<int32_t*>(nullptr), static_cast<int32_t*>(nullptr), cells + 1);
    return bytes;
}

template <class Real>
void launchBuildGrid(const GridArgs<Real>& g, cudaStream_t stream) {
    const int cells = g.dims[0] * g.dims[1] * g.dims[2];
    cudaMemsetAsync(g.cellFill, 0, size_t(cells + 1) * sizeof(int32_t), stream);
    assignCellsKernel<Real><<<blocksFor(g.n), kBlock, 0, stream>>>(g);
    checkLaunch("cell assignment kernel");
    size_t bytes = g.scanScratchBytes;
    cub::DeviceScan::ExclusiveSum(g.scanScratch, bytes, g.cellFill, g.cellStart, cells + 1, stream);
    cudaMemcpyAsync(g.cellFill, g.cellStart, size_t(cells) * sizeof(int32_t), cudaMemcpyDeviceToDevice, stream);
    scatterKernel<Real><<<blocksFor(g.n), kBlock, 0, stream>>>(g);
    checkLaunch("cell scatter kernel");
}

template <class Real>
void launchFindEvents(const CollisionArgs<Real>& a, cudaStream_t stream) {
    findEventsKernel<Real><<<blocksFor(a.p.n), kBlock, 0, stream>>>(a);
    checkLaunch("event kernel");
}

template <class Real>
void launchContactAccelerations(const CollisionArgs<Real>& a, const ForceArgs<Real>& f, int count, cudaStream_t stream) {
    if (count <= 0) return;
    contactAccelerationKernel<Real><<<blocksFor(int64_t(count) * 32), kBlock, 0, stream>>>(a, f, count);
    checkLaunch("contact acceleration kernel");
}

template <class Real>
void launchResolve(const CollisionArgs<Real>& a, cudaStream_t stream) {
    resolveKernel<Real><<<blocksFor(a.p.n), kBlock, 0, stream>>>(a);
    checkLaunch("resolve kernel");
}

template <class Real>
void launchUpdateActive(const CollisionArgs<Real>& a, cudaStream_t stream) {
    updateActiveKernel<Real><<<blocksFor(a.p.n), kBlock, 0, stream>>>(a);
    checkLaunch("active kernel");
}

#define COREBOX_INSTANTIATE(Real)                                                                                  \
    template void launchBuildGrid<Real>(const GridArgs<Real>&, cudaStream_t);                                      \
    template void launchFindEvents<Real>(const CollisionArgs<Real>&, cudaStream_t);                                \
    template void launchContactAccelerations<Real>(const CollisionArgs<Real>&, const ForceArgs<Real>&, int, cudaStream_t); \
    template void launchResolve<Real>(const CollisionArgs<Real>&, cudaStream_t);                                  \
    template void launchUpdateActive<Real>(const CollisionArgs<Real>&, cudaStream_t);
COREBOX_INSTANTIATE(float)
COREBOX_INSTANTIATE(double)
#undef COREBOX_INSTANTIATE

}  // namespace corebox::gpu
