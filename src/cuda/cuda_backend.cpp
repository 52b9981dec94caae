// The CUDA backend: construction, model and state, reductions, phase timing and instance output.
// Integration and collision rounds are in cuda_integration.cpp and cuda_collisions.cpp.
#include <algorithm>
#include <cmath>

#include "cuda_device.h"
#include "pair_table.h"
#include "state_conversions.h"

namespace corebox {

int cudaDeviceCount() {
    int count = 0;
    if (cudaGetDeviceCount(&count) != cudaSuccess) {
        cudaGetLastError();  // clear the sticky "no driver" error
        return 0;
    }
    return count;
}

std::string cudaDeviceDescription(int device) {
    cudaDeviceProp prop{};
    if (cudaGetDeviceProperties(&prop, device) != cudaSuccess) return "unknown CUDA device";
    int driver = 0, runtime = 0;
    cudaDriverGetVersion(&driver);
    cudaRuntimeGetVersion(&runtime);
    return std::string(prop.name) + " (CUDA driver " + std::to_string(driver / 1000) + "." + std::to_string((driver % 1000) / 10) +
           ", runtime " + std::to_string(runtime / 1000) + "." + std::to_string((runtime % 1000) / 10) + ")";
}

std::unique_ptr<Backend> makeCudaBackend(const CudaBackendOptions& options) {
    const int count = cudaDeviceCount();
    if (count == 0) throw DeviceError("no CUDA device found (no NVIDIA driver or no GPU); use --backend cpu");
    auto found = [&] {
        std::string names;
        for (int d = 0; d < count; ++d) names += (names.empty() ? "" : "; ") + std::to_string(d) + ": " + cudaDeviceDescription(d);
        return std::to_string(count) + " found: " + names;
    };
    if (options.device < 0 || options.device >= count) {
        throw DeviceError("CUDA device " + std::to_string(options.device) + " is not available (" + found() + ")");
    }
    if (options.gpus < 1 || options.gpus > gpu::kMaxGpus || options.device + options.gpus > count) {
        throw DeviceError(std::to_string(options.gpus) + " GPU(s) asked for from device " + std::to_string(options.device) +
                          ", but only devices 0 .. " + std::to_string(count - 1) + " exist (" + found() + ")");
    }
    cudaCheck(cudaSetDevice(options.device), "cudaSetDevice");
    if (options.precision == Precision::Fp32) return std::make_unique<CudaDevice<float>>(options);
    return std::make_unique<CudaDevice<double>>(options);
}

namespace {

std::vector<int> devicesOf(const CudaBackendOptions& options) {
    std::vector<int> devices;
    for (int k = 0; k < options.gpus; ++k) devices.push_back(options.device + k);
    return devices;
}

}  // namespace

template <class Real>
CudaDevice<Real>::CudaDevice(const CudaBackendOptions& options) : m_partition(devicesOf(options), 0) {
    for (const DeviceSlice& s : m_partition.slices()) {
        m_replicas.push_back(std::make_unique<Replica<Real>>());
        m_replicas.back()->device = s.device;
    }
    m_pairsOnce = options.pairsOnce;
    m_fusedSteps = options.fusedSteps;
    m_runAheadEnabled = options.fusedSteps && options.runAhead;
    m_aheadListColumns = options.aheadListColumns;
    m_gaussSeidelContacts = options.gaussSeidelContacts;
    if (options.narrowedSearchFrom >= 0) m_narrowedSearchFrom = options.narrowedSearchFrom;
    m_skipUnmovedCellBuilds = options.skipUnmovedCellBuilds;
    m_impactCandidates = options.impactCandidates;
    if (options.candidateSlots > 0) m_candidateSlots = options.candidateSlots;
    if (options.candidateRowsFrom >= 0) m_candidateRowsFrom = options.candidateRowsFrom;
    m_scatteredSearch = options.scatteredSearch;
    if (options.listedScatterMax >= 0) m_listedScatterMax = options.listedScatterMax;
    m_sweepBlocks = options.sweepBlocks;
    m_moversFirst = options.moversFirst;
    const bool peerAccess = peerAccessProblem(devicesOf(options), options.peerAccessDenied).empty();
    m_pairsOnceAcross = options.pairsOnce && options.gpus > 1 && peerAccess;
    const Exchange exchange = options.exchange != Exchange::Auto ? options.exchange : fastestExchange(options.gpus, peerAccess);
    m_exchange = std::make_unique<PeerExchange>(m_partition, exchange, options.peerAccessDenied);
    cudaCheck(cudaSetDevice(home().device), "cudaSetDevice");
    for (PhaseEvents& set : m_phaseSets)
        for (cudaEvent_t& e : set.marks) cudaCheck(cudaEventCreate(&e), "cudaEventCreate");
    cudaCheck(cudaEventCreateWithFlags(&m_mailCopied, cudaEventDisableTiming), "cudaEventCreate");
    cudaCheck(cudaEventCreateWithFlags(&m_stageDone, cudaEventDisableTiming), "cudaEventCreate");
    cudaCheck(cudaEventCreateWithFlags(&m_readBackCopied, cudaEventDisableTiming), "cudaEventCreate");
    cudaCheck(cudaStreamCreateWithFlags(&m_mailStream, cudaStreamNonBlocking), "cudaStreamCreate");
    // [0..2]: findEvents reads them back, the log's count even when no step has logged; [3]: the host-driven
    // rounds' count of the round before (findEvents).
    m_counters.resize(4);
    cudaCheck(cudaMemsetAsync(m_counters.data(), 0, 4 * sizeof(unsigned int), stream()), "memset");
    sizeStepBuffers();
}

template <class Real>
CudaDevice<Real>::~CudaDevice() {
    // Kernels still queued may read other GPUs' buffers (DA positions, the pairs-once row sums): every
    // stream drains before any buffer is freed. No throw from a destructor: errors are ignored here.
    for (const DeviceSlice& s : m_partition.slices()) {
        cudaSetDevice(s.device);
        cudaStreamSynchronize(s.stream);
    }
    cudaSetDevice(home().device);
    if (m_mailStream) {
        cudaStreamSynchronize(m_mailStream);
        cudaStreamDestroy(m_mailStream);
    }
    for (RkGraph& g : m_rkGraphs) g.reset();
    if (m_stageDone) cudaEventDestroy(m_stageDone);
    if (m_readBackCopied) cudaEventDestroy(m_readBackCopied);
    if (m_mailCopied) cudaEventDestroy(m_mailCopied);
    for (PhaseEvents& set : m_phaseSets) {
        for (cudaEvent_t e : set.marks) cudaEventDestroy(e);
        for (cudaEvent_t e : set.forces) cudaEventDestroy(e);
    }
    // Each replica's buffers are freed with their own GPU current.
    for (auto& r : m_replicas) {
        cudaSetDevice(r->device);
        r.reset();
    }
    cudaSetDevice(m_partition.primary().device);
}

// ---- model and state ----

template <class Real>
void CudaDevice<Real>::setModel(const DeviceModel& model) {
    beforeStateChange();  // masses, radii, box and skin: what was read of the state no longer holds
    ++m_modelGeneration;
    m_model = model;
    m_screenPending = false;  // screened with the old radii and box
    m_listAtX = false;
    const std::vector<PairCoefficients<Real>> pairs = convertPairTable<Real>(model.pairs);
    const size_t s = model.mass.size();
    m_speciesCount = int(s);
    chooseContactCellSplit();
    std::vector<Real> mass(s), invMass(s), radius(s);
    std::vector<Vec3<Real>> field(s);
    for (size_t k = 0; k < s; ++k) {
        mass[k] = Real(model.mass[k]);
        invMass[k] = Real(1.0 / model.mass[k]);
        radius[k] = Real(model.radius[k]);
        field[k] = vec3Cast<Real>(model.acceleration[k]);
    }
    onEachGpu([&](int, Replica<Real>& r) {
        r.pairs.upload(pairs.data(), pairs.size());
        r.mass.upload(mass.data(), s);
        r.invMass.upload(invMass.data(), s);
        r.radius.upload(radius.data(), s);
        r.field.upload(field.data(), s);
    });
    m_gravity = vec3Cast<Real>(model.gravity);
    m_box = vec3Cast<Real>(model.box);
    m_listedThisStep = m_warmValid = false;  // no warm start across a change of masses or radii
    m_candidatesMade = false;                // rows made for other radii and another box
}

template <class Real>
void CudaDevice<Real>::setTableau(const ButcherTableau& tableau) {
    m_tableau = tableau;
    ++m_modelGeneration;
    onEachGpu([&](int, Replica<Real>& r) { r.tableau.upload(&m_tableau, 1); });
}

template <class Real>
void CudaDevice<Real>::setState(const ParticleState& state) {
    beforeStateChange();
    m_kickDriftKnown = false;
    ++m_modelGeneration;
    sync();
    m_accelerationMatchesX = false;
    m_listAtX = false;
    m_listedThisStep = m_warmValid = false;  // indices may now mean other particles: no warm start
    m_candidatesMade = false;                // and the candidate rows hold other particles
    m_n = int64_t(state.size());
    m_partition.resize(m_n);
    // Full-length arrays are padded to P equal chunks (NCCL); padding rows are never read as particles.
    const size_t padded = size_t(m_partition.paddedRows());
    // Converted on every core into kept memory: an edit of the World (the sandbox at 10^5 balls on an
    // H200's host) re-sends the whole state, and fresh arrays converted on one thread were part of the
    // 2.3 to 3.2 ms its replaceParticles took.
    std::vector<Vec3<Real>>& x = m_uploadX;
    std::vector<Vec3<Real>>& v = m_uploadV;
    x.resize(padded);
    v.resize(padded);
    const int64_t n = int64_t(state.size());
    conversionLoop(int64_t(padded), 0, [&](int64_t i) {
        x[size_t(i)] = i < n ? vec3Cast<Real>(state.position[size_t(i)]) : Vec3<Real>{0, 0, 0};
        v[size_t(i)] = i < n ? vec3Cast<Real>(state.velocity[size_t(i)]) : Vec3<Real>{0, 0, 0};
    });
    onEachGpu([&](int k, Replica<Real>& r) {
        const size_t rows = size_t(slice(k).size());
        r.x.upload(x.data(), padded);
        r.v.upload(v.data(), padded);
        r.species.upload(state.species.data(), state.species.size());
        for (auto* b : {&r.xStage, &r.vStage}) b->resize(padded);
        r.acceleration.resize(rows);
        r.forceScratch.resize(gpu::forceScratchBytes<Real>(int64_t(rows), m_n, m_pairsOnce, m_pairsOnceAcross ? gpuCount() : 1));
    });
    m_hostSpecies = state.species;
    chooseContactCellSplit();
    for (auto* b : {&m_contactAcceleration, &m_snapshotX, &m_snapshotV}) b->resize(size_t(m_n));
    m_homeForceScratch.resize(gpu::forceScratchBytes<Real>(m_n, m_n));
    sizeStepBuffers();
    m_homeCurrent = m_slicesCurrent = true;
    m_cellsMatchPositions = false;
}

template <class Real>
void CudaDevice<Real>::keepSnapshot() {
    if (m_fusedSteps && gpuCount() == 1) {  // taken by the next kickDrift's kernel, or before any other change
        m_snapshotPending = true;
        return;
    }
    gatherToHome();
    const size_t bytes = size_t(m_n) * sizeof(Vec3<Real>);
    cudaCheck(cudaMemcpyAsync(m_snapshotX.data(), home().x.data(), bytes, cudaMemcpyDeviceToDevice, stream()), "snapshot");
    cudaCheck(cudaMemcpyAsync(m_snapshotV.data(), home().v.data(), bytes, cudaMemcpyDeviceToDevice, stream()), "snapshot");
}

// Both arrays in one wait, through page-locked staging (a pageable copy is staged by the driver).
template <class Real>
void CudaDevice<Real>::download(const DeviceBuffer<Vec3<Real>>& xd, const DeviceBuffer<Vec3<Real>>& vd, ParticleState& out) const {
    const size_t n = size_t(m_n);
    Vec3<Real>* x = m_hostStateX.resize(n);
    Vec3<Real>* v = m_hostStateV.resize(n);
    if (n > 0) {
        cudaCheck(cudaMemcpyAsync(x, xd.data(), n * sizeof(Vec3<Real>), cudaMemcpyDeviceToHost, stream()), "state");
        cudaCheck(cudaMemcpyAsync(v, vd.data(), n * sizeof(Vec3<Real>), cudaMemcpyDeviceToHost, stream()), "state");
    }
    sync();
    out.resize(n);
    // On every core where long (the World reads the state back before each edit).
    conversionLoop(int64_t(n), 0, [&](int64_t i) {
        out.position[size_t(i)] = vec3Cast<double>(x[i]);
        out.velocity[size_t(i)] = vec3Cast<double>(v[i]);
        out.species[size_t(i)] = m_hostSpecies[size_t(i)];
    });
}

// ---- reductions ----

template <class Real>
int CudaDevice<Real>::queuePartialSums(const double* values, int rows, const char* mask) {
    const int blocks = partialBlocks();
    const size_t count = size_t(rows) * size_t(blocks);
    m_partials.resize(count);
    if (m_n > 0) gpu::launchBlockSums(values, rows, m_n, m_partials.data(), stream(), mask);
    else cudaCheck(cudaMemsetAsync(m_partials.data(), 0, count * sizeof(double), stream()), "memset");
    cudaCheck(cudaMemcpyAsync(m_hostPartials.resize(count), m_partials.data(), count * sizeof(double), cudaMemcpyDeviceToHost, stream()),
              "sums");
    return blocks;
}

template <class Real>
std::vector<double> CudaDevice<Real>::hostPartialSums(int rows, int blocks) const {
    return sumPartials(m_hostPartials.data(), rows, blocks);
}

template <class Real>
std::vector<double> CudaDevice<Real>::sumPartials(const double* partials, int rows, int blocks) {
    std::vector<double> sums(size_t(rows), 0.0);
    for (int r = 0; r < rows; ++r)
        for (int b = 0; b < blocks; ++b) sums[size_t(r)] += partials[size_t(r) * size_t(blocks) + size_t(b)];
    return sums;
}

template <class Real>
std::vector<double> CudaDevice<Real>::sumRows(int rows) {
    const int blocks = queuePartialSums(m_rows.data(), rows);
    sync();
    return hostPartialSums(rows, blocks);
}

template <class Real>
double CudaDevice<Real>::kineticEnergy() {
    if (m_kineticCached) return m_cachedKinetic;  // read with the relaxation, nothing changed since
    gatherToHome();
    const int blocks = queueKineticSum();
    sync();
    return hostPartialSums(1, blocks)[0];
}

template <class Real>
int CudaDevice<Real>::queueKineticSum() {
    m_rows.resize(size_t(m_n));
    gpu::launchKineticRow(arrays(), table(), m_rows.data(), stream());
    return queuePartialSums(m_rows.data(), 1);
}

template <class Real>
void CudaDevice<Real>::scaleVelocities(double alpha) {
    beforeStateChange();
    gatherToHome();
    gpu::launchScale(home().v.data(), m_n, Real(alpha), stream());
    homeChanged();
}

template <class Real>
EnergySums CudaDevice<Real>::energies() {
    gatherToHome();
    m_pairEnergy.resize(size_t(m_n));
    m_scratch.resize(size_t(m_n));
    gpu::ForceArgs<Real> f = homeForceArgs(home().x.data(), m_scratch.data());
    f.pairEnergy = m_pairEnergy.data();
    if (useLists() && gpuCount() == 1) {  // one GPU: its lists cover every row
        home().list.update(home().x.data(), m_n, 0, m_n, m_box, m_model.cutoff, m_model.skin, stream());
        home().list.fill(f);
    }
    gpu::launchForces(f, stream());
    const int s = m_speciesCount;
    m_rows.resize(size_t(s + 4) * size_t(m_n));
    gpu::launchEnergyRows(gpu::EnergyArgs<Real>{arrays(), table(), m_pairEnergy.data(), m_rows.data()}, stream());
    const std::vector<double> sums = sumRows(s + 4);
    EnergySums e;
    e.kineticPerSpecies.assign(sums.begin(), sums.begin() + s);
    for (double k : e.kineticPerSpecies) e.kinetic += k;
    e.potential = sums[size_t(s)];
    e.momentum = {sums[size_t(s + 1)], sums[size_t(s + 2)], sums[size_t(s + 3)]};
    return e;
}

template <class Real>
HealthReport CudaDevice<Real>::health() {
    m_checkCached = false;  // a thermostat step reads health itself: the step check goes unused
    queueHealth();
    sync();
    return healthReport();
}

template <class Real>
void CudaDevice<Real>::queueHealth() {
    gatherToHome();
    forgetRunAhead();  // its words are about to be written
    gpu::StepWords* w = stepWords();
    m_wordsFresh = false;
    cudaCheck(cudaMemsetAsync(w->healthCounts, 0, sizeof w->healthCounts, stream()), "memset");
    gpu::launchHealth(gpu::HealthArgs<Real>{arrays(), m_box, w->healthCounts, w->healthExamples}, stream());
    cudaCheck(cudaMemcpyAsync(m_hostWords.resize(kHostWords) + kHealthWord, w->healthCounts, sizeof w->healthCounts,
                              cudaMemcpyDeviceToHost, stream()),
              "health");
    cudaCheck(cudaMemcpyAsync(m_hostHealthExamples.resize(5), w->healthExamples, sizeof w->healthExamples, cudaMemcpyDeviceToHost, stream()),
              "health");
}

template <class Real>
HealthReport CudaDevice<Real>::healthReport() const {
    return healthReportOf(m_hostWords.data() + kHealthWord, m_hostHealthExamples.data());
}

template <class Real>
HealthReport CudaDevice<Real>::healthReportOf(const unsigned long long counts[3], const long long examples[5]) {
    HealthReport r;
    r.nonFinite = int64_t(counts[0]);
    r.outsideBox = int64_t(counts[1]);
    for (unsigned long long k = 0; k < std::min<unsigned long long>(counts[2], 5); ++k) r.examples.push_back(examples[k]);
    std::sort(r.examples.begin(), r.examples.end());
    return r;
}

// ---- timing and output ----

template <class Real>
void CudaDevice<Real>::markPhase(StepPhase phase) {
    if (phase == StepPhase::Collide) gatherToHome();  // the home GPU's stream then waits for every GPU
    if (phase == StepPhase::Integrate) {
        // The other set: the last step's, if still unread, stays for phaseSeconds.
        m_phaseSet = m_phaseSets[m_phaseSet].unread ? 1 - m_phaseSet : m_phaseSet;
        phaseEvents().forceEvents = 0;
        phaseEvents().unread = false;
    }
    m_timingWindow = phase == StepPhase::Integrate ? 0 : phase == StepPhase::Collide ? 1 : -1;
    cudaCheck(cudaEventRecord(phaseEvents().marks[int(phase)], stream()), "event");
    if (phase == StepPhase::Done) phaseEvents().unread = true;
}

template <class Real>
void CudaDevice<Real>::addPhases(PhaseEvents& set, PhaseSeconds& s) {
    set.unread = false;
    float integrate = 0, collide = 0;
    if (cudaEventElapsedTime(&integrate, set.marks[0], set.marks[1]) != cudaSuccess ||
        cudaEventElapsedTime(&collide, set.marks[1], set.marks[2]) != cudaSuccess) {
        cudaGetLastError();  // marks not done (no wait since): the step goes unreported
        return;
    }
    float ms = 0;
    double forces[2] = {0, 0};  // in the integrate and the collide window
    for (size_t k = 0; k + 1 < set.forceEvents; k += 2) {
        if (cudaEventElapsedTime(&ms, set.forces[k], set.forces[k + 1]) != cudaSuccess) {
            cudaGetLastError();
            ms = 0;
        }
        forces[set.forceWindow[k] != 0] += ms;
    }
    s.forces += 1e-3 * (forces[0] + forces[1]);
    s.integrate += 1e-3 * (double(integrate) - forces[0]);
    s.collide += 1e-3 * (double(collide) - forces[1]);
}

// Without a wait: a step's Done mark, recorded after the stage's last wait, is often still in the
// stream's queue when this is asked (waiting for it cost a round trip a step: 5 us of an LJ step of
// 64000 on an H200, 0.14 ms). A step whose marks are not done yet is reported with the next one,
// whose stage wait ran after them: the sum over a run is every step's time but the last one's.
template <class Real>
PhaseSeconds CudaDevice<Real>::phaseSeconds() {
    PhaseSeconds s;
    PhaseEvents& last = m_phaseSets[1 - m_phaseSet];
    if (last.unread) addPhases(last, s);
    PhaseEvents& current = phaseEvents();
    if (current.unread && cudaEventQuery(current.marks[int(StepPhase::Done)]) == cudaSuccess) addPhases(current, s);
    return s;
}

template <class Real>
void CudaDevice<Real>::writeInstances(const InstanceTarget& target) {
    gatherToHome();  // every slice reaches the render GPU
    if (target.memory == InstanceTarget::Memory::Device) {
        gpu::launchFillInstances(arrays(), home().radius.data(), target.key, target.instances, stream());
        sync();  // the caller unmaps the GL buffer next
        return;
    }
    m_instances.resize(size_t(m_n));
    gpu::launchFillInstances(arrays(), home().radius.data(), target.key, m_instances.data(), stream());
    sync();
    m_instances.download(target.instances, size_t(m_n));
}

template class CudaDevice<float>;
template class CudaDevice<double>;

}  // namespace corebox
