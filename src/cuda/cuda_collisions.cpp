// The CUDA backend's collision rounds: the cell list rebuilt each round, every particle's earliest
// event (kernels/collision_kernels.cu), end-of-step accelerations of the particles about to be
// resolved, and the resolution of the mutual-earliest matching. With several GPUs all of it runs on
// the home GPU on the gathered state (design note in cuda_device.h). One host read-back per round (the
// counts of findEvents), or, without pair forces, one per batch of rounds (runImpactRounds); one for
// the tally of the step (none when nothing was resolved) and, when the contact log is on, one when it
// is read; everything else stays on the stream. Impulses for the
// pressure observables (impulse_sums.h) go into per-particle rows, summed in a fixed order when the
// tally is read.
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

#include "cuda_device.h"

namespace corebox {
namespace {

// The first listing of a step keeps the colours the last step's listing gave the pairs it lists again
// that pushed (the fill takes them, the colouring colours only the rows left: contact_gauss_seidel.cu),
// but every kFreshColouringSteps-th step colours afresh, counted from the simulation's start
// (Backend::beginStep), so that a restart does the same; checkpoints and World edits carry the colours
// with the impulses (ContactCarryOver: the pushing pairs', the records they carry anyway). Evidence (an
// H200, fp32), first from a trial that kept the colours of every pair listed again, pushing or not.
// Kept for ever, the same colours in the same order step after step bias the same chains of a settled
// pile: the 400-ball test pile fell onto its lower layers at 0.0104 a ball a step where 0.0102 is
// allowed (DenseContact.ASettledPileHoldsEveryLayer). Coloured afresh every 2 / 4 / 8 steps, it fell at
// 0.0076 / 0.0041 / 0.0077 (every step, as before: 0.0069); `corebox bench pile` (one
// call, every step / never / every 2 / 4 / 8 steps) 10^6 balls 47.5 / 43.7 / 44.9 / 44.3 / 44.0 ms a
// frame (the last second 39.9 / 34.4 / 36.5 / 35.3 / 34.6), 10^5 balls 11.0 / 10.6 / 10.5 / 10.5
// (every step / never / 2 / 4), 10^4 5.7 / 5.6 / 5.5 / 5.5, every pile at rest as early, overlaps
// within 4e-4 of a diameter. As kept (the first listing of a step keeps the pushing pairs' colours, a
// later one every pair's, every 4th step afresh): the test pile 0.0048; 10^6 balls 44.5 ms a frame (the
// last second 35.9, its listings 10.5 ms a frame against 14.1), 10^5 10.7, 10^4 5.5 (another call).
// Tried and not kept: the colours swept in a new random order each step,
// kept or fresh, so that no chain is favoured: the test pile fell at 0.0127 and 0.0143 (the greedy
// colouring's colour 0 holds the most rows; swept first it carries the most support).
constexpr int64_t kFreshColouringSteps = 4;

}  // namespace

template <class Real>
gpu::CollisionArgs<Real> CudaDevice<Real>::collisionArgs() {
    gpu::CollisionArgs<Real> a{};
    a.p = arrays();
    a.table = table();
    a.box = m_box;
    a.events = m_events.data();
    a.active = m_active.data();
    a.contactAcceleration = m_contactAcceleration.data();
    a.hasContactAcceleration = m_hasContactAcceleration.data();
    a.needList = m_needList.data();
    a.counters = m_counters.data();
    a.kindCounts = stepWords()->kindCounts;
    a.impulses = m_impactRows.data();
    a.loss = m_impactRows.data() + size_t(kImpulseRows) * size_t(m_n);
    a.restitution = Real(m_model.restitution);
    a.wallRestitution = Real(m_model.wallRestitution);
    a.elasticBelow = Real(m_model.elasticBelowSpeed);
    a.window = m_window;
    a.grid = m_cellList;
    a.log = m_logging ? m_log.data() : nullptr;
    a.logCount = m_counters.data() + 2;
    a.logRound = m_logRound;
    a.logMinImpulse = m_logMinImpulse;
    a.activeOut = nullptr;
    a.walker = nullptr;
    a.activeIn = nullptr;
    a.activeInCount = nullptr;
    a.listedScatterMax = 0;
    a.clearActiveIn = false;
    a.cellKeys = nullptr;
    a.cellsMoved = nullptr;
    return a;
}

// Round `round` of a stage's searches: lists its particles with events in one of the two lists, and
// after the first round marks the particles near the last round's (CollisionArgs::walker) before its
// search, where few are active (collision_kernels.cu: narrowed). Not where no pair can meet (the
// search's cells are empty: every search is then the walls'), nor below kNarrowedSearchMin (524,288)
// particles (m_narrowedSearchFrom), where the marks cost what they save. lastCount: the round before's
// count of particles with events, on the device, where neither this round's search nor anything
// queued before it writes it.
// Measured on an H200 (fp32, each pair in the same call, the same bits). Marks in every later round:
// `corebox bench pile` 10^6 balls 104.7 ms a frame instead of 112.1 (the last second 58.6 instead of
// 62.9), 10^5 balls 28.2 instead of 26.3, table1's N = 1024 0.154 ms a step instead of 0.137 (a launch
// more a round). Narrowed only where fewer than one particle in eight is active, from 65,536 particles:
// 10^6 balls 104.8 against 114.6 (59.0 and 63.7), 10^5 29.5 against 27.1 (13.2 and 12.3), N = 1024
// 0.136 against 0.135, N = 65536 7.893 against 7.883; the sandbox example at 10^5 balls (`--headless
// --backend cuda --scripted`) 40.9 ms of simulation a frame against 38.7. Hence from 2^19 particles.
template <class Real>
bool CudaDevice<Real>::narrowsSearch(int round) const {
    return round > 0 && narrowableStage();
}

// Whether this stage's searches may look from a few particles (narrowed or scattered): pairs to find, and
// enough particles.
template <class Real>
bool CudaDevice<Real>::narrowableStage() const {
    return !m_pairsClear && m_n >= m_narrowedSearchFrom;
}

template <class Real>
void CudaDevice<Real>::narrowSearch(gpu::CollisionArgs<Real>& a, int round, const unsigned int* lastCount, cudaStream_t s) {
    const size_t n = size_t(m_n);
    a.activeOut = m_activeLists.data() + size_t(round % 2) * n;
    if (!narrowsSearch(round)) return;
    a.walker = m_walker.data();
    a.activeIn = m_activeLists.data() + size_t((round + 1) % 2) * n;
    a.activeInCount = lastCount;
    gpu::launchMarkSearchers(a, s);
}

// Round `round`'s search. Where it would be narrowed (narrowsSearch), in fp32 and a thread a particle,
// it is scattered instead: the last round's active particles alone search and offer their inactive
// neighbours the pairs' events (gpu::launchScatteredSearch), with no marks; else every particle searches,
// or those near an active one (narrowSearch, gpu::launchFindEvents), where few are active from the last
// round's list (scattersSparseRounds). The same bits each way
// (tests/gpu/test_cuda_contacts.cpp). Measured on an H200 (fp32, kernel times from CUPTI,
// scripts/kernel-times): at 10^6 balls a landing's later round searched in 77 us (66 the scatter, 11 the
// offers) against 101 (22 the marks, 79 the narrowed search), a settled pile's in 27 against 39 (a
// stage's first search, by every particle, about 310 us either way); `corebox bench pile` 10^6 balls
// 39.9 ms a frame against 41.4 to 42.0 the same day (the last second 34.0 against 34.4 to 34.6). Not
// below the narrowing's 2^19 particles, where every particle searched: the sandbox example at 10^5 balls
// took 12.7 ms a frame against 12.1 to 12.3 (a landing's rounds keep most particles active), the
// 10^5-ball pile 10.4 against 10.3.
// A stage's first round scatters too where the later ones would, when not every particle starts active
// (under gravity: startsActive): a settled pile's few movers search, not every ball. An H200, fp32, the
// settled 10^6-ball pile (CUPTI kernel times): 42 us a round on average over a step's 7 rounds against
// 67 with the first by every particle (about 310 us); `corebox bench pile` 3.3 ms a frame in its
// impacts against 3.8 over the settled frames, 39.8 ms a frame against 39.7 to 40.1 over the 5 s.
template <class Real>
bool CudaDevice<Real>::scattersSearch(int round) const {
    const bool few = narrowableStage() && (round > 0 || (m_moversFirst && m_window.restingSpeed > Real(0)));
    return std::is_same<Real, float>::value && m_scatteredSearch && few && gpu::searchWalksAlone(m_n) &&
           m_n < INT32_MAX;
}

// Whether a stage whose rounds every particle searches (not narrowableStage) scatters its sparse ones
// from the round before's list (gpu::launchSparseOrFullSearch): fp32, pairs to find, and particles
// enough that a thread walks each alone.
template <class Real>
bool CudaDevice<Real>::scattersSparseRounds() const {
    return std::is_same<Real, float>::value && m_scatteredSearch && m_listedScatterMax > 0 && !m_pairsClear &&
           !narrowableStage() && gpu::searchWalksAlone(m_n) && m_n < INT32_MAX;
}

template <class Real>
void CudaDevice<Real>::searchRound(gpu::CollisionArgs<Real>& a, int round, const unsigned int* lastCount,
                                   cudaStream_t s) {
    if constexpr (std::is_same<Real, float>::value) {
        // This round lists its particles with events; the round before's list, where there is one, may be
        // scattered from (CollisionArgs::listedScatterMax).
        auto useLists = [&] {
            a.activeOut = m_activeLists.data() + size_t(round % 2) * size_t(m_n);
            if (round == 0 || !lastCount) return;
            a.activeIn = m_activeLists.data() + size_t((round + 1) % 2) * size_t(m_n);
            a.activeInCount = lastCount;
            a.listedScatterMax = m_listedScatterMax;
        };
        if (scattersSearch(round)) {
            useLists();
            // The collection clears the round before's flags (runImpactRounds' listed resolution then leaves
            // them; the host-driven rounds' resolution sets every particle's after it).
            a.clearActiveIn = a.activeIn && narrowsSearch(round);
            gpu::launchScatteredSearch(a, m_offeredEvents.data(), s);
            return;
        }
        if (round > 0 && lastCount && scattersSparseRounds()) {
            useLists();
            gpu::launchSparseOrFullSearch(a, m_offeredEvents.data(), s);
            return;
        }
    }
    narrowSearch(a, round, lastCount, s);
    gpu::launchFindEvents(a, s);
}

template <class Real>
CellListView CudaDevice<Real>::emptyCells() {
    if (m_emptyCellStart.size() < 2) {
        const int32_t none[2] = {0, 0};
        m_emptyCellStart.upload(none, 2);
    }
    if (m_indexOrder.size() != size_t(m_n)) {
        std::vector<int32_t> order(static_cast<size_t>(m_n));
        std::iota(order.begin(), order.end(), 0);
        m_indexOrder.upload(order.data(), order.size());
    }
    CellListView view{};
    view.geometry = CellGeometry{{1, 1, 1}, {0.0, 0.0, 0.0}};
    view.cellStart = m_emptyCellStart.data();
    view.sorted = m_indexOrder.data();
    return view;
}

// The screen of the last list pass at X (kernels/neighbour_list_kernels.cu, ForceArgs::screen), one
// read-back. From it, a lower bound on every pair's clearance beyond its reach: the listed pairs'
// smallest R / reach, and the cutoff for the rest (lists hold every pair closer than it).
//   - no pair within reach and no particle within reach of a wall: the impact rounds would find no
//     event and the contact phase list nothing, so the stage is skipped and the backend left as an
//     empty stage leaves it (no contact log, no warm start);
//   - no pair within reach, some particles at walls: a wall event moves its particle back by at most
//     (1 + e_w) times its depth on each axis, the contact phase by its depth, so when the clearance
//     exceeds 8 times the deepest wall depth no pair can meet in this stage: the stage runs with walls
//     only (no cell list built, the searches' pair loops empty), the same events in the same order;
//   - otherwise the whole stage.
// An LJ fluid of 10^6 particles in a walled box on an H200 spent about 1 ms a step in the stage, most
// of it in the per-round cell lists, for a few hundred wall hits a step. The first call only learns the
// gap the screen is to use. With fused steps the device reads the screen itself and resolves a quiet or
// walls-only stage within the same wait (resolveOnDevice, cuda_step.cpp).
template <class Real>
StageScreen CudaDevice<Real>::screenStage(const ImpactWindow<double>& window, double contactGap) {
    const bool screened = m_screenPending && m_accelerationMatchesX && contactGap == m_screenGap;
    if (!(screened && canResolveOnDevice())) settleUncheckedLists();  // resolveOnDevice reads it with the words
    m_screenGap = contactGap;
    m_screenPending = false;
    m_pairsClearNext = false;
    m_speculated = false;
    if (!screened) return StageScreen::Full;
    if (canResolveOnDevice()) return resolveOnDevice(window);
    unsigned int* words = reinterpret_cast<unsigned int*>(m_hostWords.resize(kHostWords));
    cudaCheck(cudaMemcpyAsync(words, stepWords()->screen, 3 * sizeof(unsigned int), cudaMemcpyDeviceToHost, stream()), "screen");
    sync();
    const StageScreen verdict = screenVerdict(words, screenScales(contactGap));
    if (verdict == StageScreen::WallsOnly) m_pairsClearNext = true;
    if (verdict == StageScreen::Quiet) skipQuietStage();
    return verdict;
}

template <class Real>
ScreenScales CudaDevice<Real>::screenScales(double contactGap) const {
    const double smallestRadius = m_model.radius.empty() ? 0.0 : *std::min_element(m_model.radius.begin(), m_model.radius.end());
    return ScreenScales{smallestRadius, m_model.maxRadius(), m_model.cutoff, contactGap};
}

template <class Real>
void CudaDevice<Real>::skipQuietStage() {
    m_listedThisStep = m_warmValid = false;  // nothing listed: no warm start for the next step
    m_logging = m_logContacts;
    m_logBound = 0;
    m_logRound = 0;
    m_logQueuedRound = -1;
    m_eventsApplied = false;
    m_cellsMatchPositions = false;
}

template <class Real>
void CudaDevice<Real>::beginCollisions(const ImpactWindow<double>& window) {
    // A stage the device resolved within the screen's wait began there (resolveOnDevice): what follows
    // is the host's side of it.
    const bool resolved = m_speculated;
    if (resolved && (window.maxRewind != m_speculatedWindow.maxRewind || window.restingSpeed != m_speculatedWindow.restingSpeed))
        throw std::logic_error("beginCollisions: the window differs from the one screenStage was given");
    m_screenPending = false;
    m_stageWindow = window;
    m_tailTally = m_tailListing = false;
    m_pairsClear = m_pairsClearNext;
    m_pairsClearNext = false;
    m_wallsAtOnce = m_wallsOnlyMoved = false;
    m_wallContactsPossible = true;
    m_wallsCountedOnDevice = false;
    gatherToHome();
    m_cellsMatchPositions = false;  // the integration moved everything
    m_roundsOnCandidates = false;
    m_window = ImpactWindow<Real>{Real(window.maxRewind), Real(window.restingSpeed)};
    const size_t n = size_t(m_n);
    m_events.resize(n);
    m_active.resize(n);
    m_hasContactAcceleration.resize(n);
    m_needList.resize(n);
    m_activeLists.resize(2 * n);
    if (m_walker.size() != n) {  // a new count of particles: no marks yet
        m_walker.resize(n);
        cudaCheck(cudaMemsetAsync(m_walker.data(), 0, n, stream()), "memset");
    }
    if ((scattersSearch(1) || scattersSparseRounds()) &&
        m_offeredEvents.size() != n) {  // a new count of particles: no offers yet
        m_offeredEvents.resize(n);
        cudaCheck(cudaMemsetAsync(m_offeredEvents.data(), 0, n * sizeof(unsigned long long), stream()), "memset");
    }
    m_searchRound = 0;
    m_impactRows.resize(size_t(kImpulseRows + 2) * n);  // the last row: the one-wait step's kinetic row (cuda_step.cpp)
    m_eventsApplied = false;
    cudaStream_t s = stream();
    m_refreshable = m_accelerationMatchesX && gpuCount() == 1;
    m_accelerationMatchesX = false;  // until refreshAccelerations or a full pass
    // Walls at once (resolveWallImpacts): the particles that move are those it flags, so neither the
    // copy of X that tells the refresh who moved nor the round's active flags are needed.
    m_wallsAtOnce = m_pairsClear && m_refreshable && !m_logContacts;
    if (resolved && !m_wallsAtOnce) throw std::logic_error("beginCollisions: the device resolved the walls of a stage the host would not");
    if (resolved) {
        m_impactRowsN = m_n;
        m_logging = false;
        m_logBound = 0;
        m_logRound = 0;
        m_logQueuedRound = -1;
        m_stepDt = window.maxRewind / 1.1;
        beginWarmStart();
        return;
    }
    m_wordsFresh = false;  // the rounds count into the step words
    if (m_refreshable && !m_wallsAtOnce) {
        m_xBeforeCollisions.resize(n);
        cudaCheck(cudaMemcpyAsync(m_xBeforeCollisions.data(), home().x.data(), n * sizeof(Vec3<Real>), cudaMemcpyDeviceToDevice, s),
                  "positions before collisions");
    }
    // The impact rows are zero but for the particles that had an event in the last stage (flagged in
    // m_hasContactAcceleration, the only rows resolveKernel writes): clear those, not 14 rows of n
    // doubles (1.1 GB at 10^7 particles). After a change of n, everything. With the active flags, the
    // kind counts and the rounds' counters (runImpactRounds), in one launch: at N = 1024 a stage is
    // made of launches.
    if (m_impactRowsN != m_n) {
        cudaCheck(cudaMemsetAsync(m_impactRows.data(), 0, size_t(kImpulseRows + 1) * n * sizeof(double), s), "memset");
        cudaCheck(cudaMemsetAsync(m_hasContactAcceleration.data(), 0, n, s), "memset");
    }
    m_impactRowsN = m_n;
    // The first round's active particles: the movers (startsActive). Where that round scatters, the
    // others search nothing, so their events start cleared.
    const gpu::StageOpenArgs<Real> open{m_wallsAtOnce ? nullptr : m_active.data(),
                                        home().v.data(),
                                        m_moversFirst ? m_window.restingSpeed : Real(0),
                                        !m_wallsAtOnce && scattersSearch(0) ? m_events.data() : nullptr,
                                        m_impactRows.data(),
                                        kImpulseRows + 1,
                                        m_n,
                                        m_hasContactAcceleration.data(),
                                        stepWords()->kindCounts,
                                        m_roundCounters.data(),
                                        int64_t(m_roundCounters.size())};
    gpu::launchOpenStage(open, s);
    m_roundCountersZeroed = m_roundCounters.size() > 0;
    m_logging = m_logContacts;
    m_logBound = 0;
    m_logRound = 0;
    m_logQueuedRound = -1;
    m_stepDt = window.maxRewind / 1.1;  // collision_rounds.cpp: the window is 1.1 dt
    if (m_logging) cudaCheck(cudaMemsetAsync(m_counters.data() + 2, 0, sizeof(unsigned int), s), "memset");
    beginWarmStart();
}

// The last listing's rows become the rows the next listing's fill looks its impulses up in.
template <class Real>
void CudaDevice<Real>::swapListingIntoWarmRows() {
    std::swap(m_contactStart, m_warmStart);
    std::swap(m_contactPartner, m_warmPartner);
    std::swap(m_contactLambda, m_warmLambda);
    std::swap(m_rowColour, m_warmColour);
    std::swap(m_listingColoured, m_warmColoured);
}

// The last listing's rows become the warm start of this step's first listing.
template <class Real>
void CudaDevice<Real>::beginWarmStart() {
    m_warmValid = m_listedThisStep;
    if (m_warmValid) swapListingIntoWarmRows();
    m_listedThisStep = false;
    m_firstListing = true;
}

// Walls only, one GPU, the end-of-step accelerations at hand (m_refreshable: A matched X when the stage
// began; the rounds would compute the same rows by the same pass), no contact log (m_wallsAtOnce,
// decided by beginCollisions): one kernel and one
// wait for the impacts, their tally and whether the contact listing can find anything, instead of two
// rounds, the tally and the listing, four waits (an LJ fluid of 10^6 in a walled box: a few hundred
// wall hits a step).
template <class Real>
int CudaDevice<Real>::resolveWallImpacts() {
    if (!m_wallsAtOnce) return -1;
    if (m_speculated) {  // resolved within the screen's wait (cuda_step.cpp)
        m_speculated = false;
        const bool listAtX = m_listAtX;
        homeChanged();
        m_listAtX = listAtX;
        const int rounds = readResolvedWalls();
        m_wallsOnlyMoved = true;
        m_eventsApplied = true;
        m_cellsMatchPositions = false;
        return rounds;
    }
    beforeStateChange();
    cudaStream_t s = stream();
    unsigned int* stats = stepWords()->wallStats;
    cudaCheck(cudaMemsetAsync(stats, 0, 3 * sizeof(unsigned int), s), "memset");
    // The lists were checked at X by the step's force pass (m_listAtX): they stay valid if no moved
    // particle went past half the skin, and the refresh after the stage then needs no check of its own.
    const bool listsChecked = m_listAtX;
    const Vec3<Real>* built = listsChecked ? home().list.builtPositions() : nullptr;
    const Real halfSkin2 = Real(0.25 * m_model.skin * m_model.skin);
    gpu::launchResolveWallImpacts(collisionArgs(), home().acceleration.data(), Real(m_screenGap), built, halfSkin2, stats, s);
    unsigned long long* words = m_hostWords.resize(kHostWords);
    cudaCheck(cudaMemcpyAsync(words, stepWords()->kindCounts, 3 * sizeof(unsigned long long), cudaMemcpyDeviceToHost, s), "counts");
    cudaCheck(cudaMemcpyAsync(words + 3, stats, 3 * sizeof(unsigned int), cudaMemcpyDeviceToHost, s), "wall impacts");
    const int blocks = queuePartialSums(m_impactRows.data(), kImpulseRows + 1, m_hasContactAcceleration.data());
    sync();
    unsigned int read[3];
    std::memcpy(read, words + 3, sizeof read);
    m_wallTally = tallyOf(words, hostPartialSums(kImpulseRows + 1, blocks));
    m_wallsOnlyMoved = true;
    m_wallContactsPossible = read[1] != 0;
    m_eventsApplied = true;
    homeChanged();
    m_listAtX = built != nullptr && read[2] == 0;
    m_cellsMatchPositions = false;
    return int(read[0]) + 1;
}

// The impact search's cells at the current positions, at least the largest contact distance of the
// particles in them wide, the few large ones kept out (cell_list.h: the one rule, CellSplit); none
// when the screen showed that no pair can meet in this stage (screenStage).
template <class Real>
CellListView CudaDevice<Real>::impactCells() {
    if (m_pairsClear) return emptyCells();
    return m_contactCells.build(home().x.data(), m_n, impactGeometry(), contactCellSplit(), m_cellSplit.gridRadius,
                                stream());
}

// Cells the largest contact distance wide. Tried and not kept: the contact listing's cells (wider by the
// resting gap), so that the listing could walk the rounds' last cells where that round moved nothing
// and its count come back with the rounds' last batch: the same bits (a search finds the same events in
// any cells at least that wide: each particle's earliest by a total order, collision_resolution.h), but
// `corebox bench pile` (an H200, fp32, one call) 10^6 balls 51.1 ms a frame against 48.0 (the last
// second 43.6 against 40.0), 10^5 11.8 against 11.6. Cells wider still (1.1, 1.2 and 1.35 times),
// so that more rounds' builds are skipped: 10^6 balls 49.1, 50.1 and 52.0 against 47.9.
template <class Real>
CellGeometry CudaDevice<Real>::impactGeometry() const {
    return cellGeometry(vec3Cast<double>(m_box), m_n, 2.0 * m_cellSplit.gridRadius);
}

template <class Real>
unsigned int* CudaDevice<Real>::cellsMovedFlag() {
    if (m_cellsMoved.size() != 1) {  // any value would do (a stale 1 costs a build), but a defined one
        m_cellsMoved.resize(1);
        cudaCheck(cudaMemsetAsync(m_cellsMoved.data(), 0, sizeof(unsigned int), stream()), "memset");
    }
    return m_cellsMoved.data();
}

template <class Real>
CellListView CudaDevice<Real>::impactCellsIfMoved() {
    if (m_pairsClear) return emptyCells();
    return m_contactCells.rebuildIfMoved(home().x.data(), m_n, impactGeometry(), contactCellSplit(),
                                         m_cellSplit.gridRadius, cellsMovedFlag(), stream());
}

// Tried and not kept: a round that moved only a few particles out of their cells skipping its build, the
// searches walking those strays (a list of at most 256) after the cells (a distance test each, eight
// read at once), the cells built again where the strays times the searching particles would exceed a
// budget per particle. The same bits (pile energies, sandbox hash), and at 10^6 balls 4,820 to 6,880
// builds over the pile's 5 s instead of 15,302, but the scattered search's walks cost more than the builds
// saved: its rounds took 85 to 262 us on average against 58 (budgets of 2 to 32 strays a particle, caps of
// 256 and 1024), the pile 38.2 to 52.3 ms a frame against 37.9 (an H200, fp32, separate binaries in one
// call). A warp's walk is one thread's chain of reads, and a sparse round's active particles are one to
// a warp.
template <class Real>
void CudaDevice<Real>::trackCellMoves(gpu::CollisionArgs<Real>& a) {
    a.cellKeys = m_pairsClear ? nullptr : m_contactCells.keys();
    if (!a.cellKeys) return;
    a.cellSplit = contactCellSplit();
    a.cellsMoved = cellsMovedFlag();
}

// Candidate rows (gpu_launch.h CandidateRows) where the rounds are batched (runImpactRounds), pairs can
// meet, there are more than 32,768 particles (m_candidateRowsFrom: below, a search gives a particle
// several lanes and a round is its launches), and the cells' build can gate itself on the device (the
// rows' own gate follows it).
template <class Real>
bool CudaDevice<Real>::roundsReadCandidates() const {
    return m_impactCandidates && !m_pairsClear && m_n >= m_candidateRowsFrom && m_n < INT32_MAX &&
           !gpu::cellListBuildIsOneLaunch(m_n) && gpu::cellListIfMovedBlocks<Real>() > 0 &&
           gpu::candidateBuildBlocks<Real>() > 0;
}

// The margin a row holds beyond each pair's contact distance: kCandidateMargin (collision_resolution.h) of
// the largest diameter in the cells. A landing's balls fall about 0.1 of a diameter a step at dt = 1/240,
// so the rows are made again every step or two while they fall, and last while a pile rests.
template <class Real>
Real CudaDevice<Real>::candidateMargin() const {
    return Real(kCandidateMargin * 2.0 * m_cellSplit.gridRadius);
}

template <class Real>
CellGeometry CudaDevice<Real>::candidateGeometry() const {
    return cellGeometry(vec3Cast<double>(m_box), m_n, 2.0 * m_cellSplit.gridRadius + double(candidateMargin()));
}

// The rows' buffers for this state (n rows of m_candidateSlots, 128 bytes a particle by default: 1.3 GB
// at 10^7 particles). Where the device has not the room, the rounds walk cells from then on, as before
// the rows (and the failed allocation's error is cleared, so that no later launch check reports it).
template <class Real>
bool CudaDevice<Real>::allocateCandidates() {
    const size_t n = size_t(m_n);
    try {
        m_candidateRows.resize(n * size_t(m_candidateSlots));
        m_candidateCounts.resize(n);
        m_candidateX.resize(n);
        return true;
    } catch (const DeviceError& e) {
        (void)cudaGetLastError();
        m_candidateRows = DeviceBuffer<int32_t>{};
        m_candidateCounts = DeviceBuffer<int32_t>{};
        m_candidateX = DeviceBuffer<Vec3<Real>>{};
        m_impactCandidates = false;
        std::fprintf(stderr, "corebox: no device memory for the impact rounds' candidate rows (%s); they walk cells\n",
                     e.what());
        return false;
    }
}

template <class Real>
void CudaDevice<Real>::prepareCandidates(int round, unsigned int* stale, gpu::CollisionArgs<Real>& a) {
    cudaStream_t s = stream();
    const Real margin = candidateMargin();
    // Not quite half the margin: what fp rounds of a distance and of the moves cannot take back.
    const Real half = Real(0.49) * margin;
    const gpu::CandidateRows<Real> rows{m_candidateRows.data(), m_candidateCounts.data(), m_candidateX.data(),
                                        m_candidateSlots, half * half};
    gpu::CandidateFillArgs<Real> fill{
        home().x.data(),     a.p.species,     a.table.radius,         m_n,
        CellListView{},      margin,          m_candidateRows.data(), m_candidateCounts.data(),
        m_candidateX.data(), m_candidateSlots};
    gpu::CellListArgs<Real> build{};
    int32_t* blockTotals = nullptr;
    bool gated = false;
    if (!m_candidatesMade) {
        m_cellList = m_candidateCells.build(home().x.data(), m_n, candidateGeometry(), contactCellSplit(),
                                            m_cellSplit.gridRadius, s);
    } else {
        if (round == 0) gpu::launchCandidateStaleness(home().x.data(), m_n, rows, stale, s);
        gated = m_candidateCells.gatedBuild(home().x.data(), m_n, candidateGeometry(), contactCellSplit(),
                                            m_cellSplit.gridRadius, gpu::candidateBuildBlocks<Real>(), s, &build,
                                            &blockTotals);
        m_cellList = build.view();
    }
    fill.grid = m_cellList;
    if (gated)  // the cells and the rows where stale, in one launch
        gpu::launchCellListIfMovedThenFill(build, stale, blockTotals, fill, s);
    else  // cells just built: their rows
        gpu::launchFillCandidates(fill, s);
    m_candidatesMade = true;
    a.grid = m_cellList;
    a.candidates = rows;
}

template <class Real>
int64_t CudaDevice<Real>::findEvents(EventScope scope) {
    cudaStream_t s = stream();
    m_roundsOnCandidates = false;
    m_cellList = impactCells();
    m_cellsMatchPositions = !m_pairsClear;
    gpu::CollisionArgs<Real> a = collisionArgs();
    if (scope == EventScope::All) {
        cudaCheck(cudaMemsetAsync(m_active.data(), 1, size_t(m_n), s), "memset");
        m_searchRound = 0;  // every particle searches
    }
    // The round before's count moves from counters[1], which this search counts into, to counters[3].
    if (narrowsSearch(m_searchRound) || (m_searchRound > 0 && scattersSparseRounds()))
        cudaCheck(cudaMemcpyAsync(m_counters.data() + 3, m_counters.data() + 1, sizeof(unsigned int),
                                  cudaMemcpyDeviceToDevice, s),
                  "event count");
    cudaCheck(cudaMemsetAsync(m_counters.data(), 0, 2 * sizeof(unsigned int), s), "memset");
    searchRound(a, m_searchRound++, m_counters.data() + 3, s);
    auto* counts = reinterpret_cast<unsigned int*>(m_hostWords.resize(kHostWords));
    // The log's record count rides along (stale but unread when the log is off).
    cudaCheck(cudaMemcpyAsync(counts, m_counters.data(), 3 * sizeof(unsigned int), cudaMemcpyDeviceToHost, s), "events");
    sync();
    m_needCount = counts[0];
    m_eventCount = counts[1];
    if (m_logging) m_logBound = counts[2];
    return int64_t(counts[1]);
}

template <class Real>
void CudaDevice<Real>::applyEvents() {
    beforeStateChange();
    m_tailTally = false;
    cudaStream_t s = stream();
    if (m_logging) {  // a record per particle with an event, at most
        reserveLog(m_logBound + m_eventCount);
        m_logBound += m_eventCount;
    }
    const gpu::CollisionArgs<Real> a = collisionArgs();
    if (m_needCount > 0) {
        // End-of-step accelerations of the listed particles: a force pass over those rows only.
        gpu::ForceArgs<Real> f = homeForceArgs(home().x.data(), m_contactAcceleration.data());
        f.begin = 0;
        f.end = int64_t(m_needCount);
        f.rowIndex = m_needList.data();
        const size_t scratch = gpu::forceScratchBytes<Real>(f.end, m_n);
        if (m_homeForceScratch.size() < scratch) m_homeForceScratch.resize(scratch);
        f.scratch = m_homeForceScratch.data();
        f.scratchBytes = m_homeForceScratch.size();
        if (useLists() && gpuCount() == 1) {  // O(M x partners), not O(M x N): 10^7 particles hit the walls by the thousand
            if (!m_listAtX) home().list.update(home().x.data(), m_n, 0, m_n, m_box, m_model.cutoff, m_model.skin, s);
            home().list.fill(f);
        } else {
            f.rowCount = m_counters.data();  // the count just read, as the queued rounds read it (runImpactRounds)
        }
        gpu::launchForces(f, s);
    }
    gpu::launchResolve(a, s);
    ++m_logRound;
    m_eventsApplied = true;
    homeChanged();
    m_cellsMatchPositions = false;
}

// Rounds queued in batches, their counts read once a batch. Nothing a round queues depends on what the
// one before found: each round's search, rows, resolution and active flags are gated on the event
// count of the round before it and of itself (CollisionArgs::gate, and the round's count of particles
// needing end-of-step accelerations, which a gated search leaves at zero, ForceArgs::rowCount), so a
// round queued behind the one that found none does nothing, and the state is the one the rounds one by
// one leave. Without a pair force a particle's acceleration at the end of the step is its field
// whatever the positions: one pass over every row, before the rounds. With pair forces (all pairs on
// the gathered state) each round's new rows get theirs at the positions that round found, as applyEvents
// computes them, by a pass that reads the round's count on the device. The first batch is as long as
// the last stage's rounds (a pile's rounds vary slowly), later ones four (or the rest of a batch the
// contact log's room cut short, below): a batch too long costs its
// extra rounds' launches (their cell-list builds skipped, below), one too short a read-back. Tried and
// not kept: eight after a round of more than kTailAfterEvents events (a landing's rounds, to the cap):
// the same bits, the sandbox at 10^5 balls (an H200, fp32, one call) 15.3 and 15.7 ms a frame against
// 15.8 and 14.9, its impact rounds 5.07 against 5.14 and 5.25. Tried and not kept either: the next
// batch queued before the wait for the one before after a round of more than kTailAfterEvents events,
// gated on that batch's last round, so that the device goes on while the host reads (each round's
// counts and each batch's log count read into places of their own): the same bits as a round a wait in
// a landing of 8,000 balls with the contact log on and off, but no gain (an H200, fp32): the sandbox at
// 10^5 balls 12.3 and 12.1 ms a frame against 12.1, its landing's impact rounds 14.9 ms a frame against
// 14.9; `corebox bench pile` 10^6 balls 42.0 against 41.5, 10^5 10.4 against 10.3. A landing runs to
// the round cap step after step, so its first batch is the whole cap and there is no wait to hide; its
// rounds are the device's (the sandbox's: 58 us a round, the search 35 of them, CUPTI's kernel times).
// A round after the first resolves from its list of the particles with events (gpu::launchResolveListed)
// where the searches may look from a few particles (narrowableStage: 2^19 particles and more), not a
// thread a particle: in a landing's rounds of many events a warp of the particle-wide launch had 4.2
// threads at work on average (ncu, an H200, fp32, the 10^6-ball pile: 103 us for such a round's
// resolution, L2 at 20% of its peak). The same bits (tests/gpu/test_cuda_contacts.cpp: narrowed and not). An H200,
// fp32, CUPTI kernel times: that pile's resolutions 430 ms over the 5 s (343 resolving, 87 clearing the flags) against
// 707; `corebox bench pile` (two calls of each, alternating) 10^6 balls 38.02 and 38.33 ms a frame against 38.78
// and 38.89, the landing's frames (60 to 140) 65.4 and 66.0 against 67.9. Not below: at 10^5 balls (the
// sandbox example) a round's resolution and clearing took 8.1 us against 6.1 for a thread a particle.
// Above 32,768 particles the rounds read candidate rows instead (prepareCandidates; gpu_launch.h
// CandidateRows), made again only where some particle moved most of half their margin; below, cells:
// Cell lists skipped. A round's build (then a radix sort of every particle's cell key, now a counting
// sort: device_cell_list.h; a third of the kernel time of the sandbox example's landing, ncu) makes the
// same arrays as the last build wherever no particle changed cell since, the arrays depending on the
// keys alone. So the resolution flags any particle it moves out of the cell its key names
// (CollisionArgs::cellKeys), and each round after the call's first builds in a launch that reads and
// clears that flag and builds only where it is set (DeviceCellList::rebuildIfMoved): a settled pile's rounds
// move particles by less than a cell, and the rounds queued behind the one that found nothing move
// none. The same bits (tests/gpu/test_cuda_contacts.cpp). An H200, fp32, with the listings' 2% deep
// overlap in both (collision_rounds.cpp): `corebox bench pile` 10^6 balls 48.0 ms a frame against 49.8
// (the last second 39.8 against 40.8), 10^5 11.7 against 13.0, 10^4 5.5 against 7.5 (the last record);
// the sandbox example at 10^5 balls 13.4 ms a frame against 14.7 (the record, 0.5% deep overlap), its
// impact rounds 4.4 against 5.1, the slowest frame 54 against 60.
// The batch's wait also brings back what the calls after the rounds would each wait for (queueStageTail):
// read where the batch's last round found nothing; queued only behind a round of few events.
// With lists on one GPU or without CudaBackendOptions::fusedSteps: a round a wait. With the contact log,
// the batch is as long as a record per particle a round fits in kLogBatchBytes (at least one round),
// room the log gets before the batch; its count comes back with the batch's. The same bits as a round a
// wait (tests/gpu/test_cuda_contacts.cpp); the sandbox example at 10^5 balls on an H200 (fp32, with the
// narrowed searches above, which cost it about as much) took 40.9 ms of simulation a frame against 38.7.
// Measured (`corebox bench pile`, H200, fp32, 5 s, the same run with both): the impact phase of the
// 10^4-ball pile (18 rounds a step) took 7.2 ms a frame instead of 8.6, of 10^5 balls (26) 11.6 instead
// of 14.0; whole frames 17.7 and 43.5 ms instead of 19.0 and 46.4. What is left of a round is its
// launches, the cell list's build (a radix sort) most of them: a round is about 80 us at 10^4 balls.
// Tried and not kept: a flag per cell holding an active particle, so that an inactive particle walks its
// neighbours only near one (the later rounds' few active particles): the same bits, but the flags'
// kernel cost what the search saved (H200, fp32, bench pile, same run: 10^5 balls 38.9 against 38.3 ms
// a frame, 10^6 over 3 s 209 against 217).
// Tried and not kept: up to 1024 particles, every round in one launch of one block (the cell list built
// in shared memory, a thread a particle for the search and the resolution, the rows by teams of 128
// lanes, barriers between): Table 1's N = 1024 stage took 0.093 ms a step against 0.099 (H200, same
// call), and the same search and resolution code inlined into that kernel did not give the bits of
// the separate kernels (a pile in fp32, the LJ fluid in fp64; most likely the same source contracted
// into different fused multiply-adds in another kernel, not verified), so the paths' same-bits
// guarantee would have gone for 6 us.
template <class Real>
ImpactRounds CudaDevice<Real>::runImpactRounds(int maxRounds) {
    const bool listRows = m_model.anyPairForce && useLists() && gpuCount() == 1;  // applyEvents' list rows: checked on the host
    if (listRows || !m_fusedSteps || maxRounds < 1) return Backend::runImpactRounds(maxRounds);
    beforeStateChange();
    m_tailTally = false;
    cudaStream_t s = stream();
    gpu::ForceArgs<Real> f = homeForceArgs(home().x.data(), m_contactAcceleration.data());
    f.begin = 0;
    f.end = m_n;
    f.rowIndex = nullptr;
    if (!m_model.anyPairForce) gpu::launchForces(f, s);
    f.rowIndex = m_needList.data();
    // Two counters a round, then the candidate rows' staleness word a round and one round more (the
    // last round's resolution sets the next one's).
    const size_t counterWords = 2 * size_t(maxRounds) + size_t(maxRounds + 1);
    if (!(m_roundCountersZeroed && m_roundCounters.size() >= counterWords)) {  // else zeroed by beginCollisions
        m_roundCounters.resize(counterWords);
        cudaCheck(cudaMemsetAsync(m_roundCounters.data(), 0, counterWords * sizeof(unsigned int), s), "memset");
    }
    unsigned int* candidateStale = m_roundCounters.data() + 2 * size_t(maxRounds);
    const bool candidates = roundsReadCandidates() && (m_candidatesMade || allocateCandidates());
    m_roundsOnCandidates = candidates;
    bool tailCells = false;  // the last batch's tail built the listing's cells behind it (queueStageTail)
    m_roundCountersZeroed = false;
    ImpactRounds result;
    bool applied = false;
    int batch = std::clamp(m_lastImpactRounds, std::min(2, maxRounds), maxRounds);
    // The events of the last round read back; before the first batch, many where the last stage ran to
    // the cap (a landing goes on), none otherwise.
    unsigned int lastEvents = m_lastImpactRounds >= maxRounds ? UINT_MAX : 0u;
    while (result.rounds < maxRounds && !result.settled) {
        const int first = result.rounds;
        const int wanted = std::min(batch, maxRounds - first);
        int queued = wanted;
        if (m_logging) {  // room for a record per particle a round, within kLogBatchBytes beyond one round
            const size_t perRound = size_t(std::max<int64_t>(m_n, 1)) * sizeof(gpu::ImpactRecord<Real>);
            queued = std::clamp(int(kLogBatchBytes / perRound), 1, queued);
            reserveLog(m_logBound + size_t(queued) * size_t(m_n));
        }
        for (int r = first; r < first + queued; ++r) {
            // Only the rounds' resolutions move particles between builds here: a round after the first
            // builds where the one before moved a particle out of its cell, or leaves the arrays that build
            // would make (the same keys). The first round builds: the integration moved everything.
            gpu::CollisionArgs<Real> a = collisionArgs();
            if (candidates) {
                prepareCandidates(r, candidateStale + r, a);
                a.staleNext = candidateStale + (r + 1);
            } else {
                const bool gated = r > 0 && m_skipUnmovedCellBuilds;
                m_cellList = gated ? impactCellsIfMoved() : impactCells();
                a.grid = m_cellList;
                if (m_skipUnmovedCellBuilds) trackCellMoves(a);
            }
            a.logRound = m_logRound + (r - first);  // every round before r in the batch found events, or r does nothing
            a.counters = m_roundCounters.data() + 2 * r;
            a.gate = r > first ? a.counters - 1 : nullptr;  // the round before (known to have found events when r == first)
            a.activeOut =
                m_activeLists.data() + size_t(r % 2) * size_t(m_n);  // every round lists its particles with events
            searchRound(a, r, r > 0 ? a.counters - 1 : nullptr, s);
            if (m_model.anyPairForce) {
                f.rowCount = a.counters;  // this round's new rows; none where the search was gated off
                gpu::launchForces(f, s);
            }
            a.gate = a.counters + 1;  // this round's events
            if (narrowsSearch(r)) {   // from the list (below), the round before's flags (its list) cleared first
                a.activeIn = m_activeLists.data() + size_t((r + 1) % 2) * size_t(m_n);
                a.activeInCount = a.counters - 1;
                gpu::launchResolveListed(a, s);
            } else {  // a thread a particle: the stage's first round (its flags are every particle's:
                      // startsActive), and every round of a stage that cannot narrow
                gpu::launchResolve(a, s);
            }
        }
        unsigned int* counts = m_hostRoundCounts.resize(2 * size_t(queued) + 1);
        cudaCheck(cudaMemcpyAsync(counts, m_roundCounters.data() + 2 * first, 2 * size_t(queued) * sizeof(unsigned int),
                                  cudaMemcpyDeviceToHost, s),
                  "round counts");
        if (m_logging)
            cudaCheck(cudaMemcpyAsync(counts + 2 * queued, m_counters.data() + 2, sizeof(unsigned int), cudaMemcpyDeviceToHost, s), "log count");
        // The tail is read only where the batch's last round finds nothing: not queued behind a batch that
        // follows a round with many events (queueStageTail says why).
        const StageTail tail = lastEvents <= kTailAfterEvents ? queueStageTail() : StageTail{};
        tailCells = tail.listing;
        sync();
        if (m_logging) m_logBound = counts[2 * queued];
        for (int k = 0; k < queued && !result.settled; ++k) {
            ++result.rounds;
            lastEvents = counts[2 * size_t(k) + 1];
            result.settled = lastEvents == 0;
            if (!result.settled) {
                ++m_logRound;
                applied = true;
            }
        }
        if (result.settled && tail.tally) readStageTail(tail, applied);
        // A batch cut short by the log's room leaves the rest of what it wanted to the next one: a landing's
        // rounds to the cap at 10^5 particles are then two batches (55 and 9) instead of four (55, 4, 4, 1).
        // The sandbox at 10^5 balls (an H200, fp32, separate libraries alternating in one call, three runs
        // each): its landing's impact rounds 9.5 to 9.7 ms a frame against 9.7 to 9.9, the same state hash.
        batch = std::max(4, wanted - queued);
    }
    m_lastImpactRounds = result.rounds;
    // The log is complete for the stage (the contact phase records nothing): its sort and copy are queued
    // here, behind the rounds, and come back with the step's next wait instead of two waits of their own
    // when the log is read (readContactLog). With the log read into kept memory (World's logBuffer), the
    // sandbox at 10^5 balls (an H200, fp32, host probes) spent 190 to 244 us a step reading its log in
    // its landing instead of 276 (calls apart).
    if (m_logging && m_logRound > 0) {
        if (m_logBound > 0) queueLogRead(m_logBound);
        m_logQueuedRound = m_logRound;
        m_logQueuedCount = m_logBound;
    }
    if (applied) {
        m_eventsApplied = true;
        homeChanged();
    }
    // Cells at the positions the rounds leave when the last found nothing to move: the rounds' own, or
    // where they read rows (whose cells are where the particles were when the rows were made) those the
    // last batch's tail built.
    m_cellsMatchPositions = result.settled && !m_pairsClear && (!candidates || tailCells);
    return result;
}

// What the calls after settled rounds would each wait for, queued behind a batch of rounds to come back
// in the same copy of the step mail: the tally (collisionTally: the kind counts are step words, the
// impact rows' block partials follow them); and where no gravity gives contacts a resting gap (the
// contact listing's cells are then the rounds' last, which match the positions when that round found
// nothing), the listing's count (listContacts, for the resting contact of this stage's window and
// screen: its total in a step word, the scan left for a listing that finds some) and the step check
// (checkStep, its kinetic row summed with the impact rows), which stand if the listing finds nothing.
// RK4 at N = 1024 (all pairs, 13 impacts a step): the stage's five waits become one.
// Not behind a batch whose round before found more than kTailAfterEvents events: a landing's rounds
// run to the cap, and each batch's tail (a contact count over every particle, the step check and the
// block sums) went unread. The sandbox example at 10^5 balls while they land (ncu, an H200, fp32, 4
// steps): 72 contact counts for 16 listings, 4.25 ms of the 45 ms of kernels. Left unqueued there: the
// same bits, the sandbox 14.5 and 14.4 ms a frame against 14.8 (the slowest 60 and 61 against 66), `corebox
// bench pile` 10^6 balls 59.3 against 59.8, 10^5 14.5 against 14.8, 10^4 7.4 against 7.6 (one call).
template <class Real>
typename CudaDevice<Real>::StageTail CudaDevice<Real>::queueStageTail() {
    StageTail tail;
    cudaStream_t s = stream();
    gpu::StepWords* w = stepWords();
    int rows = kImpulseRows + 1;
    const RestingContact<double> resting{m_stageWindow.restingSpeed, m_screenGap};
    // m_screenGap < 0: screenStage was not called, no resting contact known.
    // Where the rounds read candidate rows, their cells are the rows' build, not the positions': the
    // listing's cells are built here, behind the rounds, rather than after the wait (a build wasted
    // where the batch does not end the stage, which a round of few events before it makes rare).
    const bool listingCells = m_roundsOnCandidates && !m_pairsClear;
    if (m_screenGap >= 0 &&
        (m_pairsClear || listingCells || sameGeometry(listingGeometry(resting), m_cellList.geometry))) {
        gatherToHome();
        forgetRunAhead();  // its words are about to be written
        m_wordsFresh = false;
        static_assert(offsetof(gpu::StepWords, listedContacts) == offsetof(gpu::StepWords, healthCounts) + sizeof w->healthCounts,
                      "one memset for the health counts and the contact total");
        cudaCheck(cudaMemsetAsync(w->healthCounts, 0, sizeof w->healthCounts + sizeof w->listedContacts, s), "memset");
        m_resting = RestingContact<Real>{Real(resting.speed), Real(resting.gap)};
        if (listingCells)
            m_cellList = m_contactCells.build(home().x.data(), m_n, listingGeometry(resting), contactCellSplit(),
                                              m_cellSplit.gridRadius, s);
        countContacts(false, &w->listedContacts);
        gpu::StepCheckArgs<Real> a = stepCheckArgs(m_impactRows.data() + size_t(kImpulseRows + 1) * size_t(m_n));
        tail.checkForecast = a.forecast.moves != nullptr;
        if (tail.checkForecast) cudaCheck(cudaMemsetAsync(&w->listForecast, 0, sizeof w->listForecast, s), "memset");
        gpu::launchStepCheck(a, s);
        rows = kImpulseRows + 2;
        tail.listing = tail.check = true;
        tail.resting = resting;
    }
    gpu::launchBlockSums(m_impactRows.data(), rows, m_n, m_stepMail.data() + kStepWordDoubles, s, m_hasContactAcceleration.data(),
                         kImpulseRows + 1);
    const size_t doubles = kStepWordDoubles + size_t(rows) * size_t(partialBlocks());
    cudaCheck(cudaMemcpyAsync(m_hostStepMail.data(), m_stepMail.data(), doubles * sizeof(double), cudaMemcpyDeviceToHost, s), "step words");
    tail.tally = true;
    return tail;
}

template <class Real>
void CudaDevice<Real>::readStageTail(const StageTail& tail, bool applied) {
    const gpu::StepWords& words = hostStepWords();
    const double* partials = m_hostStepMail.data() + kStepWordDoubles;
    const int blocks = partialBlocks();
    m_tailTally = tail.tally;
    if (tail.tally) m_tailTallyValue = applied ? tallyOf(words.kindCounts, sumPartials(partials, kImpulseRows + 1, blocks)) : CollisionTally{};
    m_tailListing = tail.listing;
    m_tailResting = tail.resting;
    m_tailListed = int64_t(words.listedContacts);
    if (tail.check) {
        readForecast(tail.checkForecast, words);
        m_cachedCheck = stepCheckOf(words, partials + size_t(kImpulseRows + 1) * size_t(blocks));
        m_checkCached = m_tailListed == 0;  // contacts to relax change the state it checked
    }
}

template <class Real>
CollisionTally CudaDevice<Real>::collisionTally() {
    if (m_wallsAtOnce) return m_wallTally;  // read with resolveWallImpacts' wait
    if (m_tailTally) return m_tailTallyValue;  // read with the last batch of rounds (queueStageTail)
    // Nothing resolved since beginCollisions zeroed the counters: nothing to read back.
    if (!m_eventsApplied) return CollisionTally{};
    // The counts, the losses and the impulses come back with one wait: the loss is the last of the
    // impact rows, summed with them in block order.
    unsigned long long* kinds = m_hostWords.resize(kHostWords);
    cudaCheck(cudaMemcpyAsync(kinds, stepWords()->kindCounts, 3 * sizeof(unsigned long long), cudaMemcpyDeviceToHost, stream()), "counts");
    const int blocks = queuePartialSums(m_impactRows.data(), kImpulseRows + 1, m_hasContactAcceleration.data());
    sync();
    return tallyOf(kinds, hostPartialSums(kImpulseRows + 1, blocks));
}

template <class Real>
void CudaDevice<Real>::reserveLog(size_t records) {
    if (m_log.size() >= records) return;
    // Geometric growth: a dense step's rounds add records a few at a time.
    DeviceBuffer<gpu::ImpactRecord<Real>> grown(std::max(records, 2 * m_log.size()));
    const size_t bytes = std::min(m_logBound, m_log.size()) * sizeof(gpu::ImpactRecord<Real>);
    if (bytes > 0) cudaCheck(cudaMemcpyAsync(grown.data(), m_log.data(), bytes, cudaMemcpyDeviceToDevice, stream()), "contact log");
    sync();  // the old buffer is freed next
    m_log = std::move(grown);
}

template <class Real>
void CudaDevice<Real>::queueLogRead(size_t count) const {
    // The CPU's order: by round, then by the resolving particle (one impact each per round), sorted on
    // the device (gpu::launchSortImpactLog).
    m_logSorted.resize(count);
    const size_t scratch = gpu::impactLogSortBytes(int64_t(count));
    if (m_logSortScratch.size() < scratch) m_logSortScratch.resize(scratch);
    gpu::launchSortImpactLog(m_log.data(), int64_t(count), m_logRound, m_logSorted.data(), m_logSortScratch.data(),
                             m_logSortScratch.size(), stream());
    m_hostLog.resize(count);
    cudaCheck(cudaMemcpyAsync(m_hostLog.data(), m_logSorted.data(), count * sizeof(gpu::ImpactRecord<Real>),
                              cudaMemcpyDeviceToHost, stream()),
              "contact log");
}

template <class Real>
void CudaDevice<Real>::readContactLog(std::vector<ContactRecord>& out) const {
    out.clear();
    if (!m_logging || m_logRound == 0) return;
    size_t count = 0;
    if (m_logQueuedRound == m_logRound) {  // queued behind the rounds, and no round since
        count = m_logQueuedCount;
    } else {
        unsigned int written = 0;
        cudaCheck(cudaMemcpyAsync(&written, m_counters.data() + 2, sizeof(written), cudaMemcpyDeviceToHost, stream()),
                  "contact log");
        sync();
        count = written;
        if (count > 0) queueLogRead(count);
        m_logQueuedRound = m_logRound;  // a second read takes the same copy
        m_logQueuedCount = count;
    }
    if (count == 0) return;
    sync();
    const gpu::ImpactRecord<Real>* records = m_hostLog.data();
    out.resize(count);
    for (size_t k = 0; k < out.size(); ++k) {
        const gpu::ImpactRecord<Real>& r = records[k];
        ContactRecord& c = out[k];
        c.a = r.particle;
        c.b = r.partner;
        c.round = r.round;
        c.time = std::clamp(m_stepDt - double(r.detail.rewind), 0.0, m_stepDt);
        c.normal = vec3Cast<double>(r.detail.normal);
        c.impulse = double(r.detail.impulse);
        c.speed = double(r.detail.speed);
    }
}

template <class Real>
gpu::ContactArgs<Real> CudaDevice<Real>::contactArgs() {
    gpu::ContactArgs<Real> a{};
    a.p = arrays();
    a.table = table();
    a.box = m_box;
    a.cells = m_cellList;
    a.contactStart = m_contactStart.data();
    a.partner = m_contactPartner.data();
    a.resting = m_resting;
    a.up = upOf(m_gravity);
    a.bounce = ContactBounce<Real>{Real(m_model.restitution), Real(m_model.wallRestitution), Real(m_model.elasticBelowSpeed), m_resting.speed};
    a.dv = m_dv.data();
    a.dx = m_dx.data();
    a.residual = m_residual.data();
    a.impulses = m_contactImpulses.data();
    a.lambda = m_contactLambda.data();
    a.warm = false;
    a.warmStart = m_warmStart.data();
    a.warmPartner = m_warmPartner.data();
    a.warmLambda = m_warmLambda.data();
    a.warmColour = nullptr;  // listContacts gives them to a fill that keeps colours, and its colouring
    a.prevColour = nullptr;
    a.applied = m_contactApplied.data();
    a.gaussSeidel = m_gaussSeidelContacts;
    a.rowParticle = m_rowParticle.data();
    a.mirror = m_rowMirror.data();
    a.colour = m_rowColour.data();
    a.target = m_rowTarget.data();
    a.colourStart = m_colouringWords.size() > kColouringWords
                        ? reinterpret_cast<int32_t*>(m_colouringWords.data() + kColouringWords)
                        : nullptr;
    a.packedParticle = m_packedParticle.data();
    a.packedPartner = m_packedPartner.data();
    a.packedTarget = m_packedTarget.data();
    a.packedLambda = m_packedLambda.data();
    a.rowRank = m_rowRank.data();
    a.body = m_body.data();
    const bool listsPartners = gpu::contactCountListsPartners(m_n) && m_partnerScratch.size() >= size_t(m_n) * gpu::kListedPartners;
    a.partnerScratch = listsPartners ? m_partnerScratch.data() : nullptr;
    a.omega = Real(kGaussSeidelOverRelaxation);
    a.sweepBlocks = m_sweepBlocks;
    return a;
}

// Colours the listing's contacts for Gauss-Seidel sweeps (kernels/contact_gauss_seidel.cu) and reads
// back how many colours they took and where each begins: one wait. False (the listing is relaxed with
// Jacobi sweeps) where the device has no cooperative launch or the contacts need more than
// gpu::kMaxContactColours colours. withKinetic: the kinetic energy (kineticEnergy's kernels and sums) is
// read back with the same wait and kept until the state changes: the core asks for it after a stage's
// first listing, which changes no velocity (collision_rounds.cpp), and its own wait left the GPU idle
// after every colouring: an H200, fp32, CUPTI, the 10^6-ball pile over 5 s, 1,192 such waits, 27 ms
// of idle GPU around them, which went.
template <class Real>
bool CudaDevice<Real>::colourListing(int64_t rows, bool keepColours, bool withKinetic) {
    cudaStream_t s = stream();
    for (auto* b : {&m_rowParticle, &m_rowMirror}) b->resize(size_t(rows));
    for (auto* b : {&m_packedParticle, &m_packedPartner, &m_rowRank}) b->resize(size_t(rows));
    for (auto* b : {&m_packedTarget, &m_packedLambda}) b->resize(size_t(rows));
    m_rowColour.resize(size_t(rows));
    // [6..7]: the deepest overlap's bits; then the colours' starts (ContactArgs::colourStart), read back
    // with the words in one copy.
    m_colouringWords.resize(kColouringWords + gpu::kMaxContactColours + 1);
    m_colouringScratch.resize(gpu::contactColouringScratchBytes(m_n, rows));
    auto* deepest = reinterpret_cast<unsigned long long*>(m_colouringWords.data() + 6);
    gpu::ContactArgs<Real> a = contactArgs();
    if (keepColours) a.prevColour = m_prevColour.data();
    if (!gpu::launchColourContacts(a, rows, m_colouringScratch.data(), m_colouringScratch.size(), m_colouringWords.data(),
                                   deepest, s))
        return false;
    unsigned int* words = m_hostColouring.resize(m_colouringWords.size());
    cudaCheck(cudaMemcpyAsync(words, m_colouringWords.data(), m_colouringWords.size() * sizeof(unsigned int),
                              cudaMemcpyDeviceToHost, s),
              "contact colouring");
    const int kineticBlocks = withKinetic ? queueKineticSum() : 0;
    sync();
    if (withKinetic) {
        m_cachedKinetic = hostPartialSums(1, kineticBlocks)[0];
        m_kineticCached = true;
    }
    unsigned long long bits = 0;
    std::memcpy(&bits, words + 6, sizeof bits);
    std::memcpy(&m_listedOverlap, &bits, sizeof m_listedOverlap);
    if (words[1] != 0 || words[0] < 1 || words[0] > unsigned(gpu::kMaxContactColours)) return false;
    m_colourStart.assign(size_t(words[0]) + 1, 0);
    std::memcpy(m_colourStart.data(), words + kColouringWords, m_colourStart.size() * sizeof(int32_t));
    return true;
}

// The particles the contact grids keep out of their cells (chooseContactCellSplit), on the home GPU.
template <class Real>
CellSplit<Real> CudaDevice<Real>::contactCellSplit() {
    return cellSplitOf(m_cellSplit, home().species.data(), home().radius.data());
}

// Cells for the contact listing: every listed pair in neighbouring cells, or within a large
// particle's reach.
template <class Real>
CellGeometry CudaDevice<Real>::listingGeometry(const RestingContact<double>& resting) const {
    return cellGeometry(vec3Cast<double>(m_box), m_n, 2.0 * m_cellSplit.gridRadius + resting.gap);
}

// Each particle's contacts within m_resting through m_cellList into m_contactStart, their total into
// *total where set; with scan, scanned into offsets (the total at [n]).
template <class Real>
void CudaDevice<Real>::countContacts(bool scan, unsigned long long* total) {
    m_contactStart.resize(size_t(m_n) + 1);
    m_residual.resize(2);
    for (auto* b : {&m_xListed, &m_dv, &m_dx}) b->resize(size_t(m_n));
    m_body.resize(2 * size_t(m_n));  // packed by the count
    if (gpu::contactCountListsPartners(m_n)) m_partnerScratch.resize(size_t(m_n) * gpu::kListedPartners);
    gpu::launchCountContacts(contactArgs(), stream(), total);
    if (scan) scanContacts();
}

template <class Real>
void CudaDevice<Real>::scanContacts() {
    const size_t scratch = gpu::contactScanScratchBytes(m_n);
    m_contactScanScratch.resize(scratch);
    gpu::scanContactCounts(m_contactStart.data(), m_n, m_contactScanScratch.data(), scratch, stream());
}

template <class Real>
int64_t CudaDevice<Real>::listContacts(const RestingContact<double>& resting) {
    gatherToHome();
    cudaStream_t s = stream();
    m_resting = RestingContact<Real>{Real(resting.speed), Real(resting.gap)};
    // The device's count of wall contacts (resolveOnDevice) holds for the resting contact it was given.
    const bool countedFor = !m_wallsCountedOnDevice || (resting.speed == m_speculatedWindow.restingSpeed && resting.gap == m_screenGap);
    m_wallsCountedOnDevice = false;
    if (m_wallsAtOnce && !m_wallContactsPossible && resting.gap <= m_screenGap && countedFor) {
        // No pair within reach (the screen) and no particle near a wall after the impacts (or none in
        // contact, as the device counted): nothing to list, and nothing for the next step's warm start
        // (as a listing of zero contacts leaves it).
        m_listedThisStep = false;
        m_firstListing = false;
        return 0;
    }
    // A later listing of this step carries this step's impulses so far: the last listing's rows become
    // the rows its fill looks each contact up in (as the first listing's look up the last step's), their
    // bounces dropped (an impact, not a support to take back), not applied again (contact_relaxation.h;
    // the CPU's listContacts says why).
    const bool carry = !m_firstListing && m_listedThisStep;
    if (carry) {
        if (m_gaussSeidel) gpu::launchDropBounceImpulses(m_contactLambda.data(), m_rowTarget.data(), int64_t(m_contactPartner.size()), s);
        swapListingIntoWarmRows();
    }
    m_listingColoured = false;  // until this listing is
    // The impulse rows and the relaxation tally's two (queueRelaxationTally), the impulse rows zeroed.
    bool impulsesCleared = false;
    auto clearImpulseRows = [&] {
        m_contactImpulses.resize(size_t(kImpulseRows + 2) * size_t(m_n));
        cudaCheck(cudaMemsetAsync(m_contactImpulses.data(), 0, size_t(kImpulseRows) * size_t(m_n) * sizeof(double), s),
                  "memset");
        impulsesCleared = true;
    };
    int64_t total = 0;
    if (m_tailListing && resting.speed == m_tailResting.speed && resting.gap == m_tailResting.gap) {
        total = m_tailListed;  // counted behind the rounds (queueStageTail), nothing moved since
        if (total > 0) scanContacts();
    } else {
        const CellGeometry geometry = listingGeometry(resting);
        // The impact search's grid serves when nothing moved since it was built and the cells are the
        // same (no resting gap, as without gravity): one build fewer per step.
        if (m_pairsClear) m_cellList = emptyCells();  // walls only (screenStage)
        else if (!(m_cellsMatchPositions && sameGeometry(geometry, m_cellList.geometry)))
            m_cellList = m_contactCells.build(home().x.data(), m_n, geometry, contactCellSplit(), m_cellSplit.gridRadius, s);
        countContacts(true);
        // Where the last listing found contacts (this one most likely will), the impulse rows' clearing
        // (104 MB at 10^6 particles) runs while the host waits for the count and reads it. Before, the GPU
        // stood idle 26 to 33 us after each count's copy (an H200, the 10^6-ball pile, CUPTI: 1,624 such
        // waits in 5 s), then cleared the rows.
        if (m_lastListingFound && gpuCount() == 1)
            total = readBackThen(m_contactStart, size_t(m_n), clearImpulseRows);
        else
            total = readBack(m_contactStart, size_t(m_n));
    }
    m_lastListingFound = total > 0;
    m_tailListing = false;
    m_listedThisStep = true;
    const bool warm = m_firstListing && m_warmValid;  // the last step's impulses, applied before the first sweep
    m_firstListing = false;
    if (total == 0) return 0;
    m_wallsOnlyMoved = false;  // the relaxation may move particles the wall impacts did not
    m_contactPartner.resize(size_t(total));
    m_contactLambda.resize(size_t(total));
    m_contactApplied.resize(size_t(total));
    m_sweepsDone = 0;
    m_relaxationEnded = m_tallyRead = false;  // a relaxation's end and tally belong to it alone
    if (!impulsesCleared) clearImpulseRows();
    if (m_gaussSeidelContacts) m_rowTarget.resize(size_t(total));  // the fill sets the targets
    // A later listing of a step keeps the colours of the pairs the listing before coloured, and so does
    // the first listing of a step that does not colour afresh (kFreshColouringSteps).
    const bool keepAcross = warm && m_stepIndex % kFreshColouringSteps != 0;
    const bool recolour = (carry || keepAcross) && m_warmColoured && m_gaussSeidelContacts;
    if (recolour) m_prevColour.resize(size_t(total));
    gpu::ContactArgs<Real> fill = contactArgs();
    fill.warm = warm || carry;
    if (recolour) {
        fill.warmColour = m_warmColour.data();
        fill.prevColour = m_prevColour.data();
        fill.keepPushedColoursOnly = keepAcross;
    }
    gpu::launchFillContacts(fill, s);
    // The positions the relaxation's lift work is measured from, copied before the colouring's wait
    // rather than after it.
    cudaCheck(cudaMemcpyAsync(m_xListed.data(), home().x.data(), size_t(m_n) * sizeof(Vec3<Real>),
                              cudaMemcpyDeviceToDevice, s),
              "contacts");
    m_warmPending = warm;
    // The kinetic energy the core reads after the stage's first listing (not a later one: carry).
    m_gaussSeidel = m_gaussSeidelContacts && colourListing(total, recolour, !carry && !m_kineticCached);
    m_listingColoured = m_gaussSeidel;
    if (!m_gaussSeidel) m_listedOverlap = -1;  // Jacobi's first sweep measures it
    return total;
}

// The first listing of a step begins from the last step's impulses (listContacts filled them in).
template <class Real>
void CudaDevice<Real>::applyPendingWarmStart() {
    if (m_warmPending) gpu::launchWarmStart(contactArgs(), stream());
    m_warmPending = false;
}

template <class Real>
ContactResidual<double> CudaDevice<Real>::relaxContacts(int sweeps) {
    beforeStateChange();
    applyPendingWarmStart();
    if (m_gaussSeidel) gpu::launchGaussSeidelSweeps(contactArgs(), m_colourStart, sweeps, stream());
    else gpu::launchRelaxContacts(contactArgs(), sweeps, m_sweepsDone, stream());
    m_sweepsDone += sweeps;
    homeChanged();
    m_cellsMatchPositions = false;
    unsigned long long* bits = m_hostWords.resize(kHostWords);
    cudaCheck(cudaMemcpyAsync(bits, m_residual.data(), 2 * sizeof(unsigned long long), cudaMemcpyDeviceToHost, stream()), "contact residual");
    sync();
    ContactResidual<double> r{0, 0};
    std::memcpy(&r.speedChange, &bits[0], sizeof(double));
    std::memcpy(&r.overlap, &bits[1], sizeof(double));
    return r;
}

// The listing's relaxation in one launch and one wait (gpu::launchRelaxListing), from its first sweep,
// with CudaBackendOptions::fusedSteps; else the host's schedule, a launch pair a sweep and a wait a batch.
template <class Real>
RelaxationOutcome CudaDevice<Real>::relaxListing(const RelaxationPlan& plan) {
    if (!m_fusedSteps || m_sweepsDone != 0) return Backend::relaxListing(plan);
    beforeStateChange();
    cudaStream_t s = stream();
    applyPendingWarmStart();
    m_relaxationWords.resize(9);
    const bool launched = m_gaussSeidel ? gpu::launchGaussSeidelListing(contactArgs(), m_colourStart, plan, m_relaxationWords.data(), s)
                                        : gpu::launchRelaxListing(contactArgs(), plan, m_relaxationWords.data(), s);
    if (!launched) return Backend::relaxListing(plan);
    homeChanged();
    m_cellsMatchPositions = false;
    const bool tally = queueRelaxationTally();
    unsigned long long* words = m_hostWords.resize(kHostWords);
    static_assert(kHostWords >= 5, "the outcome's words");
    cudaCheck(cudaMemcpyAsync(words, m_relaxationWords.data() + 4, 5 * sizeof(unsigned long long), cudaMemcpyDeviceToHost, s),
              "contact relaxation");
    sync();
    if (tally) readRelaxationTally();
    RelaxationOutcome outcome;
    std::memcpy(&outcome.first.speedChange, &words[0], sizeof(double));
    std::memcpy(&outcome.first.overlap, &words[1], sizeof(double));
    std::memcpy(&outcome.last.speedChange, &words[2], sizeof(double));
    std::memcpy(&outcome.last.overlap, &words[3], sizeof(double));
    outcome.sweeps = int(words[4]);
    m_sweepsDone = outcome.sweeps;
    return outcome;
}

// What the core reads after a listing's relaxation (collision_rounds.cpp), queued behind its one launch
// and read back with its wait (the fused path of relaxListing): the end of the relaxation (endRelaxation's
// kernels), the work of its position moves against gravity (contactLiftWork), its impulse rows'
// sums (contactImpulses) and the step check of the state it leaves (checkStep; the kinetic energy, for
// kineticEnergy). The same kernels and sums as those calls make, so the same values, each kept until
// the state changes or the call takes it. Where the step's mail is not sized for it (no one-wait step),
// nothing: the calls wait on their own.
// Before, five more waits a listing: the settled 10^6-ball pile's GPU stood idle 15 to 26 us after each
// (an H200, CUPTI, KERNEL_TIMES_GAPS).
template <class Real>
bool CudaDevice<Real>::queueRelaxationTally() {
    const int blocks = partialBlocks();
    const size_t doubles = kStepWordDoubles + size_t(kImpulseRows + 2) * size_t(blocks);
    if (m_stepMail.size() < doubles || m_n == 0) return false;
    m_hostStepMail.resize(doubles);
    cudaStream_t s = stream();
    queueEndOfRelaxation();
    m_relaxationEnded = true;
    const size_t n = size_t(m_n);
    double* lift = m_contactImpulses.data() + size_t(kImpulseRows) * n;
    double* kinetic = lift + n;
    gpu::launchLiftWorkRow(arrays(), table(), m_xListed.data(), lift, s);
    m_tallyForecast = queueStepCheck(kinetic);
    gpu::launchBlockSums(m_contactImpulses.data(), kImpulseRows + 2, m_n, m_stepMail.data() + kStepWordDoubles, s);
    cudaCheck(
        cudaMemcpyAsync(m_hostStepMail.data(), m_stepMail.data(), doubles * sizeof(double), cudaMemcpyDeviceToHost, s),
        "step words");
    return true;
}

template <class Real>
void CudaDevice<Real>::readRelaxationTally() {
    const int blocks = partialBlocks();
    const double* partials = m_hostStepMail.data() + kStepWordDoubles;
    const std::vector<double> sums = sumPartials(partials, kImpulseRows + 1, blocks);
    m_tallyImpulses = impulseSumsOf(sums);
    m_tallyLift = sums[size_t(kImpulseRows)];
    m_tallyRead = true;
    readForecast(m_tallyForecast, hostStepWords());
    m_cachedCheck = stepCheckOf(hostStepWords(), partials + size_t(kImpulseRows + 1) * size_t(blocks));
    m_checkCached = true;
    m_cachedKinetic = m_cachedCheck.kinetic;
    m_kineticCached = true;
}

template <class Real>
void CudaDevice<Real>::endRelaxation() {
    if (m_relaxationEnded) {  // queued by queueRelaxationTally
        m_relaxationEnded = false;
        m_sweepsDone = 0;
        return;
    }
    if (m_sweepsDone == 0) return;
    queueEndOfRelaxation();
    m_sweepsDone = 0;
}

// Gauss-Seidel sweeps hold each pair's impulse in its own row, with nothing extrapolated: the other row
// takes it. Jacobi's rows go from their applied impulses to their projected ones (which moves velocities).
template <class Real>
void CudaDevice<Real>::queueEndOfRelaxation() {
    if (m_gaussSeidel)
        gpu::launchMirrorImpulses(contactArgs(), int64_t(m_contactPartner.size()), stream());
    else gpu::launchSettleContacts(contactArgs(), stream());
    homeChanged();
}

// Each pair once, from its lower index, and the walls: the contacts that end the last relaxation
// pushing (lambda > 0), from the current rows, with their colours where that listing was coloured.
template <class Real>
ContactCarryOver CudaDevice<Real>::contactWarmStart() const {
    if (!m_listedThisStep || m_n == 0) return {};
    sync();
    std::vector<int64_t> start(size_t(m_n) + 1);
    m_contactStart.download(start.data(), start.size());
    const size_t total = size_t(start.back());
    std::vector<int64_t> partner(total);
    std::vector<Real> lambda(total);
    std::vector<uint8_t> colour;
    const bool coloured = m_listingColoured && m_rowColour.size() >= total;
    if (total > 0) {
        m_contactPartner.download(partner.data(), total);
        m_contactLambda.download(lambda.data(), total);
        if (coloured) {
            colour.resize(total);
            m_rowColour.download(colour.data(), total);
        }
    }
    ContactCarryOver kept;
    for (int64_t i = 0; i < m_n; ++i) {
        for (int64_t k = start[size_t(i)]; k < start[size_t(i) + 1]; ++k) {
            const int64_t p = partner[size_t(k)];
            if (!((p < 0 || p > i) && lambda[size_t(k)] > Real(0))) continue;
            kept.impulses.push_back(ContactWarmStart{i, p, double(lambda[size_t(k)])});
            if (coloured) kept.colours.push_back(colour[size_t(k)]);
        }
    }
    return kept;
}

// Rows as a listing leaves them (both particles of a pair hold it), for the next step's first listing,
// and the records' colours on their own rows (the rows the next fill looks the pairs up in) where they
// are a colouring: one a record, every colour in range, no two contacts of a particle sharing one. Else
// none: the next listing colours afresh. The values were this precision's before the round trip through
// double: restored exactly.
template <class Real>
void CudaDevice<Real>::restoreContactWarmStart(const ContactCarryOver& carried) {
    const std::vector<ContactWarmStart>& impulses = carried.impulses;
    const size_t n = size_t(m_n);
    auto valid = [&](const ContactWarmStart& w) { return isUsableWarmStart(w, m_n); };
    std::vector<int64_t> start(n + 1, 0);
    for (const ContactWarmStart& w : impulses) {
        if (!valid(w)) continue;
        ++start[size_t(w.i) + 1];
        if (w.partner >= 0) ++start[size_t(w.partner) + 1];
    }
    for (size_t i = 0; i < n; ++i) start[i + 1] += start[i];
    const size_t total = size_t(start[n]);
    std::vector<int64_t> partner(total), slot(start.begin(), start.end() - 1);
    std::vector<Real> lambda(total);
    bool coloured = carried.colours.size() == impulses.size() && !impulses.empty();
    std::vector<uint8_t> colour(coloured ? total : 0, gpu::kUncolouredRow);
    std::vector<unsigned long long> used(coloured ? n : 0, 0);
    for (size_t r = 0; r < impulses.size(); ++r) {
        const ContactWarmStart& w = impulses[r];
        if (!valid(w)) continue;
        size_t k = size_t(slot[size_t(w.i)]++);
        partner[k] = w.partner;
        lambda[k] = Real(w.lambda);
        if (coloured) {
            const unsigned c = carried.colours[r];
            const unsigned long long bit = c < unsigned(gpu::kMaxContactColours) ? 1ull << c : 0ull;
            const bool clash =
                bit == 0 || (used[size_t(w.i)] & bit) || (w.partner >= 0 && (used[size_t(w.partner)] & bit));
            coloured = !clash;
            if (coloured) {
                used[size_t(w.i)] |= bit;
                if (w.partner >= 0) used[size_t(w.partner)] |= bit;
                colour[k] = uint8_t(c);
            }
        }
        if (w.partner < 0) continue;
        k = size_t(slot[size_t(w.partner)]++);
        partner[k] = w.i;
        lambda[k] = Real(w.lambda);
    }
    sync();
    m_contactStart.upload(start.data(), start.size());
    m_contactPartner.upload(partner.data(), partner.size());
    m_contactLambda.upload(lambda.data(), lambda.size());
    if (coloured) m_rowColour.upload(colour.data(), colour.size());
    m_listedThisStep = true;
    m_listingColoured = coloured;
}

template <class Real>
double CudaDevice<Real>::contactLiftWork() {
    if (m_tallyRead) return m_tallyLift;  // read with the relaxation (queueRelaxationTally)
    m_rows.resize(size_t(m_n));
    gpu::launchLiftWorkRow(arrays(), table(), m_xListed.data(), m_rows.data(), stream());
    return sumRows(1)[0];
}

template <class Real>
ImpulseSums CudaDevice<Real>::contactImpulses() {
    if (m_tallyRead) {  // read with the relaxation (queueRelaxationTally)
        m_tallyRead = false;
        return m_tallyImpulses;
    }
    return sumImpulseRows(m_contactImpulses);
}

template class CudaDevice<float>;
template class CudaDevice<double>;

}  // namespace corebox
