// The CUDA backend's class, shared by the files that implement it: cuda_backend.cpp (model, state,
// reductions, timing, output), cuda_integration.cpp (forces, RK stages, Verlet), cuda_collisions.cpp
// (the collision stage) and cuda_replicas.cpp (state movement between GPUs). Internal to src/cuda.
//
// Design note: one to P GPUs. Particle rows are split into contiguous slices (DevicePartition), one
// per GPU; each GPU keeps a Replica: the model tables, the positions of every particle (its own slice
// authoritative, the others received before each force pass through the chosen PeerExchange) and the
// integration state of its own slice. Integration operations (kick, drift, RK stages, error norms)
// run on every GPU over its slice; a force pass first shares the positions, then each GPU computes
// the accelerations of its rows against all N (every ordered pair), or, where the pairs-once pass
// applies and the GPUs have peer access, each GPU an equal share of the pairs, each once, and the
// accelerations of its rows from every GPU's sums (pairs_once_kernels.cu). Everything that needs the
// whole state at once (the collision stage, reductions, health, snapshots, state downloads, instances
// for the renderer) runs on the home GPU (the first, which also renders), after a gather of the
// slices; whatever it changes is scattered back before the next integration operation. So the
// collision stage is literally the one-GPU code on the gathered state, and gives one GPU's counts and
// dissipation by construction; its cost is O(N) on one GPU next to the O(N^2 / P) force passes, and
// the gather and scatter move 2 x 24 bytes per particle over NVLink (microseconds at N = 65536).
// With one GPU there is one replica and nothing moves.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "backend.h"
#include "cuda_backend.h"
#include "device_neighbour_list.h"
#include "cuda_check.h"
#include "device_buffer.h"
#include "device_cell_list.h"
#include "device_partition.h"
#include "host_cell_list.h"
#include "gpu_launch.h"
#include "peer_exchange.h"
#include "pinned_buffer.h"

namespace corebox {

// What one GPU holds. Full-length arrays have partition().paddedRows() rows (an NCCL all-gather moves
// equal chunks); slice arrays have the slice's rows, indexed from the slice's first row.
template <class Real>
struct Replica {
    int device = 0;
    DeviceBuffer<PairCoefficients<Real>> pairs;
    DeviceBuffer<ButcherTableau> tableau;
    DeviceBuffer<Real> mass, invMass, radius;
    DeviceBuffer<Vec3<Real>> field;                 // per species: gravity plus the species' own acceleration
    DeviceBuffer<int32_t> species;                  // full length
    DeviceBuffer<Vec3<Real>> x, v, xStage, vStage;  // full length
    DeviceBuffer<Vec3<Real>> acceleration, kx, kv;  // slice (kx, kv: stage-major, stages x slice rows)
    DeviceBuffer<unsigned char> forceScratch;
    DeviceBuffer<double> errorRows, errorPartials;  // slice
    DeviceNeighbourList<Real> list;                 // the slice's rows over all positions (cut-off forces)
    PinnedBuffer<double> hostErrorPartials;
};

template <class Real>
class CudaDevice final : public Backend {
public:
    explicit CudaDevice(const CudaBackendOptions& options);
    ~CudaDevice() override;

    // ---- identity ----
    std::string name() const override { return "cuda"; }
    std::string deviceName() const override;  // "2 x NVIDIA H200 (...), dta exchange" with several GPUs
    Precision precision() const override { return std::is_same<Real, float>::value ? Precision::Fp32 : Precision::Fp64; }
    int interopDevice() const override { return home().device; }
    DeviceState deviceState() override;  // cuda_replicas.cpp
    void bindCallingThread() override { cudaCheck(cudaSetDevice(home().device), "cudaSetDevice"); }

    // ---- model and state (cuda_backend.cpp) ----
    void setModel(const DeviceModel& model) override;
    void setTableau(const ButcherTableau& tableau) override;
    void setState(const ParticleState& state) override;
    ParticleState state() const override;
    void readState(ParticleState& out) const override;
    void readPositions(const PositionSink& sink) const override;
    void keepSnapshot() override;
    ParticleState snapshot() const override;

    // ---- integration (cuda_integration.cpp) ----
    void computeAccelerations() override;
    bool supportsNeighbourLists() const override { return true; }
    bool refreshAccelerations() override;
    std::vector<Vec3<double>> cachedAccelerations() const override;
    void restoreAccelerations(const std::vector<Vec3<double>>& a) override;
    ForceCounters forceCounters() const override;
    void kick(double h) override;
    void drift(double dt) override;
    void kickDrift(double h, double dt) override;  // cuda_step.cpp
    void accelerateAndKick(double h) override;     // cuda_step.cpp
    void rkStage(int stage, double dt) override;
    void stageForces(int stage) override;
    void rkSolution(int stages, double dt) override;
    void rkStep(int stages, double dt) override;  // cuda_rk_graph.cpp
    double rkErrorNorm(double dt, double tolerance) override;
    void acceptStage() override;

    // ---- collision rounds (cuda_collisions.cpp) ----
    StageScreen screenStage(const ImpactWindow<double>& window, double contactGap) override;
    int resolveWallImpacts() override;
    void beginCollisions(const ImpactWindow<double>& window) override;
    int64_t findEvents(EventScope scope) override;
    void applyEvents() override;
    ImpactRounds runImpactRounds(int maxRounds) override;
    CollisionTally collisionTally() override;
    void setContactLog(bool on, double minImpulse) override {
        m_logContacts = on;
        m_logMinImpulse = minImpulse;
    }
    void readContactLog(std::vector<ContactRecord>& out) const override;
    int64_t listContacts(const RestingContact<double>& resting) override;
    bool relaxesGaussSeidel() const override { return m_gaussSeidel; }
    double listedOverlap() const override { return m_listedOverlap; }
    ContactResidual<double> relaxContacts(int sweeps) override;
    RelaxationOutcome relaxListing(const RelaxationPlan& plan) override;
    void endRelaxation() override;
    ContactCarryOver contactWarmStart() const override;
    void restoreContactWarmStart(const ContactCarryOver& carried) override;
    void beginStep(int64_t step) override { m_stepIndex = step; }
    double contactLiftWork() override;
    ImpulseSums contactImpulses() override;

