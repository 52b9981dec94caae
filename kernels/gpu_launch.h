// Host-callable launch functions of the CUDA kernels (kernels/*.cu). Each takes a plain args struct
// of device pointers and sizes plus a stream; the .cu files include no GL, GLFW or ImGui headers and
// the host side (src/cuda) never sees CUDA syntax. Templates are instantiated for float and double.
#pragma once

#include <cuda_runtime_api.h>

#include <cstdint>
#include <vector>

#include "butcher_tableau.h"
#include "cell_list.h"
#include "collision_resolution.h"
#include "collision_screen.h"
#include "contact_relaxation.h"
#include "impulse_sums.h"
#include "pair_potential.h"
#include "particle_instance.h"
#include "vec3.h"

namespace corebox::gpu {

template <class Real>
struct ParticleArrays {
    Vec3<Real>* x;
    Vec3<Real>* v;
    const int32_t* species;
    int64_t n;
};

// A particle's position or velocity with a fourth value (its hard-core radius, its mass), aligned so that
// a thread reads or writes it whole in one vector access (two for fp64): the contact phase's copy of
// the state (ContactArgs::body).
template <class Real>
struct alignas(4 * sizeof(Real)) PackedBody {
    Real x, y, z, w;
};

template <class Real>
struct SpeciesTable {
    const PairCoefficients<Real>* pairs;  // S x S
    const Real* mass;
    const Real* invMass;
    const Real* radius;
    const Vec3<Real>* field;  // per species: the acceleration of the uniform fields (gravity plus the species' own)
    int count;  // S
};

struct StepWords;
// A launch that runs only when the collision stage the device decided for this step (StepWords::stage,
// launchStageWalls) is one of `stages` (bit 1 << StageScreen), or, with runAheadOf set instead, where
// runAheadOpen(*runAheadOf, freshLists) (every thread reads the words: no launch of its own to decide);
// and, when `clear` is set, *clear is 0. Nothing set: always (every launch outside the one-wait step).
struct StageGate {
    const unsigned int* stage = nullptr;
    unsigned int stages = 0;
    const unsigned int* clear = nullptr;
    const StepWords* runAheadOf = nullptr;
    bool freshLists = false;
};
constexpr unsigned int stageBit(StageScreen s) { return 1u << unsigned(s); }

// launchBlockSums' arguments (reductions below), for a launch that sums alongside its own work (launchStageSumsAndRefresh).
struct BlockSumArgs {
    const double* values;
    int64_t n;
    double* partials;  // row r's partial of block b at [r * blocks + b]
    int blocks;        // blockSumBlocks(n)
    const char* mask;
    int maskedRows;
};

// ---- forces (force_kernels.cu) ----
// Most GPUs one simulation spreads over (the size of PeerSources below, passed by value to kernels).
constexpr int kMaxGpus = 64;

// Direct access (DA) between GPUs: the positions of particle j are read from x[j / chunk], the array
// of the GPU owning j (peer memory over unified addressing). count 0: every position from ForceArgs::x.
template <class Real>
struct PeerSources {
    const Vec3<Real>* x[kMaxGpus];
    int64_t chunk;
    int count;
};

// The lists' forecast of the next kick-drift (the one-wait step, src/cuda/cuda_step.cpp): *moves = 1 when
// x + dt (v + h a) (the next kickDrift's arithmetic) lies farther than sqrt(limit2) from xBuilt
// (indexed by particle). Off where moves is null.
// With hint set, *hint = 1 also when a second such step (its kick taken as this one's) would: a guess of
// the step after the next that lets the lists be built ahead (src/cuda/cuda_step.cpp), never relied on.
template <class Real>
struct ListForecastArgs {
    const Vec3<Real>* v;  // the force pass's rows' velocities (ForceArgs::forecast); other users pass theirs
    const Vec3<Real>* xBuilt;
    Real h, dt, limit2;
    unsigned int* moves;
    unsigned int* hint;
};

template <class Real>
struct ForceArgs {
    const Vec3<Real>* x;
    const int32_t* species;
    int64_t n;
    int64_t begin, end;  // rows computed: [begin, end) (the device's slice of the partition)
    SpeciesTable<Real> table;
    bool anyPairForce;
    bool hasCutoff;
    Vec3<Real>* acceleration;  // out: row i at acceleration[i - begin]
    double* pairEnergy;        // out when not null: sum_j U_ij of row i at pairEnergy[i - begin]
    void* scratch;             // per-chunk partial sums, forceScratchBytes large (owned by the caller)
    size_t scratchBytes;
    PeerSources<Real> peers;   // DA: where the positions are read (count 0: from x)
    // When set, rows are listed particles: row r (begin <= r < end) is particle rowIndex[r], and its
    // acceleration goes to acceleration[rowIndex[r]] (the collision stage's end-of-step accelerations);
    // from neighbour lists too when they are set and have a row per particle (one GPU).
    const int32_t* rowIndex;
    // When set with rowIndex (all pairs, no peers): the rows are [begin, begin + *rowCount) within
    // [begin, end), the count read on the device (a collision round's count, not waited for).
    const unsigned int* rowCount;
    // When set (and peers are not), forces come from neighbour lists over rows [begin, end)
    // (neighbour_list_kernels.cu) instead of all pairs.
    const int32_t* neighbours;      // partner c of row r at neighbours[c * (end - begin) + r]
    const int32_t* neighbourCount;  // per row
    int64_t listRows;               // rows of the lists (their column stride): end - begin unless rowIndex is set
    const int32_t* rowParticle;     // the particle of list row r (rows run in cell order on one GPU)
    const int32_t* rowOf;           // the list row of particle p (rowIndex passes)
    // Rows split into listLanes(n) lanes (NeighbourListArgs): lane t of row r holds the entries
    // [laneStart[t * rows + r], laneStart[(t + 1) * rows + r]) (the last lane ends at the count); null
    // with one lane.
    const int32_t* laneStart;
    // Lists only, when set (indexed by list row, read before anything else of the row): rows whose mask is 0 are skipped,
    // their acceleration kept (the refresh of the rows a collision stage touched; neighbour_list_kernels.cu).
    const unsigned char* rowMask;
    // All pairs on one GPU may evaluate each pair once (Newton's third law, pairs_once_kernels.cu)
    // where that applies (pairsOnceApplies); false: every ordered pair, the report's kernel.
    bool pairsOnce;
    // Lists only, when set: the pass also screens the collision stage at these positions (Backend::
    // screenStage) into three words, which the caller sets to (0xffffffff, 0, 0) before:
    //   screen[0]: the smallest R^2 / reach^2 over the listed pairs as float bits (rounded down), reach =
    //              screenReach(a_i + a_j, contactGap) (collision_screen.h);
    //   screen[1]: the largest deepestWallApproach(x, screenReach(a_i, contactGap)) over the particles, as
    //              float bits (rounded up), where positive; 0 where none is;
    //   screen[2]: 1 when some position is not finite.
    unsigned int* screen;
    Vec3<Real> box;
    Real contactGap;
    // Lists only, when set: each row's particle is kicked with its new acceleration, kickV[i - begin] +=
    // kickH a_i (verletKick, as launchVerletKick would after the pass: Backend::accelerateAndKick).
    Vec3<Real>* kickV;
    Real kickH;
    // Lists only: each row's forecast (ListForecastArgs, with its v) from its new acceleration.
    ListForecastArgs<Real> forecast;
    StageGate gate;  // lists only: the pass runs when the gate is open
};
template <class Real>
void launchForces(const ForceArgs<Real>& args, cudaStream_t stream);
// The particles whose position differs from xBefore: moved[i] = 1 (else 0) and their indices appended
// to movedList (in no particular order; *movedCount, reset by the launch, counts them).
template <class Real>
void launchMarkMoved(const Vec3<Real>* x, const Vec3<Real>* xBefore, int64_t n, unsigned char* moved, int32_t* movedList,
                     unsigned int* movedCount, cudaStream_t stream);
// All pairs after a collision stage that moved a few particles (movedList, ascending, count of them):
// every particle not moved exchanges each moved partner's old pair force (at xBefore) for its new one,
// partners in list order; acceleration[i] += invMass (sum of new - old). O(N x moved).
template <class Real>
void launchExchangeMovedPairForces(const ForceArgs<Real>& args, const Vec3<Real>* xBefore, const unsigned char* moved,
                                   const int32_t* movedList, int64_t movedCount, cudaStream_t stream);

// ---- neighbour lists (neighbour_list_kernels.cu) ----
// Full Verlet lists (both directions, each row sums its own pairs: no atomics, a fixed order) of rows
// [begin, end) over all n positions, from the cell list of cells >= r_c + skin: partners in the
// 27-cell walk's order (cell_list.h), so the sums are the same on every run.
// A particle of a cell list with its position, in the list's order (cell by cell): the list build
// streams these instead of gathering x[sorted[k]] from all over memory (one 16-byte load in fp32
// instead of an index and a scattered position).
template <class Real>
struct alignas(16) CellEntry {
    Real x, y, z;
    int32_t index;
};
template <class Real>
struct NeighbourListArgs {
    const Vec3<Real>* x;  // all n positions
    int64_t n, begin, end;
    const int32_t* rowParticle;  // the particle of each list row (launchListRowOrder)
    CellListView cells;   // over x, cells at least reach wide
    const CellEntry<Real>* cellEntries;  // n: entry k is particle cells.sorted[k] (launchGatherCellEntries)
    Real reach2;          // (r_c + skin)^2
    int32_t maxNeighbours;
    int32_t* neighbours;       // out: maxNeighbours x rows, partner c of row r at [c * rows + r]
    int32_t* neighbourCount;   // out: per row (may exceed maxNeighbours: then the list must grow)
    unsigned int* mostNeighbours;  // out: the largest count (atomicMax; reset by the launch)
    // listLanes(n): each row is ordered by (partner % lanes, partner), and with more than one lane
    // laneStart (lanes x rows, ForceArgs::laneStart) says where each lane's partners begin.
    int lanes;
    int32_t* laneStart;
    unsigned int* overflow;  // when set: 1 where some row has more partners than maxNeighbours (lists unusable)
};
template <class Real>
void launchBuildNeighbourList(const NeighbourListArgs<Real>& args, cudaStream_t stream);
// Threads a row of the list force pass sums with, from the particle count alone (the same for every
// pass over lists of these particles, on any number of GPUs): small systems have too few rows to hide
// the latency of a row's walk.
inline int listLanes(int64_t n) { return n <= 131072 ? 8 : n <= 524288 ? 4 : 1; }
// entries[k] = (x[sorted[k]], sorted[k]) for k < n.
template <class Real>
void launchGatherCellEntries(const Vec3<Real>* x, const int32_t* sorted, int64_t n, CellEntry<Real>* entries, cudaStream_t stream);
// The order of list rows: when the lists cover every particle, the cell list's order (neighbouring
// threads then read the same partners: the locality of a particle sort, while particle arrays, ids
// and every output keep their order); otherwise (one GPU's slice) the particles' own order.
// rowParticle[r] = particle of row r, rowOf[p - begin] = row of particle p.
void launchListRowOrder(const CellListView& cells, int64_t n, int64_t begin, int64_t end, int32_t* rowParticle, int32_t* rowOf,
                        cudaStream_t stream);
// row[r] = half the sum over row r's listed partners of r_ij . F_ij (the pair virial, each pair seen from
// both sides), partners in list order; the lists' rows must be every particle (one GPU).
template <class Real>
void launchListVirialRows(const ForceArgs<Real>& lists, double* row, cudaStream_t stream);
// touched[rowOf[p]] = 1 for every particle p (lists of every particle: one GPU) that moved, and for each
// listed partner of such a particle (full lists: exactly the rows whose sums read it); 0 elsewhere.
// Moved: moved[p] != 0 when `moved` is set, else a position that differs from xBefore. Particles are
// read in index order (coalesced), the lists only for the moved.
template <class Real>
void launchTouchMoved(const Vec3<Real>* x, const Vec3<Real>* xBefore, const char* moved, int64_t rows, const int32_t* rowOf,
                      const int32_t* neighbours, const int32_t* neighbourCount, unsigned char* touched, cudaStream_t stream);
// The end of the one-wait step's stage in one launch (its parts need only the stage pass before them):
// launchBlockSums(sums, rows), and the accelerations of the rows the stage changed recomputed (with
// ForceArgs' forecast), gated: those of the particles moved[0 .. *movedCount) (a count on the device)
// and of their listed partners (lists of every particle: one GPU; `columns` their width). In place of
// three launches (the sums, launchTouchMoved and a pass over its row mask: 4, 5 and 9 us on an H200
// for the twenty-odd particles a step's walls move in an LJ fluid of 64000, and a gap between each).
template <class Real>
void launchStageSumsAndRefresh(const BlockSumArgs& sums, int rows, const ForceArgs<Real>& refresh, const int32_t* moved,
                               const unsigned int* movedCount, int32_t columns, cudaStream_t stream);
// *moved = 1 when some row of x[begin, end) is farther than halfSkin from xBuilt (row-indexed) or not
// finite; reset to 0 by the launch.
template <class Real>
void launchListMoved(const Vec3<Real>* x, const Vec3<Real>* xBuilt, int64_t begin, int64_t end, Real halfSkin2, unsigned int* moved,
                     cudaStream_t stream);
// Scratch the force pass needs for rows [begin, end) of n particles (0 when it does not split j), and
// with pairsOnce the partial forces of the pairs-once pass where it applies: a full pass (rows = n) on
// one GPU, or a GPU's share of it (and its row sums) when `gpus` GPUs share the pass.
template <class Real>
size_t forceScratchBytes(int64_t rows, int64_t n, bool pairsOnce = false, int gpus = 1);
// Whether a full pass over n particles with these arguments evaluates each pair once (one GPU); the
// pair evaluations a full all-pairs pass does over all GPUs: n (n - 1) / 2 plus the diagonal tiles'
// extra, or n (n - 1).
template <class Real>
bool pairsOnceApplies(const ForceArgs<Real>& args);
template <class Real>
int64_t allPairsEvaluations(int64_t n, bool pairsOnce, int gpus = 1);
template <class Real>
void launchPairsOnceForces(const ForceArgs<Real>& args, cudaStream_t stream);  // pairs_once_kernels.cu
// Several GPUs sharing one pairs-once pass (pairs_once_kernels.cu): whether it applies to GPU args
// (its slice's rows, all positions, or the peers' with DA) of `gpus` GPUs that can read each other's
// memory; then every GPU k launches launchPairsOnceShare (its share of the tile pairs, and its row sums
// of every particle, pairsOnceRowSums), and once every GPU's share is done (a barrier across the
// streams) launchPairsOnceCombine: its slice's accelerations from the GPUs' row sums in GPU order.
template <class Real>
struct PairsOnceSums {
    const Vec3<Real>* rows[kMaxGpus];  // GPU g's row sums (n), read in place over peer access
    int count;
};
template <class Real>
bool pairsOnceAppliesAcross(const ForceArgs<Real>& args, int gpus);
template <class Real>
Vec3<Real>* pairsOnceRowSums(const ForceArgs<Real>& args, int gpus);
template <class Real>
void launchPairsOnceShare(const ForceArgs<Real>& args, int gpu, int gpus, cudaStream_t stream);
template <class Real>
void launchPairsOnceCombine(const ForceArgs<Real>& args, const PairsOnceSums<Real>& sums, cudaStream_t stream);

// ---- integration (integrate_kernels.cu) ----
template <class Real>
struct StageArgs {
    const Vec3<Real>* x0;
    const Vec3<Real>* v0;
    Vec3<Real>* kx;  // stage-major, stages * n
    Vec3<Real>* kv;
    Vec3<Real>* xOut;
    Vec3<Real>* vOut;
    int64_t n;
    int stage;  // stage index, or -1 for the final combination with b
    int count;  // weights used
    Real dt;
    const ButcherTableau* tableau;  // device copy owned by the backend (read-only, the same for every thread)
};
// Stage state Y_s = y0 + dt sum_{j<s} a_sj K_j into (xOut, vOut) and kx[s] = vOut; or, with
// stage = -1, the solution y0 + dt sum b_j K_j.
template <class Real>
void launchStage(const StageArgs<Real>& args, cudaStream_t stream);
// Per-particle scaled error of the embedded pair into errorOut (summed by the caller).
template <class Real>
void launchErrorNorm(const StageArgs<Real>& args, double tolerance, double* errorOut, cudaStream_t stream);

// Velocity Verlet's halves: v += h a, and x += dt v.
template <class Real>
void launchVerletKick(Vec3<Real>* v, const Vec3<Real>* a, int64_t n, Real h, cudaStream_t stream);
template <class Real>
void launchVerletDrift(Vec3<Real>* x, const Vec3<Real>* v, int64_t n, Real dt, cudaStream_t stream);
template <class Real>
void launchScale(Vec3<Real>* v, int64_t n, Real alpha, cudaStream_t stream);

// ---- cell list (cell_list_kernels.cu; layout and rule in cell_list.h) ----
template <class Real>
struct CellListArgs {
    const Vec3<Real>* x;    // n positions
    int64_t n;              // at most INT32_MAX
    CellGeometry geometry;  // from cellGeometry (the one rule)
    int32_t* cellStart;     // out: cells + 1
    int32_t* sorted;        // out: n particle indices by ascending (cell key, index)
    uint32_t* keys;         // scratch: n cell keys
    uint32_t* sortedKeys;   // scratch: n cell keys, sorted
    int32_t* indices;       // scratch: n (0 .. n-1, the values the sort carries; the counted build's ranks)
    void* scratch;          // radix sort and scan scratch, cellListScratchBytes(n) large
    size_t scratchBytes;
    int32_t* counts;        // scratch for launchCountedCellList: cells + 1 (may be null otherwise)
    unsigned int* crowded;  // scratch for launchCountedCellList: one word
    CellSplit<Real> split;  // particles kept out of the cells (cell_list.h), none by default
    double gridRadius;      // the largest radius left in the cells, where split names species

