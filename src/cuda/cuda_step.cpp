// The CUDA backend's one-wait step (design note in cuda_device.h): the fused kick-drift and
// force-and-kick, the collision stage decided and resolved on the device within the screen's wait,
// the step check read with it, and the lists' forecast.
#include <algorithm>

#include "cuda_device.h"

namespace corebox {

template <class Real>
void CudaDevice<Real>::sizeStepBuffers() {
    const size_t doubles = kStepWordDoubles + size_t(kImpulseRows + 2) * size_t(partialBlocks());
    // On the stream (the legacy default stream does not order against it).
    if (m_stepMail.size() != doubles) {
        m_stepMail.resize(doubles);
        cudaCheck(cudaMemsetAsync(m_stepMail.data(), 0, doubles * sizeof(double), stream()), "memset");
    }
    m_hostStepMail.resize(doubles);
    m_wordsFresh = false;
    // The impact rows zero and nobody flagged, as after a stage: the device may open the first one.
    const size_t n = size_t(std::max<int64_t>(m_n, 1));
    m_impactRows.resize(size_t(kImpulseRows + 2) * n);
    m_hasContactAcceleration.resize(n);
    m_wallMoved.resize(n);
    cudaCheck(cudaMemsetAsync(m_impactRows.data(), 0, size_t(kImpulseRows + 2) * n * sizeof(double), stream()), "memset");
    cudaCheck(cudaMemsetAsync(m_hasContactAcceleration.data(), 0, n, stream()), "memset");
    m_impactRowsN = m_n;
}

template <class Real>
void CudaDevice<Real>::takeSnapshot() const {
    if (!m_snapshotPending) return;
    m_snapshotPending = false;
    const size_t bytes = size_t(m_n) * sizeof(Vec3<Real>);
    cudaCheck(cudaMemcpyAsync(m_snapshotX.data(), home().x.data(), bytes, cudaMemcpyDeviceToDevice, stream()), "snapshot");
    cudaCheck(cudaMemcpyAsync(m_snapshotV.data(), home().v.data(), bytes, cudaMemcpyDeviceToDevice, stream()), "snapshot");
}

template <class Real>
void CudaDevice<Real>::beforeStateChange(bool forcePassAtX) {
    takeSnapshot();
    forgetRunAhead();  // what ran ahead started from the state about to change
    m_runAhead.committed = false;
    m_lastWasKickDrift = false;
    m_checkCached = false;
    m_kineticCached = false;
    m_tallyRead = false;
    m_tailListing = false;  // counted at the positions about to change
    if (!forcePassAtX) {
        m_forecast.stage = 0;
        m_wordsFresh = false;
    }
    m_speculatedRefresh = false;
}

template <class Real>
void CudaDevice<Real>::kickDrift(double h, double dt) {
    if (!m_fusedSteps) {  // the separate operations, for comparison
        Backend::kickDrift(h, dt);
        return;
    }
    if (takeRunAhead(h, dt)) return;
    // The forecast was made for exactly this kick-drift: it survives it (and only it).
    const bool forecastHolds = m_forecast.stage == 1 && m_kickDriftKnown && h == m_kickDriftH && dt == m_kickDriftDt;
    const ListForecast forecast = m_forecast;
    const bool snapshot = m_snapshotPending;
    m_snapshotPending = false;
    beforeStateChange();  // takes no snapshot: the kernel below does
    m_snapshotPending = snapshot;  // until its launch went through
    if (forecastHolds) {
        m_forecast = forecast;
        m_forecast.stage = 2;
    }
    scatterFromHome();
    const bool resetWords = gpuCount() == 1;  // for the screening pass that follows
    onEachGpu([&](int k, Replica<Real>& r) {
        const DeviceSlice& s = slice(k);
        gpu::KickDriftArgs<Real> a{};
        a.x = a.xOut = r.x.data() + s.begin;
        a.v = a.vOut = r.v.data() + s.begin;
        a.a = r.acceleration.data();
        a.n = s.size();
        a.h = Real(h);
        a.dt = Real(dt);
        a.snapshotX = snapshot ? m_snapshotX.data() : nullptr;
        a.snapshotV = snapshot ? m_snapshotV.data() : nullptr;
        a.reset = resetWords ? stepWords() : nullptr;
        gpu::launchKickDrift(a, s.stream);
    });
    m_snapshotPending = false;
    m_wordsFresh = resetWords;
    m_kickDriftH = h;
    m_kickDriftDt = dt;
    m_kickDriftKnown = true;
    m_accelerationMatchesX = false;
    m_listAtX = false;
    m_homeCurrent = gpuCount() == 1;
    m_lastWasKickDrift = true;
}

template <class Real>
void CudaDevice<Real>::accelerateAndKick(double h) {
    if (!m_fusedSteps) {
        Backend::accelerateAndKick(h);
        return;
    }
    if (m_runAhead.committed) {  // the pass ran ahead with the kick of the kickDrift it followed
        m_runAhead.committed = false;
        if (h != m_runAhead.h) throw std::logic_error("accelerateAndKick: the step that ran ahead kicked by another h");
        return;
    }
    m_verletSteps = m_lastWasKickDrift && h == m_kickDriftH;
    beforeStateChange(true);
    if (!forcePass(-1, true, h)) kick(h);
}

template <class Real>
bool CudaDevice<Real>::screensAtX() const {
    return gpuCount() == 1 && useLists() && m_screenGap >= 0 && screenReach(2 * m_model.maxRadius(), m_screenGap) < m_model.cutoff;
}

template <class Real>
void CudaDevice<Real>::forgetRunAhead() {
    if (m_runAhead.launched && m_runAhead.open && ++m_runAheadsForgotten >= 2) {
        m_runAheadsForgotten = 0;
        m_runAheadPause = 32;
    }
    m_runAhead.launched = false;
}

// The next step's kickDrift and force pass, behind the device's gate (design note in cuda_device.h),
// into the ahead buffers: what kickDrift(m_kickDriftH, m_kickDriftDt) and accelerateAndKick would
// launch, but for where they write.
template <class Real>
bool CudaDevice<Real>::launchRunAhead(bool build) {
    cudaStream_t s = stream();
    Replica<Real>& r = home();
    const size_t n = size_t(m_n);
    DeviceBuffer<Vec3<Real>>* const buffers[] = {&m_aheadX, &m_aheadV, &m_aheadA, &m_aheadSnapshotX, &m_aheadSnapshotV};
    try {  // five more arrays of n (and lists): where they do not fit, the steps go on without running ahead
        for (DeviceBuffer<Vec3<Real>>* b : buffers) b->resize(n);
        m_aheadMail.resize(m_stepMail.size());
    } catch (const DeviceError&) {
        cudaGetLastError();  // the failed cudaMalloc's error, which the next launch check would report
        for (DeviceBuffer<Vec3<Real>>* b : buffers) *b = DeviceBuffer<Vec3<Real>>();
        m_runAheadEnabled = false;
        return false;
    }
    // Each kernel reads this step's words for the gate; the step ahead resets and screens its own.
    gpu::StepWords* const aheadWords = reinterpret_cast<gpu::StepWords*>(m_aheadMail.data());
    gpu::StageGate gate{};
    gate.runAheadOf = stepWords();
    gate.freshLists = build;
    gpu::KickDriftArgs<Real> a{};
    a.x = r.x.data();
    a.v = r.v.data();
    a.a = r.acceleration.data();
    a.xOut = m_aheadX.data();
    a.vOut = m_aheadV.data();
    a.n = m_n;
    a.h = Real(m_kickDriftH);
    a.dt = Real(m_kickDriftDt);
    a.snapshotX = m_aheadSnapshotX.data();
    a.snapshotV = m_aheadSnapshotV.data();
    a.reset = aheadWords;
    a.gate = gate;
    gpu::launchKickDrift(a, s);
    gpu::ForceArgs<Real> f = forceArgs(0, m_aheadX.data(), m_aheadA.data());
    if (build) {
        // Lists of their own at the positions ahead, not waited for: where the gate is shut they are
        // built from stale positions and never used; where a row overflows their columns, the pass
        // below does not run and the step's words say so (resolveOnDevice then does it again).
        try {
            m_aheadList.invalidate();
            m_aheadList.setColumns(m_aheadListColumns > 0 ? m_aheadListColumns : r.list.columns());
            m_aheadList.update(m_aheadX.data(), m_n, 0, m_n, m_box, m_model.cutoff, m_model.skin, s,
                               DeviceNeighbourList<Real>::Displacement::Unknown, &aheadWords->listOverflow);
        } catch (const DeviceError&) {
            if (cudaGetLastError() != cudaErrorMemoryAllocation) throw;  // only a list that does not fit turns this off
            m_aheadList.invalidate();
            m_runAheadEnabled = false;
            return false;  // the kick-drift queued above wrote only the ahead buffers
        }
        m_aheadList.fillUnchecked(f);
        gate.clear = &aheadWords->listOverflow;
    } else {
        r.list.fillUnchecked(f);  // gated: runAheadOpen reads the overflow of an unchecked build
    }
    f.kickV = m_aheadV.data();
    f.kickH = Real(m_kickDriftH);
    f.screen = aheadWords->screen;
    f.box = m_box;
    f.contactGap = Real(m_screenGap);
    f.gate = gate;
    launchTimedForces(f);
    m_runAhead = RunAhead{true, false, false, build, m_kickDriftH, m_kickDriftDt};
    return true;
}

// kickDrift(h, dt) where the step ran ahead: the ahead buffers become the state, as the kickDrift and
// force pass that ran would have left it.
template <class Real>
bool CudaDevice<Real>::takeRunAhead(double h, double dt) {
    // Not this step's: kickDrift's beforeStateChange forgets it.
    if (!(m_runAhead.launched && m_runAhead.open && h == m_runAhead.h && dt == m_runAhead.dt && gpuCount() == 1)) return false;
    const bool built = m_runAhead.built;
    m_runAhead = RunAhead{};
    m_runAheadsForgotten = 0;
    if (m_snapshotPending) {  // the state before this step, as the kernel that ran ahead kept it
        std::swap(m_snapshotX, m_aheadSnapshotX);
        std::swap(m_snapshotV, m_aheadSnapshotV);
        m_snapshotPending = false;
    }
    Replica<Real>& r = home();
    std::swap(r.x, m_aheadX);
    std::swap(r.v, m_aheadV);
    std::swap(r.acceleration, m_aheadA);
    std::swap(m_stepMail, m_aheadMail);  // the words the kickDrift that ran reset and its pass screened
    if (built) {
        r.list.swap(m_aheadList);
        m_takenListsUnchecked = true;  // resolveOnDevice reads their overflow with the words (settleUncheckedLists elsewhere)
    }
    m_checkCached = m_kineticCached = m_tallyRead = false;
    m_forecast.stage = 0;
    m_speculated = m_speculatedRefresh = false;
    m_wordsFresh = true;  // reset by the kickDrift that ran, screened by the pass
    m_kickDriftH = h;
    m_kickDriftDt = dt;
    m_kickDriftKnown = true;
    m_lastWasKickDrift = false;
    m_homeCurrent = true;
    ++m_fullPasses;
    ++m_stepsRunAhead;
    m_accelerationMatchesX = true;
    m_screenPending = true;
    m_listAtX = true;
    m_accelerationIncremental = false;
    m_runAhead.committed = true;
    m_runAhead.h = h;
    return true;
}

// The stage on the device (design note in cuda_device.h): one GPU, the screen of the pass at X in
// hand, no contact log, the impact rows of the last stage zero but where flagged.
template <class Real>
bool CudaDevice<Real>::canResolveOnDevice() const {
    return m_fusedSteps && gpuCount() == 1 && !m_logContacts && m_impactRowsN == m_n && useLists() &&
           home().list.builtPositions() != nullptr && m_listAtX && m_wordsFresh;
}

template <class Real>
StageScreen CudaDevice<Real>::resolveOnDevice(const ImpactWindow<double>& window) {
    beforeStateChange();  // the walls may move particles
    cudaStream_t s = stream();
    gpu::StepWords* w = stepWords();
    Replica<Real>& r = home();
    // The verdict, the stage opened and the walls resolved (as beginCollisions and resolveWallImpacts
    // would for WallsOnly), and each particle checked, in one pass.
    m_window = ImpactWindow<Real>{Real(window.maxRewind), Real(window.restingSpeed)};
    m_cellList = emptyCells();
    m_logging = false;
    const Real halfSkin2 = Real(0.25 * m_model.skin * m_model.skin);
    const size_t n = size_t(m_n);
    double* kineticRow = m_impactRows.data() + size_t(kImpulseRows + 1) * n;
    const gpu::ListForecastArgs<Real> forecast = listForecastArgs();
    const gpu::StageOpening<Real> opening{w, screenScales(m_screenGap), RestingContact<Real>{Real(window.restingSpeed), Real(m_screenGap)},
                                          kineticRow, m_wallMoved.data(), forecast};
    gpu::launchStageWalls(collisionArgs(), r.acceleration.data(), Real(m_screenGap), r.list.builtPositions(), halfSkin2, opening, s);
    // In one launch: the tally's rows (only the flagged particles') and the kinetic row summed, and the
    // refresh of the accelerations the walls changed, as refreshAccelerations would run it, when the
    // lists still hold every moved particle's partners, with the forecast of the rows it changes.
    const int blocks = partialBlocks();
    const gpu::BlockSumArgs sums{m_impactRows.data(), m_n, m_stepMail.data() + kStepWordDoubles, blocks, m_hasContactAcceleration.data(),
                                 kImpulseRows + 1};
    const gpu::StageGate refresh{&w->stage, gpu::stageBit(StageScreen::WallsOnly), &w->wallStats[2]};
    gpu::ForceArgs<Real> f = forceArgs(0, r.x.data(), r.acceleration.data());
    r.list.fillUnchecked(f);  // an overflow of lists built ahead left the screen quiet: the refresh shut
    f.forecast = forecast;
    f.gate = refresh;
    gpu::launchStageSumsAndRefresh(sums, kImpulseRows + 2, f, m_wallMoved.data(), &w->wallMoved, r.list.columns(), s);
    const bool forecastMade = forecast.moves != nullptr;
    // The words come back on a stream of their own, beside the step that runs ahead (nothing of it
    // writes them: its gate reads them), so the copy's latency is not between the two on the device.
    cudaCheck(cudaEventRecord(m_stageDone, s), "event");
    cudaCheck(cudaStreamWaitEvent(m_mailStream, m_stageDone, 0), "event");
    cudaCheck(cudaMemcpyAsync(m_hostStepMail.data(), m_stepMail.data(), m_stepMail.size() * sizeof(double), cudaMemcpyDeviceToHost,
                              m_mailStream),
              "step words");
    cudaCheck(cudaEventRecord(m_mailCopied, m_mailStream), "event");
    bool runAhead = m_runAheadEnabled && forecastMade && m_verletSteps && m_kickDriftKnown && screensAtX();
    if (runAhead && m_runAheadPause > 0) {
        --m_runAheadPause;
        runAhead = false;
    }
    // The lists built ahead where the last forecast's hint says the step after this one moves past half
    // the skin (and nothing rebuilt them since): that step then runs ahead too.
    const bool buildAhead = m_buildAheadHint && m_buildAheadHintId == r.list.buildId();
    if (runAhead) runAhead = launchRunAhead(buildAhead);
    cudaCheck(cudaEventSynchronize(m_mailCopied), "step words");

    m_wordsFresh = false;
    const gpu::StepWords& words = hostStepWords();
    if (m_takenListsUnchecked) {
        m_takenListsUnchecked = false;
        if (words.listOverflow != 0) {
            // The lists this step built ahead had too few columns: its force pass and kick did not run,
            // the screen stayed quiet and nothing ran after it. Built again with more, the pass, then
            // the stage (once: the lists are checked now).
            redoOverflowedPass();
            return resolveOnDevice(window);
        }
        r.list.checked(false, s);
    }
    m_buildAheadHint = words.listHint != 0 && words.listForecast == 0;
    m_buildAheadHintId = r.list.buildId();
    m_runAhead.open = runAhead && gpu::runAheadOpen(words, m_runAhead.built);
    const StageScreen verdict = StageScreen(words.stage);
    // The check read the state as the stage leaves it on the device: as it is now for Quiet and
    // WallsOnly, as the integration left it for Full (which the rounds may yet change: beforeStateChange).
    m_cachedCheck = stepCheckOf(words, m_hostStepMail.data() + kStepWordDoubles + size_t(kImpulseRows + 1) * size_t(blocks));
    m_checkCached = true;
    readForecast(forecastMade, words);
    if (verdict == StageScreen::Quiet) skipQuietStage();
    if (verdict != StageScreen::WallsOnly) return verdict;
    // resolveWallImpacts reads the rest from the words.
    m_pairsClearNext = true;
    m_speculated = true;
    m_speculatedWindow = window;
    m_speculatedRefresh = words.wallStats[2] == 0;
    return verdict;
}

// A step taken from lists built ahead that overflowed (StepWords::listOverflow): the lists built again
// with more columns, then the force pass and kick that did not run (the state is the kick-drift's).
template <class Real>
void CudaDevice<Real>::redoOverflowedPass() {
    home().list.checked(true, stream());
    cudaCheck(cudaMemsetAsync(&stepWords()->listOverflow, 0, sizeof(unsigned int), stream()), "memset");
    beforeStateChange(true);
    if (!forcePass(-1, true, m_kickDriftH)) kick(m_kickDriftH);
}

// Lists built ahead and taken whose stage does not go through resolveOnDevice: their overflow read
// here, with a wait.
template <class Real>
void CudaDevice<Real>::settleUncheckedLists() {
    if (!m_takenListsUnchecked) return;
    m_takenListsUnchecked = false;
    unsigned int overflow = 0;
    cudaCheck(cudaMemcpyAsync(&overflow, &stepWords()->listOverflow, sizeof overflow, cudaMemcpyDeviceToHost, stream()), "list overflow");
    sync();
    if (overflow != 0) redoOverflowedPass();
    else home().list.checked(false, stream());
}

// The walls' tally and stats as resolveOnDevice brought them back (still in m_hostStepMail: nothing is
// copied back between the screen and the stage's calls), for resolveWallImpacts.
template <class Real>
int CudaDevice<Real>::readResolvedWalls() {
    const gpu::StepWords& words = hostStepWords();
    m_wallTally = tallyOf(words.kindCounts, sumPartials(m_hostStepMail.data() + kStepWordDoubles, kImpulseRows + 1, partialBlocks()));
    // The contact listing would find the wall contacts the device counted, and no pair (the screen).
    m_wallContactsPossible = words.wallStats[1] != 0 && words.wallContacts != 0;
    m_wallsCountedOnDevice = true;
    m_listAtX = m_listAtX && words.wallStats[2] == 0;
    return int(words.wallStats[0]) + 1;
}

template <class Real>
gpu::ListForecastArgs<Real> CudaDevice<Real>::listForecastArgs() {
    gpu::ListForecastArgs<Real> f{};
    // One GPU, lists built, Verlet's step known: the next kickDrift repeats the last.
    Replica<Real>& r = home();
    if (!(m_fusedSteps && gpuCount() == 1 && useLists() && m_kickDriftKnown && r.list.builtPositions() != nullptr)) return f;
    f.v = r.v.data();
    f.xBuilt = r.list.builtPositions();
    f.h = Real(m_kickDriftH);
    f.dt = Real(m_kickDriftDt);
    // Below the lists' own test by far more than the rounding of a position, so that the forecast
    // never says "within" where the check after the drift would say "beyond".
    f.limit2 = Real(0.25 * m_model.skin * m_model.skin * (1 - 1e-3));
    f.moves = &stepWords()->listForecast;
    f.hint = m_runAheadEnabled ? &stepWords()->listHint : nullptr;
    return f;
}

template <class Real>
StepCheck CudaDevice<Real>::stepCheckOf(const gpu::StepWords& words, const double* partials) const {
    StepCheck check;
    check.kinetic = sumPartials(partials, 1, partialBlocks())[0];
    check.health = healthReportOf(words.healthCounts, words.healthExamples);
    return check;
}

template <class Real>
void CudaDevice<Real>::readForecast(bool made, const gpu::StepWords& words) {
    m_forecast = ListForecast{};
    if (!made) return;
    m_forecast.stage = 1;
    m_forecast.beyondHalfSkin = words.listForecast != 0;
    m_forecast.buildId = home().list.buildId();
}

template <class Real>
gpu::StepCheckArgs<Real> CudaDevice<Real>::stepCheckArgs(double* kineticRow) {
    gpu::StepWords* w = stepWords();
    gpu::StepCheckArgs<Real> a{};
    a.health.p = arrays();
    a.health.box = m_box;
    a.table = table();
    a.acceleration = home().acceleration.data();
    a.forecast = listForecastArgs();
    a.health.counts = w->healthCounts;
    a.health.examples = w->healthExamples;
    a.kineticRow = kineticRow;
    return a;
}

template <class Real>
StepCheck CudaDevice<Real>::checkStep() {
    if (m_checkCached) {  // read with the screen's or the rounds' wait, and nothing changed since
        m_checkCached = false;
        return m_cachedCheck;
    }
    // The health counts, the kinetic row's block partials and the forecast, read back with one wait.
    gatherToHome();
    forgetRunAhead();  // its words are about to be written
    cudaStream_t s = stream();
    m_rows.resize(size_t(m_n));
    const bool forecast = queueStepCheck(m_rows.data());
    gpu::launchBlockSums(m_rows.data(), 1, m_n, m_stepMail.data() + kStepWordDoubles, s);
    const size_t doubles = kStepWordDoubles + size_t(partialBlocks());
    cudaCheck(cudaMemcpyAsync(m_hostStepMail.data(), m_stepMail.data(), doubles * sizeof(double), cudaMemcpyDeviceToHost, s), "step words");
    sync();
    readForecast(forecast, hostStepWords());
    return stepCheckOf(hostStepWords(), m_hostStepMail.data() + kStepWordDoubles);
}

// The step check of the current state queued: its health counts and forecast into the step words (cleared
// first), each particle's kinetic energy into kineticRow; returns whether it made a forecast.
template <class Real>
bool CudaDevice<Real>::queueStepCheck(double* kineticRow) {
    cudaStream_t s = stream();
    gpu::StepWords* w = stepWords();
    m_wordsFresh = false;
    cudaCheck(cudaMemsetAsync(w->healthCounts, 0, sizeof w->healthCounts, s), "memset");
    cudaCheck(cudaMemsetAsync(&w->listForecast, 0, sizeof w->listForecast, s), "memset");
    const gpu::StepCheckArgs<Real> a = stepCheckArgs(kineticRow);
    gpu::launchStepCheck(a, s);
    return a.forecast.moves != nullptr;
}

template class CudaDevice<float>;
template class CudaDevice<double>;

}  // namespace corebox