    // ---- reductions, timing, output (cuda_backend.cpp) ----
    double kineticEnergy() override;
    void scaleVelocities(double alpha) override;
    EnergySums energies() override;
    double pairVirial() override;  // cuda_pressure.cpp
    HealthReport health() override;
    StepCheck checkStep() override;
    void markPhase(StepPhase phase) override;
    PhaseSeconds phaseSeconds() override;
    void writeInstances(const InstanceTarget& target) override;
    void finish() override { sync(); }

private:
    // ---- the home GPU and the replicas (cuda_replicas.cpp) ----
    Replica<Real>& home() const { return *m_replicas.front(); }
    cudaStream_t stream() const { return m_partition.primary().stream; }  // the home GPU's stream
    void sync() const { m_partition.synchronize(); }
    int gpuCount() const { return int(m_replicas.size()); }
    // Makes the home GPU hold every row of X and V (gathering the slices when the GPUs integrated
    // since), or every GPU its own slice (scattering what the home GPU changed). Both cheap no-ops
    // when already so, and always with one GPU.
    void gatherToHome() const;
    std::vector<std::vector<void*>> stateBuffers() const;  // X and V, each one buffer per GPU
    void scatterFromHome() const;
    // The home GPU changed X or V (collisions, thermostat): the other GPUs' slices are stale.
    void homeChanged() const {
        m_slicesCurrent = gpuCount() == 1;
        m_listAtX = false;
        m_kineticCached = false;
    }
    // Runs body(k, replica) on every GPU k with that GPU current; the home GPU is current after.
    template <class Body>
    void onEachGpu(Body body) const {
        for (int k = 0; k < gpuCount(); ++k) {
            cudaCheck(cudaSetDevice(m_replicas[size_t(k)]->device), "cudaSetDevice");
            body(k, *m_replicas[size_t(k)]);
        }
        cudaCheck(cudaSetDevice(home().device), "cudaSetDevice");
    }
    const DeviceSlice& slice(int k) const { return m_partition.slices()[size_t(k)]; }

    gpu::ParticleArrays<Real> arrays() { return {home().x.data(), home().v.data(), home().species.data(), m_n}; }
    gpu::SpeciesTable<Real> tableOf(const Replica<Real>& r) const {
        return {r.pairs.data(), r.mass.data(), r.invMass.data(), r.radius.data(), r.field.data(), m_speciesCount};
    }
    gpu::SpeciesTable<Real> table() const { return tableOf(home()); }
    // Force pass of GPU k's rows from the positions `x` (that GPU's copy), into `out` (slice rows).
    gpu::ForceArgs<Real> forceArgs(int k, const Vec3<Real>* x, Vec3<Real>* out);
    // Every row on the home GPU alone (energies, contact accelerations): begin 0, end n.
    gpu::ForceArgs<Real> homeForceArgs(const Vec3<Real>* x, Vec3<Real>* out);
    // One force pass on every GPU: positions shared by the exchange, then each GPU's rows. `stage`:
    // -1 for A = a(X), else Kv_stage = a(Xs). With `kick`, a pass from lists also kicks V by
    // kickH A (accelerateAndKick); returns whether it did.
    bool forcePass(int stage, bool kick = false, double kickH = 0);
    // Forces from neighbour lists: the model asks for them and every GPU holds every position when it
    // computes (with direct access, DA, the peers' positions stay remote: all pairs then).
    bool useLists() const;
    // Force launches on the home GPU bracketed by timing events (markForceTime before and after),
    // read once the step has finished.
    void launchTimedForces(const gpu::ForceArgs<Real>& args);
    void markForceTime();
    // x and v of the home GPU (or its snapshot) into out, with the species, in one wait.
    void download(const DeviceBuffer<Vec3<Real>>& x, const DeviceBuffer<Vec3<Real>>& v, ParticleState& out) const;
    // Sums of `rows` rows of m_rows (each n long); block partials are added on the host in order.
    std::vector<double> sumRows(int rows);
    // The kinetic energy's row and its block partials queued (kineticEnergy, colourListing); returns the
    // blocks for hostPartialSums(1, blocks) after a sync.
    int queueKineticSum();
    template <class T>
    T readBack(const DeviceBuffer<T>& buffer, size_t offset = 0) {  // one value, after a sync
        const T* value = queueReadBack(buffer, offset);
        sync();
        return *value;
    }
    // The same with queue()'s launches behind the copy, which run on while the host waits for the copy
    // alone (one GPU: an event on the home stream).
    template <class T, class Queue>
    T readBackThen(const DeviceBuffer<T>& buffer, size_t offset, Queue queue) {
        const T* value = queueReadBack(buffer, offset);
        cudaCheck(cudaEventRecord(m_readBackCopied, stream()), "event");
        queue();
        cudaCheck(cudaEventSynchronize(m_readBackCopied), "read-back");
        return *value;
    }
    // The copy of one value into the host words, queued (readBack, readBackThen).
    template <class T>
    const T* queueReadBack(const DeviceBuffer<T>& buffer, size_t offset) {
        static_assert(sizeof(T) <= sizeof(unsigned long long), "one word");
        T* value = reinterpret_cast<T*>(m_hostWords.resize(kHostWords));
        cudaCheck(cudaMemcpyAsync(value, buffer.data() + offset, sizeof(T), cudaMemcpyDeviceToHost, stream()),
                  "read-back");
        return value;
    }
    // Queues the block partials of `rows` rows of `values` (each n long) into pinned memory;
    // hostPartialSums() adds them, in block order, after a sync.
    int queuePartialSums(const double* values, int rows, const char* mask = nullptr);
    std::vector<double> hostPartialSums(int rows, int blocks) const;
    // The block partials of a reduction over n rows: how many per row, and their sums per row in block order.
    int partialBlocks() const { return std::max(gpu::blockSumBlocks(m_n), 1); }
    static std::vector<double> sumPartials(const double* partials, int rows, int blocks);
    // Health kernel and its read-back queued (host arrays below); healthReport() reads them after a sync.
    void queueHealth();
    HealthReport healthReport() const;
    static HealthReport healthReportOf(const unsigned long long counts[3], const long long examples[5]);
    // The screen's scales for the contact phase's resting gap (screenVerdict).
    ScreenScales screenScales(double contactGap) const;
    // What a stage that the screen skips leaves: nothing listed (no warm start), no events, no log.
    void skipQuietStage();
    // Sums the kImpulseRows rows of `rows` (impulse_sums.h) in a fixed order (cuda_pressure.cpp).
    ImpulseSums sumImpulseRows(const DeviceBuffer<double>& rows);
    static ImpulseSums impulseSumsOf(const std::vector<double>& rowSums);  // kImpulseRows sums, in order
    // A stage's tally from the pair and wall counts of the step words and the sums of the impact rows
    // (kImpulseRows, then the loss).
    static CollisionTally tallyOf(const unsigned long long kindCounts[2], const std::vector<double>& rowSums);
    gpu::CollisionArgs<Real> collisionArgs();
    bool narrowsSearch(int round) const;
    bool narrowableStage() const;
    void narrowSearch(gpu::CollisionArgs<Real>& a, int round, const unsigned int* lastCount, cudaStream_t s);
    bool scattersSearch(int round) const;
    bool scattersSparseRounds() const;
    void searchRound(gpu::CollisionArgs<Real>& a, int round, const unsigned int* lastCount, cudaStream_t s);
    void beginWarmStart();  // beginCollisions: the last listing's rows become the warm start
    void swapListingIntoWarmRows();  // the last listing's rows into m_warm*, for the next listing's fill
    // Room for `records` contact log records, keeping those written so far (at most m_logBound).
    void reserveLog(size_t records);
    // Queues the sort of the log's `count` records by (round, particle) and their copy into m_hostLog.
    void queueLogRead(size_t count) const;
    gpu::ContactArgs<Real> contactArgs();

