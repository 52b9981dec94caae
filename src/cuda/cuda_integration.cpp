// The CUDA backend's integration operations: force passes (positions shared between GPUs first,
// timed by stream events on the home GPU), Runge-Kutta stages and Verlet's kick and drift, each a
// launch of kernels/force_kernels.cu or kernels/integrate_kernels.cu per GPU over its slice.
#include <algorithm>
#include <cmath>

#include "cuda_device.h"

namespace corebox {

template <class Real>
gpu::ForceArgs<Real> CudaDevice<Real>::forceArgs(int k, const Vec3<Real>* x, Vec3<Real>* out) {
    Replica<Real>& r = *m_replicas[size_t(k)];
    const DeviceSlice& s = slice(k);
    gpu::ForceArgs<Real> f{};  // no list, no screen, no kick: set where used
    f.x = x;
    f.species = r.species.data();
    f.n = m_n;
    f.begin = s.begin;
    f.end = s.end;
    f.table = tableOf(r);
    f.anyPairForce = m_model.anyPairForce;
    f.hasCutoff = m_model.hasCutoff;
    f.acceleration = out;
    f.scratch = r.forceScratch.data();
    f.scratchBytes = r.forceScratch.size();
    f.pairsOnce = m_pairsOnce;
    return f;
}

template <class Real>
gpu::ForceArgs<Real> CudaDevice<Real>::homeForceArgs(const Vec3<Real>* x, Vec3<Real>* out) {
    gpu::ForceArgs<Real> f = forceArgs(0, x, out);
    f.begin = 0;
    f.end = m_n;
    f.table = table();
    f.scratch = m_homeForceScratch.data();
    f.scratchBytes = m_homeForceScratch.size();
    f.pairsOnce = false;
    return f;
}

template <class Real>
void CudaDevice<Real>::markForceTime() {
    if (m_timingWindow < 0) return;  // outside a step (energies, benchmarks): nothing to attribute the time to
    PhaseEvents& set = phaseEvents();
    if (set.forceEvents + 1 > set.forces.size()) {
        cudaEvent_t e;
        cudaCheck(cudaEventCreate(&e), "cudaEventCreate");
        set.forces.push_back(e);
        set.forceWindow.push_back(0);
    }
    set.forceWindow[set.forceEvents] = (unsigned char)m_timingWindow;
    cudaCheck(cudaEventRecord(set.forces[set.forceEvents], stream()), "event");
    ++set.forceEvents;
}

template <class Real>
void CudaDevice<Real>::launchTimedForces(const gpu::ForceArgs<Real>& args) {
    markForceTime();
    gpu::launchForces(args, stream());
    markForceTime();
}

template <class Real>
bool CudaDevice<Real>::forcePass(int stage, bool kick, double kickH) {
    // What the last step check forecast of the lists at these positions (cuda_step.cpp): the force pass
    // right after the kickDrift it was made for needs no displacement check.
    using Displacement = typename DeviceNeighbourList<Real>::Displacement;
    Displacement known = Displacement::Unknown;
    if (stage < 0 && m_forecast.stage == 2 && home().list.buildId() == m_forecast.buildId)
        known = m_forecast.beyondHalfSkin ? Displacement::BeyondHalfSkin : Displacement::WithinHalfSkin;
    m_forecast.stage = 0;
    kick = kick && stage < 0 && useLists();
    scatterFromHome();
    // The positions: X for A = a(X), the stage positions Xs otherwise; every GPU's copy.
    auto positions = [&](Replica<Real>& r) { return stage < 0 ? r.x.data() : r.xStage.data(); };
    // Lists hold every pair closer than the cutoff: the screen sees every pair within reach only if
    // the largest reach is below it.
    const bool screen = stage < 0 && screensAtX();
    std::vector<void*> buffers;
    for (auto& r : m_replicas) buffers.push_back(positions(*r));
    m_exchange->share(buffers, sizeof(Vec3<Real>));
    std::vector<gpu::ForceArgs<Real>> args(m_replicas.size());
    onEachGpu([&](int k, Replica<Real>& r) {
        Vec3<Real>* out = stage < 0 ? r.acceleration.data() : r.kv.data() + size_t(stage) * size_t(slice(k).size());
        gpu::ForceArgs<Real> f = forceArgs(k, positions(r), out);
        if (useLists()) {
            r.list.update(positions(r), m_n, slice(k).begin, slice(k).end, m_box, m_model.cutoff, m_model.skin, slice(k).stream,
                          gpuCount() == 1 ? known : Displacement::Unknown);
            r.list.fill(f);
        }
        if (kick) {
            f.kickV = r.v.data() + slice(k).begin;
            f.kickH = Real(kickH);
        }
        if (screen) {  // this pass also screens the collision stage at X (screenStage), into fresh step words
            if (!m_wordsFresh) gpu::launchResetStepWords(stepWords(), stream());
            m_wordsFresh = true;
            f.screen = stepWords()->screen;
            f.box = m_box;
            f.contactGap = Real(m_screenGap);
        }
        if (m_exchange->method() == Exchange::Da && gpuCount() > 1) {
            f.peers.count = gpuCount();
            f.peers.chunk = m_partition.chunk();
            for (int j = 0; j < gpuCount(); ++j) f.peers.x[j] = positions(*m_replicas[size_t(j)]);
        }
        args[size_t(k)] = f;
    });
    if (!useLists() && m_pairsOnceAcross && gpu::pairsOnceAppliesAcross(args.front(), gpuCount())) {
        // Each GPU its share of the tile pairs and its row sums; once all are done, each GPU its
        // slice's rows from every GPU's sums (pairs_once_kernels.cu). The peers' reads of a GPU's
        // row sums end before its next pass writes them: that pass opens with share()
        // (PeerExchange::readsDone says how each method orders it), and nothing else writes them.
        m_allPairsEvaluations += gpu::allPairsEvaluations<Real>(m_n, true, gpuCount());
        markForceTime();
        onEachGpu([&](int k, Replica<Real>&) { gpu::launchPairsOnceShare(args[size_t(k)], k, gpuCount(), slice(k).stream); });
        m_exchange->barrier();
        gpu::PairsOnceSums<Real> sums{};
        sums.count = gpuCount();
        for (int g = 0; g < gpuCount(); ++g) sums.rows[g] = gpu::pairsOnceRowSums(args[size_t(g)], gpuCount());
        onEachGpu([&](int k, Replica<Real>&) { gpu::launchPairsOnceCombine(args[size_t(k)], sums, slice(k).stream); });
        markForceTime();
    } else {
        onEachGpu([&](int k, Replica<Real>&) {
            const gpu::ForceArgs<Real>& f = args[size_t(k)];
            if (!useLists() && m_model.anyPairForce) {
                if (gpu::pairsOnceApplies(f)) m_allPairsEvaluations += gpu::allPairsEvaluations<Real>(m_n, true);
                else m_allPairsEvaluations += std::max<int64_t>(f.end - f.begin, 0) * (m_n - 1);  // the slice's rows against all others
            }
            if (k == 0) launchTimedForces(f);
            else gpu::launchForces(f, slice(k).stream);
        });
    }
    m_exchange->readsDone();
    m_homeCurrent = gpuCount() == 1;
    ++m_fullPasses;
    m_accelerationMatchesX = stage < 0;
    m_screenPending = screen;
    m_listAtX = stage < 0 && gpuCount() == 1 && useLists();
    if (stage < 0) m_accelerationIncremental = false;
    return kick;
}

// The collision stage moved a few particles (against the copy taken at beginCollisions), on one GPU.
// Lists: only the rows whose sums read a moved particle are summed again, by the same kernel in the
// same order, so A is bit for bit what a full pass gives (a full pass when the moves pushed someone
// past half the skin). All pairs: each moved particle sums again over everyone, and everyone else
// exchanges the old pair force of each moved partner for the new one (O(N M), as the CPU does; a full
// pass when more than a quarter moved). Several GPUs: a full pass at the next step.
template <class Real>
bool CudaDevice<Real>::refreshAccelerations() {
    if (!m_refreshable) return false;
    m_refreshable = false;
    ++m_refreshes;
    if (!m_model.anyPairForce) {
        m_accelerationMatchesX = true;  // uniform fields alone do not depend on X
        return true;
    }
    Replica<Real>& r = home();
    if (m_speculatedRefresh && m_wallsAtOnce && m_wallsOnlyMoved) {  // done within the screen's wait (cuda_step.cpp)
        m_speculatedRefresh = false;
        m_accelerationMatchesX = true;
        return true;
    }
    beforeStateChange();
    if (!useLists()) return refreshAllPairs();
    if (m_wallsAtOnce && !m_wallsOnlyMoved) {  // no copy of X tells who the relaxation moved
        forcePass(-1);
        return true;
    }
    if (!m_listAtX && r.list.update(r.x.data(), m_n, 0, m_n, m_box, m_model.cutoff, m_model.skin, stream())) {
        forcePass(-1);
        return true;
    }
    gpu::ForceArgs<Real> f = forceArgs(0, r.x.data(), r.acceleration.data());
    r.list.fill(f);
    // Who moved: the particles the walls-at-once stage flagged, else those whose position changed.
    f.rowMask = m_wallsOnlyMoved ? r.list.touchFlagged(m_hasContactAcceleration.data(), stream())
                                 : r.list.touchMoved(r.x.data(), m_xBeforeCollisions.data(), stream());
    gpu::launchForces(f, stream());
    m_accelerationMatchesX = true;
    return true;
}

template <class Real>
bool CudaDevice<Real>::refreshAllPairs() {
    Replica<Real>& r = home();
    const size_t n = size_t(m_n);
    m_movedFlags.resize(n);
    m_movedList.resize(n);
    m_movedCount.resize(1);
    gpu::launchMarkMoved(r.x.data(), m_xBeforeCollisions.data(), m_n, m_movedFlags.data(), m_movedList.data(), m_movedCount.data(), stream());
    const int64_t moved = int64_t(readBack(m_movedCount));
    if (moved == 0) {
        m_accelerationMatchesX = true;
        return true;
    }
    if (4 * moved > m_n) {
        forcePass(-1);
        return true;
    }
    // Ascending: each row's exchange sums the moved partners in one fixed order.
    std::vector<int32_t> ascending(static_cast<size_t>(moved));
    cudaCheck(cudaMemcpyAsync(ascending.data(), m_movedList.data(), size_t(moved) * sizeof(int32_t), cudaMemcpyDeviceToHost, stream()), "moved list");
    sync();
    std::sort(ascending.begin(), ascending.end());
    cudaCheck(cudaMemcpyAsync(m_movedList.data(), ascending.data(), size_t(moved) * sizeof(int32_t), cudaMemcpyHostToDevice, stream()), "moved list");
    sync();  // the host vector goes out of scope
    gpu::ForceArgs<Real> exchange = homeForceArgs(r.x.data(), r.acceleration.data());
    gpu::launchExchangeMovedPairForces(exchange, m_xBeforeCollisions.data(), m_movedFlags.data(), m_movedList.data(), moved, stream());
    gpu::ForceArgs<Real> rows = homeForceArgs(r.x.data(), r.acceleration.data());
    rows.begin = 0;
    rows.end = moved;
    rows.rowIndex = m_movedList.data();
    const size_t scratch = gpu::forceScratchBytes<Real>(moved, m_n);
    if (m_homeForceScratch.size() < scratch) m_homeForceScratch.resize(scratch);
    rows.scratch = m_homeForceScratch.data();
    rows.scratchBytes = m_homeForceScratch.size();
    gpu::launchForces(rows, stream());
    m_accelerationMatchesX = true;
    m_accelerationIncremental = true;
    return true;
}

template <class Real>
std::vector<Vec3<double>> CudaDevice<Real>::cachedAccelerations() const {
    if (!m_accelerationIncremental || gpuCount() != 1) return {};
    sync();
    std::vector<Vec3<Real>> a(static_cast<size_t>(m_n));
    if (m_n > 0) {
        cudaCheck(cudaMemcpyAsync(a.data(), home().acceleration.data(), size_t(m_n) * sizeof(Vec3<Real>), cudaMemcpyDeviceToHost, stream()),
                  "accelerations");
        sync();
    }
    std::vector<Vec3<double>> out(a.size());
    for (size_t i = 0; i < a.size(); ++i) out[i] = vec3Cast<double>(a[i]);
    return out;
}

// The values were this precision's before the round trip through double: restored exactly.
template <class Real>
void CudaDevice<Real>::restoreAccelerations(const std::vector<Vec3<double>>& a) {
    if (gpuCount() != 1 || int64_t(a.size()) != m_n) return;  // never written for several GPUs
    beforeStateChange();
    sync();
    std::vector<Vec3<Real>> values(a.size());
    for (size_t i = 0; i < a.size(); ++i) values[i] = vec3Cast<Real>(a[i]);
    if (m_n > 0) {
        cudaCheck(cudaMemcpyAsync(home().acceleration.data(), values.data(), values.size() * sizeof(Vec3<Real>), cudaMemcpyHostToDevice, stream()),
                  "accelerations");
        sync();
    }
    m_accelerationMatchesX = true;
    m_accelerationIncremental = true;
}

template <class Real>
bool CudaDevice<Real>::useLists() const {
    return m_model.forces == ForceModel::NeighbourList && m_model.anyPairForce && m_model.cutoff > 0 &&
           (gpuCount() == 1 || m_exchange->method() != Exchange::Da);
}

template <class Real>
ForceCounters CudaDevice<Real>::forceCounters() const {
    ForceCounters c;
    c.fullPasses = m_fullPasses;
    c.refreshes = m_refreshes;
    c.allPairsEvaluations = m_allPairsEvaluations;
    c.stepsRunAhead = m_stepsRunAhead;
    for (const auto& r : m_replicas) c.listBuilds += r->list.builds();
    c.listBuilds += m_aheadList.builds();  // the builds of steps that ran ahead (their lists swap with the home GPU's)
    return c;
}

template <class Real>
void CudaDevice<Real>::computeAccelerations() {
    beforeStateChange(true);
    forcePass(-1);
}

template <class Real>
void CudaDevice<Real>::kick(double h) {
    beforeStateChange();
    scatterFromHome();
    onEachGpu([&](int k, Replica<Real>& r) {
        const DeviceSlice& s = slice(k);
        gpu::launchVerletKick(r.v.data() + s.begin, r.acceleration.data(), s.size(), Real(h), s.stream);
    });
    m_homeCurrent = gpuCount() == 1;
}

template <class Real>
void CudaDevice<Real>::drift(double dt) {
    beforeStateChange();
    scatterFromHome();
    onEachGpu([&](int k, Replica<Real>& r) {
        const DeviceSlice& s = slice(k);
        gpu::launchVerletDrift(r.x.data() + s.begin, r.v.data() + s.begin, s.size(), Real(dt), s.stream);
    });
    m_accelerationMatchesX = false;
    m_listAtX = false;
    m_homeCurrent = gpuCount() == 1;
}

template <class Real>
gpu::StageArgs<Real> stageArgsOf(Replica<Real>& r, const DeviceSlice& s, int stage, int count, double dt) {
    return gpu::StageArgs<Real>{r.x.data() + s.begin,      r.v.data() + s.begin,      r.kx.data(), r.kv.data(), r.xStage.data() + s.begin,
                                r.vStage.data() + s.begin, s.size(),                  stage,       count,       Real(dt),
                                r.tableau.data()};
}

template <class Real>
void CudaDevice<Real>::rkStage(int stage, double dt) {
    scatterFromHome();
    onEachGpu([&](int k, Replica<Real>& r) {
        const DeviceSlice& s = slice(k);
        const size_t rows = size_t(m_tableau.stages) * size_t(s.size());
        r.kx.resize(rows);
        r.kv.resize(rows);
        gpu::launchStage(stageArgsOf(r, s, stage, stage, dt), s.stream);
    });
    m_homeCurrent = gpuCount() == 1;
}

template <class Real>
void CudaDevice<Real>::stageForces(int stage) {
    beforeStateChange();
    forcePass(stage);
}

template <class Real>
void CudaDevice<Real>::rkSolution(int stages, double dt) {
    onEachGpu([&](int k, Replica<Real>& r) { gpu::launchStage(stageArgsOf(r, slice(k), -1, stages, dt), slice(k).stream); });
    m_homeCurrent = gpuCount() == 1;
}

template <class Real>
double CudaDevice<Real>::rkErrorNorm(double dt, double tolerance) {
    // Per-GPU block partials, added on the host in GPU and block order: the same sum for any timing.
    std::vector<int> blocks(static_cast<size_t>(gpuCount()), 0);
    onEachGpu([&](int k, Replica<Real>& r) {
        const DeviceSlice& s = slice(k);
        if (s.size() == 0) return;
        r.errorRows.resize(size_t(s.size()));
        gpu::launchErrorNorm(stageArgsOf(r, s, -1, m_tableau.stages, dt), tolerance, r.errorRows.data(), s.stream);
        const int b = std::max(gpu::blockSumBlocks(s.size()), 1);
        blocks[size_t(k)] = b;
        r.errorPartials.resize(size_t(b));
        gpu::launchBlockSums(r.errorRows.data(), 1, s.size(), r.errorPartials.data(), s.stream);
        cudaCheck(cudaMemcpyAsync(r.hostErrorPartials.resize(size_t(b)), r.errorPartials.data(), size_t(b) * sizeof(double),
                                  cudaMemcpyDeviceToHost, s.stream),
                  "error norm");
    });
    sync();
    double sum = 0;
    for (int k = 0; k < gpuCount(); ++k)
        for (int b = 0; b < blocks[size_t(k)]; ++b) sum += m_replicas[size_t(k)]->hostErrorPartials.data()[b];
    return std::sqrt(sum / double(6 * std::max<int64_t>(m_n, 1)));
}

template <class Real>
void CudaDevice<Real>::acceptStage() {
    beforeStateChange();
    for (auto& r : m_replicas) {
        std::swap(r->x, r->xStage);
        std::swap(r->v, r->vStage);
    }
    m_accelerationMatchesX = false;
    m_listAtX = false;
    m_homeCurrent = gpuCount() == 1;
}

template class CudaDevice<float>;
template class CudaDevice<double>;

}  // namespace corebox