    CellListView view() const {
        return splitView(CellListView{geometry, cellStart, sorted}, largeAboveOf(split), gridRadius, n);
    }
};
// Bytes of radix-sort and scan scratch a cell list of n particles needs.
size_t cellListScratchBytes(int64_t n);
// Whether launchBuildCellList builds n particles in one launch (one block), not several.
bool cellListBuildIsOneLaunch(int64_t n);
// Keys per particle, a stable radix sort of (key, index) pairs, then cellStart by a binary search per
// cell: no atomics, so the arrays are the same on every run and equal to the host's counting sort.
template <class Real>
void launchBuildCellList(const CellListArgs<Real>& args, cudaStream_t stream);
// The same arrays by a counting sort, for builds captured into a graph (DeviceCellList): each particle's
// key and its rank among its cell's particles by atomics (in no order), the cell starts by a scan, the
// particles placed by rank, then each cell's entries put in ascending index. A cell of more than
// kCountedCellMost particles (a blow-up crowds them into one) would make that last pass quadratic: it is
// left, and `crowded` set as the graph's IF condition, whose body is to be the radix build
// (launchBuildCellList), which writes every array again. Above cellListBuildIsOneLaunch only.
constexpr int32_t kCountedCellMost = 32;
template <class Real>
void launchCountedCellList(const CellListArgs<Real>& args, cudaGraphConditionalHandle crowded, cudaStream_t stream);
// The counted build, in one cooperative launch of cellListIfMovedBlocks blocks, where *moved != 0 (which
// it clears), else nothing (DeviceCellList::rebuildIfMoved); the same arrays, a crowded cell included.
// blockTotals: scratch of cellListIfMovedBlocks words. 0 blocks: no cooperative launch on this device.
// Above cellListBuildIsOneLaunch only.
template <class Real>
int cellListIfMovedBlocks();
template <class Real>
void launchCellListIfMoved(const CellListArgs<Real>& args, unsigned int* moved, int32_t* blockTotals,
                           cudaStream_t stream);

// ---- impact candidate rows (impact_candidate_kernels.cu; walks in impact_candidates.cuh) ----
// Design note. A stage's impact rounds search the same neighbourhoods again and again, and in a landing
// every round moves some particle out of its cell, so each round built the cells again and each search
// walked 27 cells (about 30 particles in a dense pile) for its dozen neighbours. Candidate rows are a
// Verlet list for the rounds: each particle's row holds the particles that were within a_i + a_j +
// margin when the rows were made, and they hold every pair that can overlap until some particle has
// moved half the margin since (checked where positions change: a stage's start, each resolution).
// The searches then read the row (the same events: each particle's earliest by a total order,
// collision_resolution.h isBetter, from any superset of its overlapping pairs), and the cells and rows
// are made again only when stale, gated on the device. A row that overflowed (more than `slots`
// candidates: large particles among small ones) is walked in the cells of the rows' build around the
// particle's position at that build, which hold the same superset.
// Measured on an H200 (fp32, the same bits with rows and with cells, separate runs in one call): the
// sandbox example at 10^5 balls spent 12.1 and 11.6 ms a landing frame (frames 158 to 183) in its impact
// rounds against 18.7 and 18.7 (a round's build, search and resolution 27 us of kernels against about 60,
// CUPTI); `corebox bench pile` 10^6 balls 28.47 and 28.49 ms a frame against 31.71, and in another call
// 28.36 against 32.22; 10^5 balls 7.47 against 8.25. Where the integrator swaps its position buffers
// every step (the Runge-Kutta methods), the cells' build sees new arguments and is made each step, and
// the rows with it: the same results, the saving then only within a step's rounds.
// Slots a row: in a dense packing of equal spheres 12 touch each one, and within a margin of 0.3 of a
// diameter the second shell is not reached (1.41 diameters in a close packing).
constexpr int kCandidateSlots = 32;
template <class Real>
struct CandidateRows {
    const int32_t* rows = nullptr;       // n rows of `slots`: row i at rows[i * slots], counts[i] used
    const int32_t* counts = nullptr;     // candidates of particle i; above `slots`: the row overflowed
    const Vec3<Real>* xBuilt = nullptr;  // each particle's position when the rows were made
    int slots = 0;
    Real halfMargin2 = 0;  // a particle farther than this (squared) from xBuilt makes the rows stale [sigma^2]
};
template <class Real>
struct CandidateFillArgs {
    const Vec3<Real>* x;
    const int32_t* species;
    const Real* radius;  // per species
    int64_t n;
    CellListView grid;  // built from x, cells at least the largest small a_i + a_j + margin wide
    Real margin;        // [sigma]
    int32_t* rows;
    int32_t* counts;
    Vec3<Real>* xBuilt;
    int slots;
};
// Every particle's row, count and xBuilt from x (CandidateRows): its candidates in the order of its
// cell walk (cell_list.h forEachNeighbour), the same on every run.
template <class Real>
void launchFillCandidates(const CandidateFillArgs<Real>& args, cudaStream_t stream);
// The cells' gated build of launchCellListIfMoved (where *moved != 0, which it clears) and then, in the
// same cooperative launch of candidateBuildBlocks blocks, the rows of launchFillCandidates from those
// cells (fill.grid their view): one launch a round where there were two, each with its own gate. An
// H200, fp32, against the two launches (separate libraries in one call, the same bits): the sandbox at
// 10^5 balls 10.6 and 10.5 ms a landing frame in its impact rounds against 11.0 and 10.9; `corebox bench
// pile` 10^6 balls 28.21 ms a frame against 28.32, 10^5 7.19 against 7.09.
template <class Real>
int candidateBuildBlocks();
template <class Real>
void launchCellListIfMovedThenFill(const CellListArgs<Real>& args, unsigned int* moved, int32_t* blockTotals,
                                   const CandidateFillArgs<Real>& fill, cudaStream_t stream);
// *stale = 1 where some particle of x (n) has moved too far from where `rows` were made for them to hold
// (or is not finite); left as it is otherwise.
template <class Real>
void launchCandidateStaleness(const Vec3<Real>* x, int64_t n, const CandidateRows<Real>& rows, unsigned int* stale,
                              cudaStream_t stream);

// ---- collisions (collision_kernels.cu) ----
// One impact of the contact log (backend.h ContactRecord, before the host converts it): the particle
// that resolved it, the round, its event's partner code and how it went.
template <class Real>
struct ImpactRecord {
    int64_t particle;
    int64_t partner;  // particle index, or wall code -1 - (2 axis + side)
    int32_t round;
    ImpactDetail<Real> detail;
};

// The contact log in the CPU's order, by round and then by the resolving particle (one record each a
// round: the keys are unique), sorted on the device: each record's key radix-sorted with its place,
// then the records gathered in that order into `sorted`. rounds: more than the largest round of the
// log. Scratch of impactLogSortBytes(count) bytes. Sorted on the host (std::sort), the sandbox example
// at 10^5 balls (an H200, fp32, one call) took 23.6 and 23.7 ms of simulation a landing frame against
// 21.3 and 21.4: the sort stood between the steps, the GPU idle.
size_t impactLogSortBytes(int64_t count);
template <class Real>
void launchSortImpactLog(const ImpactRecord<Real>* log, int64_t count, int32_t rounds, ImpactRecord<Real>* sorted,
                         void* scratch, size_t scratchBytes, cudaStream_t stream);

template <class Real>
struct CollisionArgs {
    ParticleArrays<Real> p;
    SpeciesTable<Real> table;
    Vec3<Real> box;
    CellListView grid;  // contacts: cells at least the largest a_i + a_j of the particles in them wide (cell_list.h)
    CollisionEvent* events;
    char* active;
    Vec3<Real>* contactAcceleration;
    char* hasContactAcceleration;
    int32_t* needList;         // particles needing an acceleration this round
    unsigned int* counters;    // [0] particles listed in needList, [1] particles with an event, [2] log records
    unsigned long long* kindCounts;  // pair, wall
    double* loss;              // per particle
    double* impulses;          // kImpulseRows x n (impulse_sums.h), per particle: walls, wall centres, pair virial
    Real restitution, wallRestitution, elasticBelow;
    ImpactWindow<Real> window;  // which overlaps are impacts of this step
    // The contact log, when set: each resolved impact appended at log[(*logCount)++] (in no particular
    // order: the host sorts), room for every particle with an event this round left by the caller.
    ImpactRecord<Real>* log;
    unsigned int* logCount;
    int32_t logRound;  // this step's rounds with events before this one
    double logMinImpulse;  // impacts whose impulse magnitude is below this are not logged (compared in double)
    // When set, the search, the resolution and the active flags do nothing where *gate == 0: a round
    // queued behind one that found no event (CudaDevice::runImpactRounds).
    const unsigned int* gate;
    // The search lists each particle with an event at activeOut[its count in counters[1]] where set.
    int32_t* activeOut;
    // A round after the first (launchMarkSearchers): walker[i] = 1 for every particle within the cells
    // around a particle of activeIn[0 .. *activeInCount) (the round before's activeOut and count); the
    // search then skips every particle left unmarked (and clears the marks it reads). Null: every
    // particle searches. The active flags of that list are cleared before the listed resolution
    // (launchResolveListed, or the scattered search's collection: clearActiveIn). Both rely on a
    // particle that does not search keeping the no-event of its last search (every particle with an
    // event this round is in activeOut).
    unsigned char* walker;
    const int32_t* activeIn;
    const unsigned int* activeInCount;
    // The scattered search (launchScatteredSearch, launchSparseOrFullSearch) of a round whose activeIn
    // holds at most this many particles (and at most one in kListedScatterShare) walks from that list,
    // kListedScatterLanes lanes a particle; 0: never.
    int64_t listedScatterMax;
    // The scattered search's collection of the offered events also clears the active flags of activeIn
    // (the searches before it have read them), which launchResolveListed then leaves, for one launch fewer
    // a round (CudaDevice::searchRound: a round after the first of a narrowable stage; the host-driven
    // rounds resolve a thread a particle after it, which sets every particle's flag).
    bool clearActiveIn;
    // When set, the resolution sets *cellsMoved = 1 where a particle it moves leaves the cell key
    // cellKeys[i] the last build of `grid` gave it (with cellSplit, the build's split): a round after
    // one that moved nobody out of a cell skips its build (CudaDevice::runImpactRounds).
    const uint32_t* cellKeys;
    CellSplit<Real> cellSplit;
    unsigned int* cellsMoved;
    // When candidates.rows is set, the searches read each particle's candidate row instead of walking
    // the cells around it (`grid` is then the rows' build: CandidateRows), and the resolution sets
    // *staleNext where a particle it moves ends farther than the rows allow from its xBuilt (the next
    // round's cells and rows are then made again).
    CandidateRows<Real> candidates;
    unsigned int* staleNext;
};
// A collision stage opened in one launch (CudaDevice::beginCollisions): for every particle i, where
// active is set, active[i] = startsActive(v[i], restingSpeed) (the first round's active particles);
// with `events`, events[i] = none (a scattered first round, whose inactive particles do not search,
// leaves theirs as they are); where flagged[i], rows[r * n + i] = 0 for r < rowCount and flagged[i] = 0
// (the impact rows only the last stage's particles with events wrote); kindCounts[0..2] = 0; and
// zero[0 .. zeroCount) = 0 (the rounds' counters).
template <class Real>
struct StageOpenArgs {
    char* active;
    const Vec3<Real>* v;
    Real restingSpeed;
    CollisionEvent* events;
    double* rows;
    int rowCount;
    int64_t n;
    char* flagged;
    unsigned long long* kindCounts;
    unsigned int* zero;
    int64_t zeroCount;
};
template <class Real>
void launchOpenStage(const StageOpenArgs<Real>& args, cudaStream_t stream);
// Each particle's earliest event (all neighbours when active, else only active ones); counts the
// particles with an event into counters[1], and lists those that still need a contact acceleration
// (counted in counters[0]; marked as having one: the caller computes them next, by a force pass
// over the listed rows, ForceArgs::rowIndex).
template <class Real>
void launchFindEvents(const CollisionArgs<Real>& args, cudaStream_t stream);
// A round in fp32, as launchFindEvents finds it: only the active particles (CollisionArgs::active: in a
// stage's first round the movers, collision_resolution.h startsActive; later, those with an event in the
// round before) search, and offer each inactive neighbour they meet the pair's
// event through offered[] (n words, zero, and left zero); then the offered events are kept, counted and
// listed as the search lists its own. The inactive particles walk no cells (collision_kernels.cu).
void launchScatteredSearch(const CollisionArgs<float>& args, unsigned long long* offered, cudaStream_t stream);
// A round of n particles as launchFindEvents finds it, every particle searching, but where the round
// before's list (activeIn) is short (CollisionArgs::listedScatterMax), scattered from that list as
// launchScatteredSearch scatters it: for systems whose rounds are searched by every particle.
void launchSparseOrFullSearch(const CollisionArgs<float>& args, unsigned long long* offered, cudaStream_t stream);
constexpr int kListedScatterLanes = 32;
constexpr int64_t kListedScatterShare = 8;
constexpr int64_t kListedScatterMax = 32768;
// Whether launchFindEvents walks a thread a particle at n particles (neighbour_walk.cuh: searchGroupFor),
// as the scattered search always does: where it gives a particle several lanes, its particles are few.
bool searchWalksAlone(int64_t n);
// Marks the particles whose search can find an event this round (CollisionArgs::walker): an inactive
// particle meets only active ones, which all lie within the cells around it, so a particle with no
// active one in its cells keeps the no-event its last search left. Gated as the search.
template <class Real>
void launchMarkSearchers(const CollisionArgs<Real>& args, cudaStream_t stream);
// Resolves the matching of mutual-earliest events and adds to the kind counts and losses (a pair by
// its lower index, as the CPU), and to the contact log when it is set; active[i] = particle i had an
// event this round (the next search's flags).
template <class Real>
void launchResolve(const CollisionArgs<Real>& args, cudaStream_t stream);
// The same from this round's list of the particles with events (activeOut, counters[1] of them, as the
// search listed them) instead of a thread a particle, after the flags of the round before's list
// (activeIn, *activeInCount) are cleared (here, or by the search where clearActiveIn): the same events,
// bits and flags where the active flags are that list's (the round before resolved with either). Gated
// as launchResolve.
template <class Real>
void launchResolveListed(const CollisionArgs<Real>& args, cudaStream_t stream);
// Walls only (no pair can meet in this stage, CudaDevice::screenStage): every particle resolves its wall
// impacts one after another, earliest first, as the rounds would one a round (particles do not meet,
// so each particle's sequence is the rounds' sequence), with `acceleration` the end-of-step
// accelerations (the rounds' contact accelerations: the same pass at the same positions). Adds to the
// kind counts, losses and impulse rows as launchResolve does and marks the particles with an impact in
// hasContactAcceleration (the rows the tally reads). stats[0] = most impacts of one particle (atomicMax),
// stats[1] = 1 when some particle ends within contactGap (with the screen's margin) of a wall, or
// overlapping it: the contact phase may list it; stats[2] = 1 when a particle with an impact ends
// farther than sqrt(halfSkin2) from xBuilt (its position at the neighbour lists' build, indexed by
// particle; null: not checked): the lists may no longer hold its partners. No contact log (the caller
// runs the rounds then).
// The caller zeroes the stats before.
template <class Real>
void launchResolveWallImpacts(const CollisionArgs<Real>& args, const Vec3<Real>* acceleration, Real contactGap, const Vec3<Real>* xBuilt,
                              Real halfSkin2, unsigned int* stats, cudaStream_t stream);

// ---- contact relaxation (contact_kernels.cu) ----
template <class Real>
struct ContactArgs {
    ParticleArrays<Real> p;
    SpeciesTable<Real> table;
    Vec3<Real> box;
    CellListView cells;       // cells at least the largest contact distance in them plus the resting gap wide
    int64_t* contactStart;    // n + 1: particle i's contacts are partner[contactStart[i] .. contactStart[i + 1])
    int64_t* partner;         // particle index, or wall code -1 - (2 axis + side)
    RestingContact<Real> resting;
    Vec3<Real> up;            // against gravity, unit (0 without gravity): overlapShare
    ContactBounce<Real> bounce;  // which contacts keep their restitution (contactRestitution)
    Vec3<Real>* dv;           // n: one sweep's velocity change
    Vec3<Real>* dx;           // n: one sweep's position change
    unsigned long long* residual;  // [speed change, overlap] as the bits of non-negative doubles (max)
    double* impulses;         // kImpulseRows x n (impulse_sums.h): each particle's impulses since the listing
    Real* lambda;             // per listed contact, as partner[]: its accumulated impulse (contact_relaxation.h)
    // The last step's rows for the warm start (warm: the fill takes each contact's lambda from them).
    bool warm;
    const int64_t* warmStart;
    const int64_t* warmPartner;
    const Real* warmLambda;
    // A later listing of a step (the warm rows are the step's listing before, coloured), or the first
    // listing of a step that keeps the last step's colours (cuda_collisions.cpp: kFreshColouringSteps):
    // the warm rows' colours (kUncolouredRow for rows not their pair's own), and per row the colour the
    // fill finds there for its pair, which the colouring keeps (contact_gauss_seidel.cu). Null otherwise.
    const uint8_t* warmColour;
    uint8_t* prevColour;
    // The first listing of a step keeps a colour only where the warm row pushed (warmLambda > 0): the
    // rows a checkpoint or a World edit carries (ContactCarryOver), so that a restart keeps the same.
    bool keepPushedColoursOnly;
    // Per listed contact, as lambda: the extrapolated impulse the velocities hold (the accelerated
    // sweeps, contact_relaxation.h: acceleratedImpulse).
    Real* applied;
    // Gauss-Seidel in colours (contact_gauss_seidel.cu). A pair's own row is the one in its lower
    // index's list (a wall's, its particle's); per row: its particle, the pair's own row (mirror), the
    // colour (own rows) and the normal speed its stopping update aims at (0 but for a bounce; the fill
    // sets it when gaussSeidel).
    bool gaussSeidel;
    int64_t* rowParticle;
    int64_t* mirror;
    uint8_t* colour;
    Real* target;
    // kMaxContactColours + 1: colour c's own rows are packed at colourStart[c] .. colourStart[c + 1].
    int32_t* colourStart;
    // The own rows packed at their place e, by colour and within a colour in row order (what the sweeps read and
    // write), and each own row's place: rowRank[s] = e (of a coloured listing: where the colouring fails, nothing
    // packed is read). The sweeps keep a row's impulse here; the mirror kernels hand the impulses back to the rows
    // and add the pair virials r . J of the sweeps' net impulses to the impulse rows.
    int32_t* packedParticle;
    int32_t* packedPartner;
    Real* packedTarget;
    Real* packedLambda;
    int32_t* rowRank;
    // 2n: the contact phase's copy of X with each radius and of V with each mass, particle i's side by
    // side at 2i and 2i + 1 (packed_body.cuh says why: xBody, vBody): packed by the count, which the
    // fill reads too, and again before a listing's Gauss-Seidel sweeps, which write it back into p
    // when they end.
    PackedBody<Real>* body;
    // n x kListedPartners, where set (contactCountListsPartners): the count writes each particle's first
    // kListedPartners contacts here in list order, as whole 16-byte vectors (the entries past a particle's
    // count hold no contact: readers stop at the count), and the fill copies them instead of walking the
    // cells again (a particle with more walks them again); the colouring finds a pair's own row in its
    // partner's (mirrorRowOf). Each particle's 16 entries begin on a 64-byte boundary.
    int32_t* partnerScratch;
    Real omega;            // over-relaxation of the stopping updates (kGaussSeidelOverRelaxation)
    bool streamRows = false;  // the Gauss-Seidel sweeps stream their packed rows (contact_gauss_seidel.cu)
    int sweepBlocks = 0;      // tests: at most this many blocks for a listing's sweeps in one launch (0: as fit)
};

// The colour of an own row not coloured yet, and of every row that is not own.
constexpr uint8_t kUncolouredRow = 0xFF;
// The most colours a listing's pairs may take: a particle's colours are a 64-bit mask. A listing that
// needs more (a particle with more than ~32 contacts) is relaxed with Jacobi sweeps.
constexpr int kMaxContactColours = 64;
// Contacts a particle's count lists for the fill (ContactArgs::partnerScratch): monodisperse balls have
// at most 15 (12 neighbours and 3 walls).
constexpr int kListedPartners = 16;
// Whether the count of n particles lists them: where a thread walks a particle's cells alone (the walks of
// several lanes a particle visit its contacts out of list order), and indices fit 32 bits.
bool contactCountListsPartners(int64_t n);
// body from p (X with each radius, V with each mass), and back into p.
template <class Real>
void launchPackBodies(const ContactArgs<Real>& args, cudaStream_t stream);
template <class Real>
void launchUnpackBodies(const ContactArgs<Real>& args, cudaStream_t stream);
// contactStart[i + 1] = particle i's contact count (contactStart[0] = 0); the caller scans it. With
// total set, the counts are also added into *total (zeroed by the caller). Packs the bodies first
// (launchPackBodies), which it and the fill read.
template <class Real>
void launchCountContacts(const ContactArgs<Real>& args, cudaStream_t stream, unsigned long long* total = nullptr);
// Exclusive-scans counts in place into offsets: n + 1 entries.
size_t contactScanScratchBytes(int64_t n);
void scanContactCounts(int64_t* contactStart, int64_t n, void* scratch, size_t scratchBytes, cudaStream_t stream);
// Fills partner[] in the order the count visited them (cell-list order, then walls), and lambda[],
// from the bodies the count packed (nothing may move in between):
// with `warm`, each contact's impulse at the end of the last step (0 for a new or isolated contact).
template <class Real>
void launchFillContacts(const ContactArgs<Real>& args, cudaStream_t stream);
// lambda[s] = 0 where target[s] > 0 (a Gauss-Seidel listing's bounces), for `rows` rows: what a later
// listing of the step carries is support, not impacts.
template <class Real>
void launchDropBounceImpulses(Real* lambda, const Real* target, int64_t rows, cudaStream_t stream);
// Applies the filled impulses to V (the warm start), before the first sweep.
template <class Real>
void launchWarmStart(const ContactArgs<Real>& args, cudaStream_t stream);
// Ends the accelerated sweeps: each row from its applied impulse to its projected one (settleRow).
template <class Real>
void launchSettleContacts(const ContactArgs<Real>& args, cudaStream_t stream);
// One Jacobi sweep (contact_relaxation.h: relaxParticle) then the update, `sweeps` times; the
// residual holds the maxima of the last sweep.
template <class Real>
void launchRelaxContacts(const ContactArgs<Real>& args, int sweeps, int firstSweep, cudaStream_t stream);
// A listing's whole relaxation (the sweeps of launchRelaxContacts from the listing's first, on the
// plan's schedule) in one cooperative launch; words (9): the outcome, read back by the caller ([4..5]
// the first sweep's residual, [6..7] the last's, as double bits; [8] the sweeps run). Returns false,
// launching nothing, where the device has no cooperative launch (the caller runs the sweeps itself).
template <class Real>
bool launchRelaxListing(const ContactArgs<Real>& args, const RelaxationPlan& plan, unsigned long long* words, cudaStream_t stream);
// ---- Gauss-Seidel in colours (contact_gauss_seidel.cu) ----
// Colours the listing's pairs and walls so that no particle has two contacts of one colour (each
// pair from its own row; rowParticle, mirror and the bounce targets filled on the way), then sorts
// the own rows by colour (colourStart) and packs them (packed*, rowRank). words (6): [0]
// the colours used, [1] 1 if more than kMaxContactColours were needed (then nothing after the
// colouring is valid), [2..3] the colouring's own (its lists' lengths); *deepest: the deepest overlap
// of the listed contacts (double bits, ContactResidual::overlap). Scratch:
// contactColouringScratchBytes. Returns false, launching nothing, where the device has no cooperative
// launch.
size_t contactColouringScratchBytes(int64_t n, int64_t rows);
template <class Real>
bool launchColourContacts(const ContactArgs<Real>& args, int64_t rows, void* scratch, size_t scratchBytes, unsigned int* words,
                          unsigned long long* deepest, cudaStream_t stream);
// `sweeps` Gauss-Seidel sweeps over the colours 0 .. colours - 1 (sizes from colourStart as the host
// read it), a launch a colour; the residual holds the maxima of the last sweep.
template <class Real>
void launchGaussSeidelSweeps(const ContactArgs<Real>& args, const std::vector<int32_t>& colourStart, int sweeps, cudaStream_t stream);
// The relaxation of launchRelaxListing in coloured Gauss-Seidel sweeps: one cooperative launch, the
// same words. Returns false, launching nothing, without cooperative launch.
template <class Real>
bool launchGaussSeidelListing(const ContactArgs<Real>& args, const std::vector<int32_t>& colourStart, const RelaxationPlan& plan,
                              unsigned long long* words,
                              cudaStream_t stream);
// Each of the listing's `rows` rows takes its pair's impulse from the packed own row (as Jacobi leaves both
// rows): the rows the next step's warm start and a checkpoint read; before that, each own pair row's virial
// of the listing (its net impulse at its separation after the sweeps) joins the impulse rows.
template <class Real>
void launchMirrorImpulses(const ContactArgs<Real>& args, int64_t rows, cudaStream_t stream);

// row[i] = -m_i g_i . (x_i - xListed_i): the work against the uniform field of particle i's species
// (SpeciesTable::field) of its contact moves.
template <class Real>
void launchLiftWorkRow(const ParticleArrays<Real>& p, SpeciesTable<Real> table, const Vec3<Real>* xListed, double* row,
                       cudaStream_t stream);

// ---- pressure (pressure_kernels.cu) ----
// row[i] = sum_{j != i} r_ij . F_ij / 2 over all pairs: summed over i, the pair-force virial.
template <class Real>
void launchPairVirialRow(const ParticleArrays<Real>& p, SpeciesTable<Real> table, double* row, cudaStream_t stream);

// ---- reductions (reduce_kernels.cu) ----
// Sums of per-particle quantities: rows of `values` (row-major, rows x n) reduced into per-block
// partials (rows x blocks); returns the number of blocks. With a mask, only the entries i with
// mask[i] != 0 are read, the others taken as zero: the same sums where they are zero, without reading
// them (the collision stage's impulse rows: a few hundred particles of 10^7 have events).
// With maskedRows >= 0, the mask applies to the first maskedRows rows only.
int launchBlockSums(const double* values, int rows, int64_t n, double* partials, cudaStream_t stream, const char* mask = nullptr,
                    int maskedRows = -1);
int blockSumBlocks(int64_t n);

template <class Real>
struct EnergyArgs {
    ParticleArrays<Real> p;
    SpeciesTable<Real> table;
    const double* pairEnergy;  // per particle (may be null)
    double* rows;              // out: (S + 4) x n: kinetic per species, potential, px, py, pz
};
template <class Real>
void launchEnergyRows(const EnergyArgs<Real>& args, cudaStream_t stream);
template <class Real>
void launchKineticRow(const ParticleArrays<Real>& p, SpeciesTable<Real> table, double* row, cudaStream_t stream);

template <class Real>
struct HealthArgs {
    ParticleArrays<Real> p;
    Vec3<Real> box;
    unsigned long long* counts;  // nonFinite, outside, examples used
    long long* examples;         // 5 slots
};
template <class Real>
void launchHealth(const HealthArgs<Real>& args, cudaStream_t stream);

// ---- the one-wait step (step_kernels.cu, src/cuda/cuda_step.cpp) ----
// Everything the host reads at the end of a step, in one block of device memory (one copy back).
struct StepWords {
    unsigned long long kindCounts[3];    // CollisionArgs::kindCounts: pair, wall
    unsigned long long healthCounts[3];  // HealthArgs::counts
    unsigned long long listedContacts;   // launchCountContacts' total (the stage's tail, CudaDevice::queueStageTail)
    long long healthExamples[5];         // HealthArgs::examples
    unsigned int screen[3];              // ForceArgs::screen
    unsigned int wallStats[3];           // launchResolveWallImpacts' stats
    unsigned int stage;                  // the StageScreen the device read from the screen (launchStageWalls)
    unsigned int listForecast;           // StepCheckArgs: 1 when the next kick-drift takes some row past half the skin
    unsigned int listHint;               // ListForecastArgs::hint: 1 when the one after it may
    unsigned int wallMoved;              // launchStageWalls: the particles its walls moved (StageOpening::moved)
    unsigned int listOverflow;           // NeighbourListArgs::overflow of a build the host did not wait for
    unsigned int wallContacts;           // launchStageWalls: particles with a wall contact to list after the impacts
};
// Zeroes the words, the screen's nearest ratio set to "none" (0xffffffff): before a screening pass.
void launchResetStepWords(StepWords* words, cudaStream_t stream);
// The one-wait step's stage in one pass (collision_kernels.cu): every thread reads the screen into a
// verdict (screenVerdict, collision_screen.h: the host's reading, on the device; thread 0 records it
// in words->stage); where the verdict is WallsOnly, it opens the
// stage as beginCollisions does (the impact rows of the particles the last stage flagged zeroed, the
// flags cleared), resolves its particle's walls as launchResolveWallImpacts (stats in
// words->wallStats) and counts it into words->wallContacts when it then has a wall contact the
// contact phase would list (contact_relaxation.h wallContactActive with `resting`: with no pair
// within reach, the listing's whole count) and lists it in `moved` when its walls moved it; then it
// checks its particle (health words, kineticRow) and forecasts it (StageOpening::forecast).
template <class Real>
struct StageOpening {
    StepWords* words;
    ScreenScales scales;
    RestingContact<Real> resting;
    double* kineticRow;
    int32_t* moved;  // the particles its walls moved, words->wallMoved of them (launchStageSumsAndRefresh)
    // Each particle's forecast from the state the stage leaves and its acceleration before the refresh;
    // the refresh's pass forecasts its rows again (an extra "beyond" at worst, from a row it changes).
    ListForecastArgs<Real> forecast;
};
template <class Real>
void launchStageWalls(const CollisionArgs<Real>& args, const Vec3<Real>* acceleration, Real contactGap, const Vec3<Real>* xBuilt,
                      Real halfSkin2, const StageOpening<Real>& opening, cudaStream_t stream);
// The end of a step: with health.counts set, each particle's health (launchHealth) and kinetic energy
// (into kineticRow, launchKineticRow); with forecast.moves set, the lists' forecast (ListForecastArgs)
// from these accelerations.
template <class Real>
struct StepCheckArgs {
    HealthArgs<Real> health;
    SpeciesTable<Real> table;
    double* kineticRow;
    const Vec3<Real>* acceleration;
    ListForecastArgs<Real> forecast;
};
template <class Real>
void launchStepCheck(const StepCheckArgs<Real>& args, cudaStream_t stream);
// v += h a, then x += dt v (verletKick, verletDrift) in one pass; with snapshotX set, (x, v) are
// copied there first (Backend::keepSnapshot); with reset set, the step words are reset as
// launchResetStepWords does. The results go to xOut and vOut (x and v themselves for a step in place),
// and nothing at all is done where the gate is closed.
template <class Real>
struct KickDriftArgs {
    const Vec3<Real>* x;
    const Vec3<Real>* v;
    const Vec3<Real>* a;
    Vec3<Real>* xOut;
    Vec3<Real>* vOut;
    int64_t n;
    Real h, dt;
    Vec3<Real>* snapshotX;
    Vec3<Real>* snapshotV;
    StepWords* reset;
    StageGate gate;
};
template <class Real>
void launchKickDrift(const KickDriftArgs<Real>& args, cudaStream_t stream);

// Whether the step these words close leaves nothing for the host to do before the next Verlet step
// (src/cuda/cuda_step.cpp, running ahead): a quiet stage, or walls the device resolved with every
// moved row within the lists and no wall contact to list; the lists good for the next kick-drift;
// every particle finite and inside. Read alike on the device (StageGate::runAheadOf) and on the host.
// With freshLists, the step that runs ahead builds its own lists: the forecast does not matter.
COREBOX_HD inline bool runAheadOpen(const StepWords& w, bool freshLists = false) {
    const bool stageDone = w.stage == unsigned(StageScreen::Quiet) ||
                           (w.stage == unsigned(StageScreen::WallsOnly) && w.wallStats[2] == 0 && (w.wallStats[1] == 0 || w.wallContacts == 0));
    return stageDone && (freshLists || w.listForecast == 0) && w.listOverflow == 0 && w.healthCounts[0] == 0 &&
           w.healthCounts[1] == 0;
}

// ---- interop (interop_kernels.cu) ----
// Writes the renderer's instances (particle_instance.h) into device memory: a mapped GL buffer or a
// staging buffer.
template <class Real>
void launchFillInstances(const ParticleArrays<Real>& p, const Real* radius, InstanceKey key, ParticleInstance* out, cudaStream_t stream);

}  // namespace corebox::gpu