    // ---- the one-wait step (cuda_step.cpp) ----
    // Design note. A Verlet step of a screened list model on one GPU costs the H200 far more in host
    // round trips than in arithmetic (an LJ fluid of 64000 in a walled box: 0.28 ms a step, 0.04 of it
    // the force pass, four waits and some thirty launches). So, with CudaBackendOptions::fusedSteps:
    //   - keepSnapshot, kick and drift become one kernel (kickDrift) and the closing kick rides the
    //     force pass (accelerateAndKick);
    //   - screenStage does not wait for the screen to decide: the device reads it (launchStageWalls)
    //     and gated launches (gpu::StageGate) resolve the walls at once, sum their tally, refresh the
    //     accelerations of what they moved and check the step (health, kinetic energy), and one copy
    //     brings every word back (StepWords and block partials, m_stepMail). The calls of the stage
    //     that follow (beginCollisions, resolveWallImpacts, collisionTally, refreshAccelerations,
    //     checkStep) find their results there; a stage the device cannot finish (Full, or wall
    //     contacts to list) goes on on the host from where the device left it;
    //   - the step check also forecasts the lists: whether the next kickDrift, whose arithmetic it
    //     repeats, takes some row past half the skin; the next force pass then needs no displacement
    //     check (and no wait) of its own. The stage's pass checks and forecasts every particle, and the
    //     refresh forecasts again the rows whose accelerations it changes (one launch fewer than a
    //     check of its own).
    // The kernels compute with the same functions as the separate launches, so a step gives the same
    // bits either way (tests/gpu/test_cuda_neighbour_list.cpp compares both).
    bool m_fusedSteps = true;
    DeviceBuffer<double> m_stepMail;      // StepWords, then block partials: the impact rows' and the kinetic row's
    PinnedBuffer<double> m_hostStepMail;  // its copy
    gpu::StepWords* stepWords() { return reinterpret_cast<gpu::StepWords*>(m_stepMail.data()); }
    const gpu::StepWords& hostStepWords() const { return *reinterpret_cast<const gpu::StepWords*>(m_hostStepMail.data()); }
    static constexpr size_t kStepWordDoubles = (sizeof(gpu::StepWords) + sizeof(double) - 1) / sizeof(double);
    void sizeStepBuffers();  // the mail and the impact rows (zero, none flagged) for m_n (setState)
    // Every step word but the screen's is zero, and those are reset or a screening pass's (kickDrift
    // resets them; anything else that counts into them clears this).
    bool m_wordsFresh = false;
    mutable bool m_snapshotPending = false;  // keepSnapshot waits for the next kickDrift (one GPU)
    // What Verlet's last kickDrift did: the step the forecast repeats.
    double m_kickDriftH = 0, m_kickDriftDt = 0;
    bool m_kickDriftKnown = false;
    // The lists' forecast: 1 after a step check computed it, 2 after the kickDrift it forecast.
    struct ListForecast {
        int stage = 0;
        bool beyondHalfSkin = false;
        int64_t buildId = 0;  // DeviceNeighbourList::buildId of the lists it was made for
    } m_forecast;
    // The stage as the device resolved it within screenStage's wait (WallsOnly), until the calls of the
    // stage have read it; whether its refresh of the accelerations ran (no moved row past half the skin).
    bool m_speculated = false, m_speculatedRefresh = false;
    ImpactWindow<double> m_speculatedWindow{0, 0};
    int readResolvedWalls();  // the tally and stats of the walls resolveOnDevice resolved; returns the rounds
    bool m_wallsCountedOnDevice = false;  // m_wallContactsPossible from the device's count, for the window's resting contact
    // The step check read with the screen (valid until X, V or A change).
    bool m_checkCached = false;
    StepCheck m_cachedCheck;
    bool canResolveOnDevice() const;

    // ---- running ahead (cuda_step.cpp) ----
    // Design note. With the step's one wait gone to the stage, what is left between two Verlet steps
    // is the host's own time, the device idle: reading the stage's words, the core's bookkeeping, the
    // next launches (an LJ fluid of 64000 on an H200: 0.135 ms a step, 0.06 of it kernels). So,
    // before it waits for the stage's words, resolveOnDevice queues the next step's kickDrift and
    // force pass (with its kick and screen) behind a gate that each of their threads opens only where
    // runAheadOpen says the step is finished (gpu_launch.h: nothing left for the host, the lists good,
    // every particle sound), and waits on the copy of the words (made on a stream of its own, beside
    // the step ahead), not on the stream: the device computes the next step while the host reads this
    // one. The step it ran ahead writes other buffers (m_ahead*, its step words too: the gate reads
    // this step's while they run), so everything that reads the state between steps reads this
    // step's; the next kickDrift, if it asks for the same h and dt with nothing changed since
    // (beforeStateChange forgets it), takes those buffers as the state instead of launching, and
    // accelerateAndKick has nothing left to do. Where the step was not finished the gate stayed shut
    // and nothing ran. The arithmetic is the separate launches' (same kernels, same inputs), so
    // running ahead gives the same bits (tests/gpu/test_cuda_neighbour_list.cpp compares both).
    // A step whose lists must be rebuilt runs ahead too when the forecast's hint (ListForecastArgs:
    // the step after the next, its kick taken as the next one's) said so a step before: it builds
    // lists of its own (m_aheadList) at the positions ahead, with the columns of the home lists and no
    // wait, its pass gated on their overflow word as well; taken, they swap with the home lists, and
    // resolveOnDevice reads the overflow with the stage's words (an overflow: built again with more
    // columns, the pass done again, then the stage). The hint costs nothing where it is wrong: lists
    // built a step early serve as well (a listed pair beyond the cutoff adds an exact zero), and a step
    // it missed rebuilds after the wait as before. That fluid, fp32: 0.118 ms a step running ahead
    // (8478 steps/s) where rebuilding steps could not; 0.094 ms (10690 steps/s) with lists built
    // ahead, the stage's sums and refresh in one launch and the words copied beside: 97% of its steps
    // run ahead, and the device is the bound (the host waits 55 us a step).
    bool m_runAheadEnabled = true;  // CudaBackendOptions::runAhead
    struct RunAhead {
        bool launched = false;   // queued by the last resolveOnDevice, not yet taken or forgotten
        bool open = false;       // the host's reading of the gate (runAheadOpen of the words)
        bool committed = false;  // taken by kickDrift: accelerateAndKick(h) is done
        bool built = false;      // it built lists of its own (m_aheadList)
        double h = 0, dt = 0;
    } m_runAhead;
    // The lists of a step that runs ahead and builds (launchRunAhead), swapped with the home GPU's when
    // it is taken; whether the last forecast's hint asks for that, for the lists of which build.
    DeviceNeighbourList<Real> m_aheadList;
    bool m_takenListsUnchecked = false;  // a step taken with lists it built: their overflow not read yet
    int m_aheadListColumns = 0;  // CudaBackendOptions::aheadListColumns
    bool m_buildAheadHint = false;
    int64_t m_buildAheadHintId = 0;
    // Open run-aheads forgotten in a row (a thermostat rescales every step: the pass that ran ahead is
    // thrown away, after its cost was waited for); from two on, the next 32 stages do not run ahead.
    int m_runAheadsForgotten = 0, m_runAheadPause = 0;
    bool m_lastWasKickDrift = false;  // no other integration call since the last kickDrift
    bool m_verletSteps = false;       // the last accelerateAndKick(h) followed kickDrift(h, dt): Verlet's step
    int64_t m_stepsRunAhead = 0;      // ForceCounters::stepsRunAhead
    // The step run ahead's state, and its snapshot (the state before it, kept as kickDrift keeps it):
    // a snapshot of its own, so that a step the host then fails still finds the one before.
    DeviceBuffer<Vec3<Real>> m_aheadX, m_aheadV, m_aheadA, m_aheadSnapshotX, m_aheadSnapshotV;
    DeviceBuffer<double> m_aheadMail;  // the step ahead's step words (and room for the partials): m_stepMail's twin
    cudaEvent_t m_mailCopied = nullptr;
    cudaEvent_t m_stageDone = nullptr;    // the stage's last launch, which the words' copy waits for
    cudaEvent_t m_readBackCopied = nullptr;  // readBackThen's copy
    cudaStream_t m_mailStream = nullptr;  // the words' copy, beside the step that runs ahead
    bool screensAtX() const;  // a force pass at X on these lists also screens the stage
    bool launchRunAhead(bool build);  // false where its buffers do not fit (running ahead is then off)
    void redoOverflowedPass();
    void settleUncheckedLists();
    void forgetRunAhead();  // what ran ahead no longer matches the state or the step words
    bool takeRunAhead(double h, double dt);
    StageScreen resolveOnDevice(const ImpactWindow<double>& window);
    // The lists' forecast of the next kickDrift into the step words when there is one to make, else
    // moves null.
    gpu::ListForecastArgs<Real> listForecastArgs();
    StepCheck stepCheckOf(const gpu::StepWords& words, const double* partials) const;
    // The step check's arguments (checkStep, the stage's tail), its kinetic row into `kineticRow`.
    gpu::StepCheckArgs<Real> stepCheckArgs(double* kineticRow);
    void readForecast(bool made, const gpu::StepWords& words);
    // Every call that changes X, V or A calls this first: a deferred snapshot is taken, and what was
    // read of the state (the cached check, the forecast, the speculated refresh) is forgotten; a force
    // pass at X keeps the forecast, which it reads.
    void beforeStateChange(bool forcePassAtX = false);
    void takeSnapshot() const;  // the deferred one, if any

    // ---- the RK step as one graph (cuda_rk_graph.cpp) ----
    // Design note. An RK4 step of 1024 particles (all pairs) is four stage kernels, four force passes
    // and the solution: arithmetic of a few microseconds each, launched by the host at a few
    // microseconds each, and the host's launches were the bound. On one GPU with all pairs nothing in
    // those calls waits for the device, and a fixed-step method repeats the same launches with the same
    // arguments every step but for X and Xs, which acceptStage swaps: so the second time a step with the
    // same key comes (dt, stages, the buffers, the model's generation) its launches are captured into a
    // graph, and from then on the graph is launched instead, with the host-side effects of the calls
    // applied as they would be (the deferred snapshot too, taken inside). Two graphs are kept (the two
    // parities of X and Xs); an adaptive step, whose dt changes, never repeats a key and launches as
    // before. The graph runs the same kernels on the same arguments: the same bits. With phase timing
    // on, one pair of force events brackets the graph (the stage updates then count as forces). Table 1
    // at N = 1024 on an H200 (bench table1): the step's integration, forces included, 0.103 ms before,
    // 0.037 with the graph and the block-a-row pass (force_kernels.cu).
    struct RkGraphKey {
        uint64_t generation = 0;
        double dt = 0;
        int stages = 0;
        const void *x = nullptr, *xStage = nullptr, *kx = nullptr, *kv = nullptr;
        bool snapshot = false;  // the deferred snapshot is pending: the graph takes it
        bool operator==(const RkGraphKey& o) const {
            return generation == o.generation && dt == o.dt && stages == o.stages && x == o.x && xStage == o.xStage && kx == o.kx &&
                   kv == o.kv && snapshot == o.snapshot;
        }
    };
    struct RkGraph {
        RkGraphKey key;
        cudaGraphExec_t exec = nullptr;
        int64_t evaluations = 0, passes = 0;  // what the captured passes added to the counters
        bool launched = false;                // launched before (the capture's step ran the calls themselves)
        void reset();
    };
    bool captureRkStep(RkGraph& graph, int stages, double dt);
    bool m_rkGraphsOff = false;  // a capture failed: plain launches from then on
    std::array<RkGraph, 2> m_rkGraphs;
    int m_rkGraphNext = 0;
    uint64_t m_modelGeneration = 1;  // setModel, setTableau and setState: a captured graph's arguments no longer hold
    bool rkGraphApplies() const;

    DevicePartition m_partition;
    std::vector<std::unique_ptr<Replica<Real>>> m_replicas;  // [0]: the home GPU; pointees mutable (gathers in const calls)
    std::unique_ptr<PeerExchange> m_exchange;
    mutable bool m_homeCurrent = true;    // the home GPU holds every row of X and V
    mutable bool m_slicesCurrent = true;  // every GPU holds its own slice of X and V
    DeviceModel m_model;
    ButcherTableau m_tableau{};
    int m_speciesCount = 0;
    Vec3<Real> m_gravity{0, 0, 0};  // the global field: "up" of the contact phase (per-species fields: Replica::field)
    Vec3<Real> m_box{1, 1, 1};
    int64_t m_n = 0;
    std::vector<int32_t> m_hostSpecies;
    // The contact grids' large particles (cell_list.h), from the radii and the state's species counts.
    CellSplitChoice m_cellSplit;
    void chooseContactCellSplit() {
        m_cellSplit = chooseCellSplit(m_model.radius, speciesCounts(m_hostSpecies, m_speciesCount));
    }
    CellSplit<Real> contactCellSplit();
    mutable PinnedBuffer<Vec3<Real>> m_hostStateX, m_hostStateV;  // the state downloads' staging
    std::vector<Vec3<Real>> m_uploadX, m_uploadV;                 // setState's converted arrays, kept for their memory

    // A step's timing marks: Integrate, Collide, Done, and a pair around each force pass. Two sets, a
    // step's in one while the last step's may still be unread (phaseSeconds: read without a wait).
    struct PhaseEvents {
        cudaEvent_t marks[3] = {};
        std::vector<cudaEvent_t> forces;
        std::vector<unsigned char> forceWindow;  // the pair's window: 0 integrate, 1 collide (a pass run ahead)
        size_t forceEvents = 0;
        bool unread = false;  // all three marks recorded, not reported yet
    };
    PhaseEvents m_phaseSets[2];
    int m_phaseSet = 0;  // the set of the step being marked
    PhaseEvents& phaseEvents() { return m_phaseSets[m_phaseSet]; }
    static void addPhases(PhaseEvents& set, PhaseSeconds& s);
    int64_t m_fullPasses = 0;
    int64_t m_allPairsEvaluations = 0;  // ForceCounters::allPairsEvaluations
    bool m_pairsOnce = true;            // CudaBackendOptions::pairsOnce
    // Several GPUs share one pairs-once pass where it applies (pairsOnceAppliesAcross): pairsOnce, and
    // every GPU can read the others' row sums (peer access); else each GPU its rows, every ordered pair.
    bool m_pairsOnceAcross = false;
    // The collision screen (screenStage): the last full list pass at X wrote its three words
    // (ForceArgs::screen, in StepWords) with m_screenGap; m_screenPending until X, the model or the
    // state change.
    double m_screenGap = -1;  // the gap of the last quietStep call (< 0: none yet, no screen)
    bool m_screenPending = false;
    // One GPU: the lists were checked (and rebuilt if needed) at the current X by the last full pass;
    // the first impact round then needs no displacement check of its own. Cleared whenever X changes.
    mutable bool m_listAtX = false;
    // No pair can come within contact in this stage (the screen's clearance exceeds what the wall
    // events can move two particles): the searches see walls only, through an empty cell list, and
    // skip building one. m_pairsClearNext: from screenStage to the stage's beginCollisions.
    bool m_pairsClear = false, m_pairsClearNext = false;
    // This stage resolves its walls at once (beginCollisions decides; the core then calls
    // resolveWallImpacts instead of the rounds): its tally, read with its one wait (collisionTally
    // returns it), whether some particle ended near a wall (else the contact listing has nothing to
    // find), and whether only the particles it flagged moved (no contact relaxation followed).
    bool m_wallsAtOnce = false;
    CollisionTally m_wallTally;
    bool m_wallContactsPossible = true, m_wallsOnlyMoved = false;
    // The walls-only view: one cell holding nobody ({0, 0}), and particles in index order (the
    // searches take their particles in the view's order).
    DeviceBuffer<int32_t> m_emptyCellStart, m_indexOrder;
    CellListView emptyCells();
    CellListView impactCells();
    CellGeometry impactGeometry() const;
    // The same cells in a round after the first of runImpactRounds: the build skipped where the rounds
    // since the last moved no particle out of its cell (trackCellMoves).
    CellListView impactCellsIfMoved();
    // Sets `a` to flag where its resolution moves a particle out of the cell the impact cells' last
    // build gave it, where those cells are in use and hold keys.
    void trackCellMoves(gpu::CollisionArgs<Real>& a);
    unsigned int* cellsMovedFlag();
    // The batched rounds' candidate rows (gpu_launch.h CandidateRows; runImpactRounds): whether this
    // stage's rounds read them, and round r's cells and rows, made again where stale (*stale: the round's
    // word, set by the round before's resolution or, in a stage's first round, by the staleness check,
    // and cleared by the build; the first rows of a state are made unconditionally).
    bool roundsReadCandidates() const;
    bool allocateCandidates();
    void prepareCandidates(int round, unsigned int* stale, gpu::CollisionArgs<Real>& a);
    CellGeometry candidateGeometry() const;
    Real candidateMargin() const;
    void applyPendingWarmStart();
    int64_t m_refreshes = 0;
    // Verlet's refresh after collisions (one GPU, lists): A matched X at the last full pass and X has
    // not changed since, X as the collision stage found it, and whether both held then.
    bool m_accelerationMatchesX = false;
    bool m_refreshable = false;
    bool m_accelerationIncremental = false;  // A holds an all-pairs exchange, not a full pass's bits (checkpoints carry it)
    DeviceBuffer<Vec3<Real>> m_xBeforeCollisions;
    DeviceBuffer<unsigned char> m_movedFlags;
    DeviceBuffer<int32_t> m_movedList;
    DeviceBuffer<unsigned int> m_movedCount;
    bool refreshAllPairs();
    int m_timingWindow = -1;  // the window being timed: 0 between the Integrate and Collide marks, 1 to Done

    DeviceBuffer<Vec3<Real>> m_scratch, m_contactAcceleration;
    mutable DeviceBuffer<Vec3<Real>> m_snapshotX, m_snapshotV;  // mutable: a deferred snapshot is taken when read
    DeviceBuffer<unsigned char> m_homeForceScratch;  // force passes over every row on the home GPU
    DeviceBuffer<int32_t> m_needList;
    // A round's particles with events, two lists in turn (CollisionArgs::activeOut, activeIn), and the
    // marks of the particles that search in a later round (walker: zeroed when n changes, each mark
    // cleared by the search that reads it).
    DeviceBuffer<int32_t> m_activeLists;
    DeviceBuffer<unsigned char> m_walker;
    // The scattered search's offers (searchRound): zero between rounds.
    DeviceBuffer<unsigned long long> m_offeredEvents;
    bool m_scatteredSearch = true;  // CudaBackendOptions::scatteredSearch
    int64_t m_listedScatterMax = gpu::kListedScatterMax;  // CudaBackendOptions::listedScatterMax
    int m_sweepBlocks = 0;          // CudaBackendOptions::sweepBlocks
    bool m_moversFirst = true;      // CudaBackendOptions::moversFirst
    int m_searchRound = 0;  // the host-driven rounds' count this stage (findEvents)
    // Narrowed impact searches from this many particles (narrowSearch; CudaBackendOptions::narrowedSearchFrom).
    static constexpr int64_t kNarrowedSearchMin = int64_t(1) << 19;
    int64_t m_narrowedSearchFrom = kNarrowedSearchMin;
    bool m_skipUnmovedCellBuilds = true;  // CudaBackendOptions::skipUnmovedCellBuilds
    bool m_impactCandidates = true;       // CudaBackendOptions::impactCandidates
    int m_candidateSlots = gpu::kCandidateSlots;  // CudaBackendOptions::candidateSlots
    int64_t m_candidateRowsFrom = 32769;          // CudaBackendOptions::candidateRowsFrom
    DeviceCellList<Real> m_candidateCells;        // the rows' build (prepareCandidates)
    DeviceBuffer<int32_t> m_candidateRows, m_candidateCounts;
    DeviceBuffer<Vec3<Real>> m_candidateX;  // CandidateRows::xBuilt
    bool m_candidatesMade = false;          // rows made for the current state and model (setState, setModel clear it)
    bool m_roundsOnCandidates = false;      // the last rounds read rows: m_cellList is their build, not the positions'
    DeviceCellList<Real> m_contactCells;
    CellListView m_cellList{};  // of the last findEvents or listContacts
    bool m_cellsMatchPositions = false;  // m_cellList was built from the current positions
    bool m_eventsApplied = false;        // applyEvents ran since beginCollisions
    DeviceBuffer<unsigned int> m_roundCounters;  // runImpactRounds: counters [0..1] of each round queued
    PinnedBuffer<unsigned int> m_hostRoundCounts;  // a batch's counters, read back
    bool m_roundCountersZeroed = false;            // by beginCollisions' launch, for this stage's rounds
    // What a batch of rounds queues behind it to read with its wait (queueStageTail), and what of it
    // stands once its last round found nothing: the tally until the next stage, the listing's count
    // (for the resting contact it was made with) and the step check until the state changes.
    struct StageTail {
        bool tally = false, listing = false, check = false, checkForecast = false;
        RestingContact<double> resting{0, 0};
    };
    StageTail queueStageTail();
    void readStageTail(const StageTail& tail, bool applied);
    bool m_tailTally = false, m_tailListing = false;
    CollisionTally m_tailTallyValue;
    RestingContact<double> m_tailResting{0, 0};
    int64_t m_tailListed = 0;
    bool m_lastListingFound = false;           // the last listing found contacts (listContacts)
    ImpactWindow<double> m_stageWindow{0, 0};  // beginCollisions' window
    CellGeometry listingGeometry(const RestingContact<double>& resting) const;
    void countContacts(bool scan, unsigned long long* total = nullptr);
    void scanContacts();
    int m_lastImpactRounds = 0;                  // rounds of the last stage: the next one's first batch
    ImpactWindow<Real> m_window{0, 0};
    RestingContact<Real> m_resting{0, 0};
    DeviceBuffer<int64_t> m_contactStart, m_contactPartner;
    DeviceBuffer<Real> m_contactLambda;  // per listed contact: its accumulated impulse
    DeviceBuffer<Real> m_contactApplied;  // per listed contact: the extrapolated impulse the velocities hold
    int m_sweepsDone = 0;                 // sweeps since the listing: the momentum's index
    // Gauss-Seidel in colours (CudaBackendOptions::gaussSeidelContacts; contact_gauss_seidel.cu): the
    // listing's rows as the colouring leaves them, and its colours' bounds as the host read them.
    bool m_gaussSeidelContacts = true;
    bool m_gaussSeidel = false;  // the current listing is coloured: its sweeps are Gauss-Seidel
    DeviceBuffer<int64_t> m_rowParticle, m_rowMirror;
    DeviceBuffer<uint8_t> m_rowColour;
    // The colours of the warm rows (swapped with m_rowColour as the rows are) and whether their listing
    // was coloured; each own row's colour there (the fill's, for the colouring to keep: a later listing
    // of a step, and the first listing of a step that does not colour afresh, kFreshColouringSteps).
    DeviceBuffer<uint8_t> m_warmColour, m_prevColour;
    bool m_listingColoured = false, m_warmColoured = false;
    int64_t m_stepIndex = 0;  // beginStep's: which steps colour afresh
    DeviceBuffer<Real> m_rowTarget;
    // The own rows packed in colour order for the sweeps (gpu::ContactArgs::packed*), and each own row's place.
    DeviceBuffer<int32_t> m_packedParticle, m_packedPartner, m_rowRank;
    DeviceBuffer<int32_t> m_partnerScratch;  // the count's lists for the fill (ContactArgs::partnerScratch)
    DeviceBuffer<gpu::PackedBody<Real>> m_body;  // the contact phase's copy of X and V, 2n (ContactArgs::body)
    DeviceBuffer<Real> m_packedTarget, m_packedLambda;
    // The colouring's words (launchColourContacts), then the colours' starts.
    static constexpr size_t kColouringWords = 8;
    DeviceBuffer<unsigned int> m_colouringWords;
    PinnedBuffer<unsigned int> m_hostColouring;  // their copy
    DeviceBuffer<unsigned char> m_colouringScratch;
    std::vector<int32_t> m_colourStart;  // colours + 1 bounds of the packed rows
    double m_listedOverlap = -1;         // the colouring's measure of the listing (listedOverlap)
    // keepColours: rows keep the colours the fill put in m_prevColour (a later listing of a step).
    // The end of a relaxation and what the core reads after it, queued behind it (queueRelaxationTally).
    void queueEndOfRelaxation();
    bool queueStepCheck(double* kineticRow);
    bool queueRelaxationTally();
    void readRelaxationTally();
    bool colourListing(int64_t rows, bool keepColours, bool withKinetic);
    // Warm start (contact_relaxation.h): the last step's final rows, swapped in at beginCollisions.
    DeviceBuffer<int64_t> m_warmStart, m_warmPartner;
    DeviceBuffer<Real> m_warmLambda;
    bool m_listedThisStep = false;  // the current rows are this step's last listing (checkpoints read them)
    bool m_warmValid = false;       // m_warm* hold the last step's final rows
    bool m_firstListing = false;    // no listing yet in this step
    bool m_warmPending = false;     // the filled impulses are not applied to V yet
    DeviceBuffer<Vec3<Real>> m_xListed, m_dv, m_dx;
    DeviceBuffer<unsigned long long> m_residual;  // [speed change, overlap], double bits
    DeviceBuffer<unsigned long long> m_relaxationWords;  // relaxListing's outcome (gpu::launchRelaxListing)
    DeviceBuffer<unsigned char> m_contactScanScratch;
    DeviceBuffer<CollisionEvent> m_events;
    DeviceBuffer<char> m_active, m_hasContactAcceleration;
    DeviceBuffer<int32_t> m_wallMoved;  // StageOpening::moved
    // [0] particles needing a contact acceleration, [1] particles with an event, [2] contact log records
    DeviceBuffer<unsigned int> m_counters;
    DeviceBuffer<unsigned int> m_cellsMoved;  // a round's resolution moved a particle out of its cell (runImpactRounds)
    unsigned int m_needCount = 0;   // counters[0] of the last findEvents
    unsigned int m_eventCount = 0;  // counters[1] of the last findEvents: the next round resolves at most that many
    // The contact log (backend.h): records appended on the device by the resolution, in no order, and
    // sorted by (round, particle) on the device behind the batched rounds or when read (queueLogRead): no
    // read-back per round. Growing the buffer keeps what is
    // written, which the host bounds by counters[2] as findEvents reads it plus the events since.
    bool m_logContacts = false;  // asked for (setContactLog); m_logging: for this step, from beginCollisions
    double m_logMinImpulse = 0;  // setContactLog: impacts below this impulse are not recorded
    bool m_logging = false;
    DeviceBuffer<gpu::ImpactRecord<Real>> m_log;
    // The log's sorted copy, the sort's scratch and the host's copy (mutable: a read may sort).
    mutable DeviceBuffer<gpu::ImpactRecord<Real>> m_logSorted;
    mutable DeviceBuffer<unsigned char> m_logSortScratch;
    mutable PinnedBuffer<gpu::ImpactRecord<Real>> m_hostLog;
    size_t m_logBound = 0;       // records written this step, at most
    int32_t m_logRound = 0;      // applyEvents calls this step
    // The log's sort and copy to m_hostLog queued behind the batched rounds (runImpactRounds: the count is
    // known there), for the log as it stood after m_logQueuedRound rounds; -1: none queued this stage.
    mutable int32_t m_logQueuedRound = -1;
    mutable size_t m_logQueuedCount = 0;
    double m_stepDt = 0;         // the step the impacts' times are within [tau]
    // Read-back mailboxes in page-locked memory: words (event counts, collision kinds, residual bits,
    // health counts at kHealthWord..), health examples, block partial sums.
    static constexpr size_t kHostWords = 16, kHealthWord = 8;
    // The stage's tail is queued behind a batch of impact rounds only where the round before the batch
    // found at most this many events (queueStageTail); after more, a batch that does end the stage
    // leaves the calls after it up to three waits (the tally, the listing's count, the step check).
    static constexpr unsigned int kTailAfterEvents = 64;
    // The contact log's room for a batch of impact rounds (runImpactRounds): 256 MiB, 55 rounds of 10^5
    // particles, so that a landing's rounds to the cap (64) take few batches (with the rest of a cut batch
    // left whole to the next one, runImpactRounds: 55 and 9). With 64 MiB
    // (13 rounds) the sandbox example at 10^5 balls (an H200, fp32, one call) took 25.3 and 22.3 ms of
    // simulation a landing frame (frames 158 to 183) against 21.3 and 21.4.
    static constexpr size_t kLogBatchBytes = size_t(256) << 20;
    PinnedBuffer<unsigned long long> m_hostWords;
    PinnedBuffer<long long> m_hostHealthExamples;
    PinnedBuffer<double> m_hostPartials;
    DeviceBuffer<double> m_rows, m_partials, m_pairEnergy;
    // Impact rows: kImpulseRows x n (impulse_sums.h), then the kinetic energy each particle lost.
    DeviceBuffer<double> m_impactRows;  // and one row more: the one-wait step's kinetic row, summed with them
    int64_t m_impactRowsN = -1;  // n of the last stage: its rows are zero but where flagged (beginCollisions)
    DeviceBuffer<double> m_contactImpulses;  // kImpulseRows x n (impulse_sums.h), then the relaxation tally's two rows
    // What queueRelaxationTally read with a relaxation's wait: endRelaxation's kernels queued, the lift
    // work and impulse sums until contactImpulses takes them, the kinetic energy until the state changes.
    bool m_relaxationEnded = false, m_tallyRead = false, m_tallyForecast = false;
    double m_tallyLift = 0;
    ImpulseSums m_tallyImpulses;
    mutable bool m_kineticCached = false;  // cleared by homeChanged and beforeStateChange
    double m_cachedKinetic = 0;
    DeviceBuffer<ParticleInstance> m_instances;  // staging for host instance targets
};

}  // namespace corebox
