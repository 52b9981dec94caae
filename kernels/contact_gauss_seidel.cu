// The contact relaxation's Gauss-Seidel schedule on the GPU (contact_relaxation.h): each listed pair
// and wall once, one at a time with the latest values of both particles, as the CPU relaxes them, but
// in colours: no particle has two contacts of one colour, so the contacts of a colour are updated
// together, and the colours one after another (a grid barrier between them). The order within a
// colour does not matter (its contacts share no particle), so the result is the same bits for any
// launch geometry, in one cooperative launch or a launch a colour.
//
// The colouring. Each pair is coloured from its own row (the row in its lower index's list; a wall's,
// its particle's). In rounds: every uncoloured row takes as its candidate the lowest colour neither of
// its particles has yet; a row keeps its candidate unless another uncoloured row of one of its
// particles wants the same colour and has the higher priority (a hash of the row: neighbouring rows get
// unrelated priorities, so the rows that lose once seldom lose again); the winners' colours join their
// particles' masks. Each round reads only what the round before wrote, so the colouring is the same
// bits every time; each round looks only at the rows the round before left (a list), not at every
// particle. In a listing of many rows, round 0 spreads the candidates over 8 colours by the row's
// hash instead: from colour 0 only one row in twenty-odd wins a round (the highest priority among the
// rows it shares a particle with), so most rows waited a round per colour; spread over 16, about half
// won at once (with 8, fewer: the spread now serves the colouring's speed less than the sweeps' fewer
// colours, below). Then a stable counting sort of the own rows by colour gives each colour's rows in row order, and
// the rows are packed in that order (what a sweep reads of a row, in one coalesced read each). A pile
// of monodisperse balls takes 11 to 13 colours from colour 0 (a host emulation of the greedy colouring
// on a settled 10,000-ball pile: 11 to 12), a particle at most 15 contacts (12 neighbours and 3 walls).
// Tried and not kept: priority to the lower contact (then the hash), so that the colours rise with the
// height and a sweep carries support up several layers, as the CPU's bottom-up order does. Priorities
// that follow the height make chains as long as the pile is deep: the 10^6-ball pile's colouring took
// 44 ms instead of 3.6 (an H200), and the sweeps a listing and the pile's stillness did not change.
// Evidence (an H200, fp32, `corebox bench pile --trace` and ncu on two steps of the settled 10^6-ball
// pile). Before the packed rows and the lists: 42 ms a step, 2 listings of 16 sweeps each (every
// listing at the sweep cap with its speed still above tolerance) and about 16 impact rounds (the pile
// never quite still: 0.2 of kinetic energy a ball); a listing's 16 sweeps took 13.2 ms, its colouring
// 3.55. Packed, the 16 sweeps take 8.3 ms; with the lists the colouring takes 3.4 (its first round,
// over every row, is most of it), with the same colours and so the same bits as before: the same
// overlaps, energy, rounds and sweeps, 198 ms a frame before and 171 after (the last second 169 and
// 141), 10^5 balls 34.2 and 31.3. Spread from round 0 (other colours, other bits), the colouring takes
// 1.44 ms, and in one run beside the lists alone the pile 156.5 ms a frame against 160.7 (the last
// second 124.9 and 132.6).
// A later listing of a step (deep overlaps moved particles: collision_rounds.cpp) keeps the colours of
// the pairs the listing before coloured (ContactArgs::prevColour, found by the fill's warm-start
// lookup): they take them before round 0, and the rows left choose among the colours those leave
// (round 0's spread too). An H200, fp32, `corebox bench pile`, one call: 10^6 balls 65.3 ms a frame
// against 66.7, 10^5 15.5 against 15.6; the sandbox at 10^5 balls 14.9 and 14.8 against 16.1 (noisy).
// Across steps too, but for a fresh colouring every few steps (cuda_collisions.cpp:
// kFreshColouringSteps, with its evidence): the first listing of a step keeps the colours of the pairs
// that pushed at the end of the last step, which checkpoints and World edits carry with their impulses
// (ContactCarryOver). An earlier trial kept them for ever (no fresh colouring, code of its day): the
// 10^6-ball pile took 63.1 ms a frame against 68.1, but a settled pile of 400 balls sank onto its lower
// layers at 0.0152 a ball against the 0.0102 the dense-contact tests allow (the same order of colours
// every step biases the same chains, where a fresh colouring varies it). Kept from step to step with the sweeps
// taking the colours backwards in every other sweep (symmetric Gauss-Seidel, so that no order is
// favoured step after step): the piles of 10^5 and 10^6 balls never came to rest (an H200, fp32, 5 s:
// every listing at the sweep cap, 58 and 65 sweeps a step against 26 and 31, the kinetic energy at 5 s
// 256,409 and 2.0e6 against 739 and 7,864, 27.9 and 121.5 ms a frame). Tried and not kept either: round 0's
// contest decided by claims (each row's priority key atomicMax-ed per particle and candidate colour,
// a row winning where its key is the largest at both its particles: the same winners, the same bits,
// two atomics and two reads a row instead of a look at every row of both particles): the 10^6-ball
// pile 65.1 ms a frame against 65.3, for 64 bytes a particle more.
// The sweeps read and write the particles as packed bodies (packed_body.cuh: X with the radius, V with
// the mass, 16 bytes each in fp32), copied from X and V before a listing's sweeps and back after them:
// a row's particles sit at random places, and as Vec3 arrays each coordinate was a load or store of
// its own, every one a 32-byte sector. ncu on a listing of the settled 10^6-ball pile (an H200, fp32,
// 16 sweeps): 9.39 ms with 1.10e9 L2 sectors, 80% of them excess, L2-bound (69% of its throughput);
// packed, 5.88 ms (0.37 a sweep) with 4.0e8. The same bits. `corebox bench pile` (fp32, the same call):
// 10^6 balls 113.4 ms a frame instead of 138.1 (the last second 64.1 instead of 79.0); with the count
// and the fill on the packed bodies too, 111.9 (62.4); 10^5 balls 26.4 instead of 31.1 (12.4 and 16.3).
// A particle's two bodies side by side (one 32-byte sector in fp32), and each written back only where it
// changed: the same bits (but for the sign of a zero velocity: relaxOwnRow), the same state hashes;
// `corebox bench pile` (an H200, fp32, the same call) 10^6 balls 59.7 ms a frame against 66.1 (the last
// second 41.9 against 45.8), 10^5 14.5 against 15.0; the sandbox example at 10^5 balls 14.7 and 14.7
// against 15.3 and 15.5 (its contact phase 5.0 ms a frame against 5.6).
// Tried and not kept: more resident blocks for the sweeps (ncu: 64 registers a thread, half the warps an
// SM could hold, and the sweeps waiting on L2 and on the colours' barriers): __launch_bounds__(kBlock, 6)
// and (kBlock, 5) made the 10^6-ball pile 109.0 and 100.1 ms a frame against 96.4 (the same call, an
// H200, fp32; the last second 64.0 and 55.5 against 53.7): more blocks make each barrier dearer.
// Two rows a thread with both rows' loads issued before either update (gaussSeidelListingKernel; 102
// registers in fp32 against 64, 159 in fp64 against 117, so about half the resident blocks and the same
// loads in flight an SM, half the blocks at each barrier): the same bits; the settled 10^6-ball pile's
// listings 4.25 ms against 4.46 (an H200, fp32, CUPTI kernel times, `corebox bench pile`, its sweeps
// 4.24 s against 4.46 over the 5 s; fp64 not compared on one machine).
// The pair virial r . J is taken after the sweeps (pairVirialsKernel: each pair's net impulse of the
// listing times its separation where the sweeps leave it), not added by each update into a packed virial
// of the row: 8 bytes fewer read and written a pushing row a sweep, and a load off the update's path
// (104 registers in fp32 against 102). The updates act at separations that the position level changes by
// a fraction of the overlaps, so the sum differs from theirs by about that fraction (a settled pile's
// overlaps are within 3e-4 of a diameter); the CPU takes it so too (CpuBackend::contactImpulses). The same motion (the
// piles' energies and overlaps, the sandbox state hash); `corebox bench pile` 10^6 balls 32.01, 31.88 and 31.85 ms a
// frame against 32.94, 32.87 and 32.94 (the last second 25.9 against 27.1; an H200, fp32, separate binaries alternating
// in one call), the sweeps 3.87 s over the 5 s against 4.21 and the virials 132 ms against 79 (CUPTI). In the same call
// the packed virial read with the row's bodies instead of after the update (the code of 4498cc5) took 32.82, 32.79
// and 32.88. Tried and not kept: each colour's first two rows' fields read into registers before the barrier that opens
// the colour (they do not depend on the colour before): 123 registers, the same resident blocks, 33.54 and 33.58 ms a
// frame against 33.40 and 33.19 with the packed virial read with the bodies, 33.56 and 33.55 without (one call); the
// colouring's contest reading every row of both particles with no early exit (unrolled, so that the reads need not wait
// on the comparisons): the colouring took 576 ms over the pile's 5 s against 535 (CUPTI). Tried and not kept: each
// colour's packed rows asked of L2 (prefetch.global.L2) before the barrier that opens it, since they do not depend on
// the colour before: the pile 35.1 and 35.3 ms a frame against 34.5 and 34.7 (an H200, fp32, separate binaries in one
// call). Where the time goes (ncu, a settled listing of that pile, 16 sweeps in 4.30 ms): L2 at 65% of its peak, L1
// hits 51%, the warps stalled half the time on loads and a third at the colours' barriers. The barriers' share,
// measured: the same sweeps (a row a thread) with the barriers left out (wrong: a row may then read a body a row of the
// colour before has yet to write; here the pile ended with other bits and overlaps of 0.14% of a diameter) took 3.27 ms
// a settled listing against 4.46. A schedule that waits per particle instead of per colour keeps the bits; tried and
// not kept: one grid barrier a checked sweep only, each warp taking 64 rows of a colour (two a lane) once a
// per-particle count of rows relaxed (read relaxed, then an acquire fence) reached the row's turn there (its colour's
// rank among the particle's colours, from the colouring's masks), the count passed on after a release fence. The same
// bits (the pile's energies and sweeps, the spread-colours test with 2 and all blocks), but the settled 10^6-ball
// pile's listing took 6.33 ms against 4.25 and the pile 45.2 ms a frame against 37.5 (an H200, fp32, separate binaries
// in one call, CUPTI kernel times): a warp's two fences and its waits a chunk cost more than the barriers they replace.
//
// Why not Jacobi: a Jacobi sweep carries support one layer of a pile, a fraction 1 / max(k_i, k_j) of
// it at a time; Gauss-Seidel in any order that visits each contact once carries it much further, and
// over-relaxed (kGaussSeidelOverRelaxation) it hands a deep pile's momentum to the floor in few
// sweeps. A host emulation of both on a settled pile of 4,444 balls 40 layers deep (10 x 10 floor,
// fp64, 1 s from the state the CPU left at 6 s): 16 coloured Gauss-Seidel sweeps a step left the
// kinetic energy at 47 and overlaps within 3.8e-4 of a diameter, 128 accelerated Jacobi sweeps 28 and
// 3.7e-4, 32 Jacobi sweeps 1927 and 1% (the pile sinking into itself); in the CPU's bottom-up order 16
// sweeps left 43 and 3.8e-4: the order of the colours costs little.
#include <cooperative_groups.h>
#include <cub/block/block_radix_sort.cuh>
#include <cub/device/device_scan.cuh>

#include <algorithm>
#include <cstdint>

#include "contact_residual.cuh"
#include "gpu_common.cuh"
#include "gpu_launch.h"
#include "packed_body.cuh"

namespace corebox::gpu {
namespace {

constexpr uint8_t kUncoloured = kUncolouredRow;
static_assert(kMaxContactColours <= 64, "a particle's colours are a 64-bit mask");
// Round 0 of a listing of at least kSpreadRows rows spreads the candidates over kSpreadColours colours
// (design note above); smaller listings start from colour 0, so that they take no more colours (a
// grid barrier each, every sweep) than they need.
// 8, not 16: spread over 16 a listing took 15.4 colours on average (a grid barrier each, every sweep),
// over 8 10.7, from colour 0 10.1 (an H200, fp32, `corebox bench pile`, 5 s, the same call): 10^5
// balls 26.4 / 24.5 / 24.4 ms a frame (the last second 12.4 / 10.7 / 11.3), 10^6 balls 97.4 / 94.8 /
// 105.1 (53.6 / 52.4 / 60.1; from colour 0 the colouring's rounds cost more than the barriers saved).
constexpr int64_t kSpreadRows = 32768;
constexpr int kSpreadColours = 8;
static_assert(kSpreadColours <= kMaxContactColours, "the spread is within the colours");

COREBOX_HD inline bool isOwnRow(int64_t i, int64_t partner) { return partner < 0 || partner > i; }

// A sweep's reads and writes of its packed rows (ContactArgs::streamRows): marked as streamed (evicted
// first) where the rows and bodies together overflow L2, so that the rows a sweep passes once do not
// push out the bodies it reads at random places. The same values either way.
template <class T, class Real>
__device__ inline T rowLoad(const ContactArgs<Real>& a, const T* p) {
    return a.streamRows ? __ldcs(p) : *p;
}
template <class T, class Real>
__device__ inline void rowStore(const ContactArgs<Real>& a, T* p, T value) {
    if (a.streamRows) {
        __stcs(p, value);
    } else {
        *p = value;
    }
}

__device__ uint32_t rowPriority(int64_t row) {
    uint64_t z = uint64_t(row) + 0x9E3779B97F4A7C15ull;  // splitmix64's finaliser
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return uint32_t(z ^ (z >> 31));
}

__device__ bool beats(int64_t a, int64_t b) {
    const uint32_t pa = rowPriority(a), pb = rowPriority(b);
    return pa > pb || (pa == pb && a < b);
}

// The row of pair (p, i) in p's list (p < i: the pair's own row), -1 if none. From the count's list of p's contacts
// where it has one (ContactArgs::partnerScratch: p's first kListedPartners, 64 bytes read at once), else
// from p's rows one after another.
template <class Real>
__device__ inline int64_t mirrorRowOf(const ContactArgs<Real>& a, int64_t i, int64_t p) {
    const int64_t first = a.contactStart[p], count = a.contactStart[p + 1] - first;
    int64_t own = -1;
    if (a.partnerScratch && count <= kListedPartners) {
        static_assert(kListedPartners == 16, "a particle's listed contacts are four int4");
        const int4* listed = reinterpret_cast<const int4*>(a.partnerScratch + size_t(p) * kListedPartners);
        const int4 q[4] = {listed[0], listed[1], listed[2], listed[3]};
        const int32_t* partners = reinterpret_cast<const int32_t*>(q);
#pragma unroll
        for (int k = 0; k < kListedPartners; ++k)
            if (k < count && partners[k] == int32_t(i)) own = first + k;
        return own;
    }
    for (int64_t t = first; t < first + count; ++t)
        if (a.partner[t] == i) own = t;
    return own;
}

// Row s of particle i: its particle, its pair's own row, and the colour the listing before gave the pair
// where it keeps it (ContactArgs::prevColour; uncoloured otherwise), which joins *mask and makes *colours
// at least its value plus one. Returns the row's overlap at the listed positions where it is an own row
// (0 otherwise).
template <class Real>
__device__ Real prepareRow(const ContactArgs<Real>& a, int64_t i, int64_t s, uint8_t* candidate,
                           unsigned long long* mask, unsigned* colours) {
    const int64_t p = a.partner[s];
    a.rowParticle[s] = i;
    int64_t own = s;
    if (!isOwnRow(i, p)) {
        const int64_t t = mirrorRowOf(a, i, p);
        if (t >= 0) own = t;
        // Every pair is listed from both sides (pairContactActive is symmetric in i and j, bit for
        // bit); were it not, the row would stand as its pair's own row (mirror[s] = s), relaxed from
        // this side alone.
    }
    a.mirror[s] = own;
    // A kept colour is written on the pair's own row, and joins the masks of both its particles through
    // the rows each has of the pair (the fill keeps colours of own rows only, so a row that is nobody's
    // keeps none).
    const uint8_t kept = a.prevColour ? a.prevColour[own] : kUncoloured;
    if (kept != kUncoloured) {
        *mask |= 1ull << kept;
        *colours = max(*colours, unsigned(kept) + 1u);
    }
    a.colour[s] = own == s ? kept : kUncoloured;
    if (own != s) return 0;
    candidate[s] = kept;
    if (!isOwnRow(i, p)) return 0;
    const int si = a.p.species[i];
    const Real ai = a.table.radius[si];
    const Vec3<Real> xi = a.p.x[i];
    if (isWallContact(p)) {
        const int code = int(-1 - p);
        return wallDepth(xi[code / 2], ai, a.box[code / 2], code % 2) / (Real(2) * ai);
    }
    const Real d = ai + a.table.radius[a.p.species[p]];
    return contactGap(d, realSqrt(norm2(xi - a.p.x[p]))) / d;
}

// Per row: its particle, the pair's own row, its kept colour or none (prepareRow); per particle: the mask
// of its kept colours (the rows left choose among the colours those leave: colourRowsKernel). The deepest
// overlap of the own rows at the listed positions (ContactResidual::overlap) into *deepest (double bits);
// the colours kept into words[0], one atomic a warp. A block takes kBlock consecutive particles and their
// rows, a thread a row (its particle found among the block's row starts in shared memory), so that a
// warp's stores are to neighbouring rows; the masks gather in shared memory.
// Before, a thread a particle walked its rows: each store of a warp went to 32 rows apart. The settled
// 10^6-ball pile (an H200, fp32, CUPTI, the median listing of the last 1.25 s): 223 us against 484. The
// same rows, colours, masks and deepest overlap (a maximum, and an OR). Tried and not kept before that: a thread a row
// with its particle written by the fill (487 us against 493, the fill 360 against 267). The kept colours were a pass of
// the colouring kernel over every row before: three atomics a kept row, one of them on words[0] by every row of the
// grid (a settled 10^6-ball pile keeps most of its few million rows' colours); the colouring kernel took 0.99 ms a
// listing of the settled 10^6-ball pile (an H200, fp32, kernel times from CUPTI). Here, with the winners' words[0] one
// atomic a warp: the same colours and bits (the sandbox example's state hash at 10^5 balls unchanged), `corebox bench
// pile` 10^6 balls 43.4 ms a frame against 44.9 (the last second 34.4 against 36.2), 10^5 10.6 against
// 10.8.
template <class Real>
__global__ void __launch_bounds__(kBlock)
    prepareRowsKernel(ContactArgs<Real> a, uint8_t* candidate, unsigned long long* used, unsigned int* words,
                      unsigned long long* deepest) {
    __shared__ int64_t starts[kBlock + 1];
    __shared__ unsigned long long masks[kBlock];
    const int64_t first = int64_t(blockIdx.x) * kBlock;
    masks[threadIdx.x] = 0;
    const int particles = stageRowStarts(starts, a.contactStart, first, a.p.n);  // a barrier: the masks too
    double overlap = 0;
    unsigned colours = 0;
    for (int64_t s = starts[0] + threadIdx.x; s < starts[particles]; s += kBlock) {
        const int lo = particleOfRow(starts, particles, s);
        unsigned long long mask = 0;
        const double o = double(prepareRow(a, first + lo, s, candidate, &mask, &colours));
        if (o > overlap) overlap = o;
        if (mask) atomicOr(&masks[lo], mask);
    }
    __syncthreads();
    if (int(threadIdx.x) < particles) used[first + threadIdx.x] = masks[threadIdx.x];
    double none = 0;
    warpMax(none, overlap);  // every lane: the warp's shuffles
    colours = __reduce_max_sync(0xffffffffu, colours);
    if (threadIdx.x % 32 == 0 && overlap > 0) atomicMaxNonNegative(deepest, overlap);
    if (threadIdx.x % 32 == 0 && colours > 0) atomicMax(&words[0], colours);
}

// The rounds of the colouring (design note above), in one cooperative launch: round 0 over every own
// row, each later one over the rows the round before left uncoloured: lists[0 .. rows) and lists[rows ..
// 2 rows) in turn, their lengths in words[2 + round % 2]. words: [0] colours used, [1] failed (a row found
// every colour taken: each round marks words[4 + round % 2], the end says words[1]). A
// coloured row's candidate stays its colour, which is in both its particles' masks, so no row of
// theirs left uncoloured can want it again: it needs no mark to leave the contest.
template <class Real>
__global__ void __launch_bounds__(kBlock) colourRowsKernel(ContactArgs<Real> a, unsigned long long* used, uint8_t* candidate,
                                                           int32_t* lists, int64_t rows, int spread, unsigned int* words) {
    cooperative_groups::grid_group grid = cooperative_groups::this_grid();
    const int64_t first = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    const int64_t stride = int64_t(gridDim.x) * blockDim.x;
    // A later listing of a step, or a first one that keeps the last step's colours: the rows whose pair
    // the listing before coloured have that colour already (prepareRowsKernel): no two of them at a
    // particle share one, since they did not there (or, restored from a checkpoint or a World edit,
    // since CudaDevice::restoreContactWarmStart takes only colours that are a colouring).
    const bool kept = a.prevColour != nullptr;
    unsigned colours = 0;  // this thread's winners' highest colour plus one, into words[0] as the kernel ends
    for (int round = 0;; ++round) {
        const int32_t* list = lists + (round % 2) * rows;
        int32_t* next = lists + ((round + 1) % 2) * rows;
        const int64_t length = round == 0 ? rows : int64_t(__ldcg(&words[2 + round % 2]));
        // The row at place k of this round: round 0's every own row not kept, then the list's.
        auto rowAt = [&](int64_t k) -> int64_t {
            if (round > 0) return int64_t(list[k]);
            return a.mirror[k] == k && !(kept && a.colour[k] != kUncoloured) ? k : -1;
        };
        // Candidates: the lowest colour neither particle has; in round 0, with a spread, a colour below
        // it from the row's hash (other bits than its priority's lowest).
        for (int64_t k = first; k < length; k += stride) {
            const int64_t s = rowAt(k);
            if (s < 0) continue;
            const int64_t i = a.rowParticle[s], p = a.partner[s];
            const unsigned long long taken = used[i] | (isWallContact(p) ? 0ull : used[p]);
            if (round == 0 && spread > 1) {
                const unsigned spreadColour = (rowPriority(s) >> 16) % unsigned(spread);
                if (!((taken >> spreadColour) & 1ull)) {  // not a kept row's colour at either particle
                    candidate[s] = uint8_t(spreadColour);
                    continue;
                }
            }
            if (~taken == 0ull) {
                candidate[s] = kUncoloured;
                words[4 + round % 2] = 1;  // this round's own slot: below
            } else {
                candidate[s] = uint8_t(__ffsll((long long)~taken) - 1);
            }
        }
        grid.sync();
        // This round's list length is read by every thread (above): its slot counts the round after next.
        if (first == 0) words[2 + round % 2] = 0;
        // Winners take their candidate into their particles' masks; every row a particle of the row has
        // is looked at through its own row. Losers make the next list.
        for (int64_t k = first; k < length; k += stride) {
            const int64_t s = rowAt(k);
            if (s < 0) continue;
            const int64_t i = a.rowParticle[s], p = a.partner[s];
            const uint8_t c = candidate[s];
            if (c == kUncoloured) continue;  // out of colours: the listing falls back to Jacobi
            bool wins = true;
            for (int side = 0; side < 2 && wins; ++side) {
                const int64_t q = side == 0 ? i : p;
                if (q < 0) break;  // a wall
                for (int64_t t = a.contactStart[q]; t < a.contactStart[q + 1]; ++t) {
                    const int64_t e = a.mirror[t];
                    if (e != s && candidate[e] == c && beats(e, s)) {
                        wins = false;
                        break;
                    }
                }
            }
            if (wins) {
                a.colour[s] = c;
                colours = max(colours, unsigned(c) + 1u);
                atomicOr(&used[i], 1ull << c);
                if (!isWallContact(p)) atomicOr(&used[p], 1ull << c);
            } else {
                next[warpAggregatedIncrement(&words[2 + (round + 1) % 2])] = int32_t(s);
            }
        }
        grid.sync();
        // Every thread alike. A round's failure has a slot of its own: a thread on into the next round's
        // candidates could otherwise mark that round failed before a slower one read this round's
        // mark, and the slower one would leave while the rest waited at the next barrier.
        const bool failed = __ldcg(&words[4 + round % 2]) != 0;
        if (failed && first == 0) words[1] = 1;
        if (__ldcg(&words[2 + (round + 1) % 2]) == 0 || failed) break;
    }
    colours = __reduce_max_sync(0xffffffffu, colours);
    if (threadIdx.x % 32 == 0 && colours > 0) atomicMax(&words[0], colours);
}

// The own rows packed in colour order, each colour's in row order (what a sweep reads of a row, in one
// coalesced read each: its particle, partner, target and impulse), and rowRank[s] = e, the place of own
// row s. A stable counting sort by colour over tiles of kPackTileRows consecutive rows, a block a tile: each tile's
// rows of each colour counted (colourTileCountsKernel), the counts scanned colour by colour, tile by tile (the place
// colour c's rows of tile t begin at), and each tile's rows sorted by colour in the block (CUB's block
// radix sort, stable) and written out colour run by colour run (packColouredRowsKernel). Uncoloured own
// rows (where the colouring failed, the listing is relaxed with Jacobi sweeps, which read no packed row)
// and the rows that are not their pair's own are not packed.
// Before, the rows' colour keys were radix-sorted over the whole listing (CUB, stable) into an order of
// every row, and a thread a packed place read its row through that order: a warp's reads of a row's
// particle, partner, target and impulse each fell on rows a colour's stride apart, and each colour's pass
// fetched the rows again (the settled 10^6-ball pile, an H200, fp32, CUPTI, per listing: keys 33 us, the
// sort 54 and its histogram 6, the bounds 16, the packing 220, 330 in all; here the counts 27, their scan 6
// and the packing 148, 181 in all; over the pile's 5 s 195 ms against 348). Tried and not kept:
// a warp a tile of 512 rows, placed 32 at a time in row order (__match_any_sync among the lanes of a
// colour): 199 us, its stores a few lanes to each colour's run, partial sectors evicted before they were
// whole. The same places either way, so the same sweeps and bits.
constexpr int kPackItems = 8;                       // rows a thread
constexpr int kPackTileRows = kBlock * kPackItems;  // rows a block
constexpr int kPackKeyBits = 7;                     // keys 0 .. kMaxContactColours
static_assert(kMaxContactColours < (1 << kPackKeyBits), "a packing key is a colour or none");

// A row's key in the sort: its colour where it is a coloured own row, else none (kMaxContactColours).
template <class Real>
__device__ inline int packKey(const ContactArgs<Real>& a, int64_t s, int64_t rows) {
    if (s >= rows || a.mirror[s] != s) return kMaxContactColours;
    const int c = a.colour[s];
    return c < kMaxContactColours ? c : kMaxContactColours;
}

// counts[c * tiles + t] = tile t's coloured own rows of colour c.
template <class Real>
__global__ void __launch_bounds__(kBlock)
    colourTileCountsKernel(ContactArgs<Real> a, int64_t rows, int64_t tiles, int32_t* counts) {
    __shared__ int32_t hist[kMaxContactColours];
    if (threadIdx.x < kMaxContactColours) hist[threadIdx.x] = 0;
    __syncthreads();
    const int64_t begin = int64_t(blockIdx.x) * kPackTileRows;
    for (int k = int(threadIdx.x); k < kPackTileRows; k += kBlock) {
        const int key = packKey(a, begin + k, rows);
        if (key < kMaxContactColours) atomicAdd(&hist[key], 1);
    }
    __syncthreads();
    if (threadIdx.x < kMaxContactColours) counts[int64_t(threadIdx.x) * tiles + blockIdx.x] = hist[threadIdx.x];
}

// Tile t's coloured own rows of colour c at start[c * tiles + t] on, in row order. The block sorts its
// rows' keys with their places in the tile (blocked in: thread j holds rows j * kPackItems on; striped
// out, so that a warp's stores are to consecutive places), and each row's place within its colour's run
// is its sorted place less the run's first (the tile's counts of the colours before). colourStart[c] =
// start[c * tiles] for c = 0 .. kMaxContactColours (the last: every packed row), so that a colour no row
// took begins where the next does.
template <class Real>
__global__ void __launch_bounds__(kBlock) packColouredRowsKernel(ContactArgs<Real> a, int64_t rows, int64_t tiles,
                                                                 const int32_t* counts, const int32_t* start) {
    using Sort = cub::BlockRadixSort<uint8_t, kBlock, kPackItems, int32_t>;
    __shared__ typename Sort::TempStorage sort;
    __shared__ int32_t runStart[kMaxContactColours];  // the tile's sorted place of each colour's first row
    const int64_t tile = blockIdx.x, begin = tile * kPackTileRows;
    if (tile == 0)
        for (int c = int(threadIdx.x); c <= kMaxContactColours; c += kBlock)
            a.colourStart[c] = start[int64_t(c) * tiles];
    if (threadIdx.x < kMaxContactColours) runStart[threadIdx.x] = counts[int64_t(threadIdx.x) * tiles + tile];
    __syncthreads();
    if (threadIdx.x == 0) {  // the counts into their exclusive sums
        int32_t sum = 0;
        for (int c = 0; c < kMaxContactColours; ++c) {
            const int32_t count = runStart[c];
            runStart[c] = sum;
            sum += count;
        }
    }
    __syncthreads();  // runStart for every thread (the sort below has barriers of its own too)
    uint8_t keys[kPackItems];
    int32_t places[kPackItems];
#pragma unroll
    for (int k = 0; k < kPackItems; ++k) {
        const int place = int(threadIdx.x) * kPackItems + k;
        keys[k] = uint8_t(packKey(a, begin + place, rows));
        places[k] = place;
    }
    Sort(sort).SortBlockedToStriped(keys, places, 0, kPackKeyBits);
#pragma unroll
    for (int k = 0; k < kPackItems; ++k) {
        const int c = keys[k];
        if (c >= kMaxContactColours) continue;
        const int sorted = int(threadIdx.x) + k * kBlock;
        const int64_t e = int64_t(start[int64_t(c) * tiles + tile]) + (sorted - runStart[c]);
        const int64_t s = begin + places[k];
        a.packedParticle[e] = int32_t(a.rowParticle[s]);
        a.packedPartner[e] = int32_t(a.partner[s]);
        a.packedTarget[e] = a.target[s];
        a.packedLambda[e] = a.lambda[s];
        a.rowRank[s] = int32_t(e);
    }
}

// What a sweep reads of a packed own row and of its particles before it updates them (loadOwnRow), so
// that a thread can have two rows' loads in flight before it computes either (gaussSeidelListingKernel).
template <class Real>
struct LoadedRow {
    int64_t e, i, p;
    PackedBody<Real> xi, vi, xj, vj;  // xj, vj: a pair's partner (neither set nor read for a wall: zeroing
                                      // them there took fp64 from 159 registers to 128 with spills)
    Real lambda, target;
};

template <class Real>
__device__ inline LoadedRow<Real> loadOwnRow(const ContactArgs<Real>& a, int64_t e) {
    LoadedRow<Real> w;
    w.e = e;
    w.i = rowLoad(a, a.packedParticle + e);
    w.p = rowLoad(a, a.packedPartner + e);
    w.lambda = rowLoad(a, a.packedLambda + e);
    w.target = rowLoad(a, a.packedTarget + e);
    w.xi = xBody(a, w.i);
    w.vi = vBody(a, w.i);
    if (!isWallContact(w.p)) {
        w.xj = xBody(a, w.p);
        w.vj = vBody(a, w.p);
    }
    return w;
}

// One contact's Gauss-Seidel update from its packed own row as loadOwnRow read it: the velocity level,
// then the position level (relaxPairContact; stopWallContact and a wall's full depth), as the CPU's
// sweeps do them (each pair's mass terms computed once for both levels, pairMassesOf); the impulse given
// goes to the owner's rows (impulse_sums.h): a wall's momentum at once; a pair's r . J is taken after the
// sweeps (pairVirialsKernel).
template <class Real>
__device__ void relaxLoadedRow(const ContactArgs<Real>& a, const LoadedRow<Real>& w, ContactResidual<Real>& r) {
    const int64_t e = w.e, i = w.i, p = w.p;
    const size_t n = size_t(a.p.n);
    const Real mi = w.vi.w, ai = w.xi.w;
    Vec3<Real> xi = vec3Of(w.xi), vi = vec3Of(w.vi);
    Real lambda = w.lambda;
    const Real before = lambda;
    // A body is written back only where it changed (stores are L2 traffic, and a settled pile's rows
    // often push nothing): a zero impulse adds zero to the velocity, a pair apart moves no position. The
    // same bits as writing every body back, but for the sign of a zero: adding a zero impulse turned a
    // velocity component of -0 into +0, which is now left -0 (the same motion; a state hash sees it).
    if (isWallContact(p)) {
        const int code = int(-1 - p), axis = code / 2;
        const bool moved =
            relaxWallContact(xi[axis], vi[axis], code % 2, ai, a.box[axis], w.target, lambda, r, a.omega);
        const Real push = lambda - before;  // per unit mass
        if (push != Real(0)) {
            rowStore(a, a.packedLambda + e, lambda);
            a.impulses[size_t(code) * n + size_t(i)] += double(mi) * double(push);
            if (atWallCentre(xi, ai, a.box, axis)) a.impulses[size_t(kWallCount + code) * n + size_t(i)] += double(mi) * double(push);
            vBody(a, i) = packed(vi, mi);
        }
        if (moved) xBody(a, i) = packed(xi, ai);
        return;
    }
    const Real mj = w.vj.w, d = ai + w.xj.w;
    Vec3<Real> xj = vec3Of(w.xj), vj = vec3Of(w.vj);
    const bool moved = relaxPairContact(xi, xj, vi, vj, pairMassesOf(mi, mj), d, a.up, w.target, lambda, r, a.omega);
    if (lambda != before) {
        rowStore(a, a.packedLambda + e, lambda);
        vBody(a, i) = packed(vi, mi);
        vBody(a, p) = packed(vj, mj);
    }
    if (moved) {
        xBody(a, i) = packed(xi, ai);
        xBody(a, p) = packed(xj, w.xj.w);
    }
}

template <class Real>
__device__ inline void relaxOwnRow(const ContactArgs<Real>& a, int64_t e, ContactResidual<Real>& r) {
    relaxLoadedRow(a, loadOwnRow(a, e), r);
}

// One colour's contacts, a thread each; with `measure`, their residual (every thread of the grid calls
// addResidual: its warp shuffles need every lane).
template <class Real>
__global__ void gaussSeidelColourKernel(ContactArgs<Real> a, int colour, bool measure) {
    const int64_t e = a.colourStart[colour] + int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    ContactResidual<Real> r{0, 0};
    if (e < a.colourStart[colour + 1]) relaxOwnRow(a, e, r);
    if (measure) addResidual(r, a.residual);
}

// launchRelaxListing's schedule (the first sweep alone, then batches, the residual read at each
// check) over coloured sweeps: a grid barrier after each colour. words as relaxListingKernel's.
template <class Real>
__global__ void __launch_bounds__(kBlock) gaussSeidelListingKernel(ContactArgs<Real> a, int colours, RelaxationPlan plan,
                                                                   unsigned long long* words) {
    cooperative_groups::grid_group grid = cooperative_groups::this_grid();
    const int64_t first = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    const int64_t stride = int64_t(gridDim.x) * blockDim.x;
    int done = 0, checks = 0;
    double firstOverlap = 0;  // the first sweep's, from its check on
    for (;;) {
        unsigned long long* slot = words + 2 * (checks % 2);
        const bool measured = plan.checkedAfter(done + 1, firstOverlap);
        ContactResidual<Real> r{0, 0};
        for (int c = 0; c < colours; ++c) {
            const int64_t end = a.colourStart[c + 1];
            // Two rows a thread at a time, both read before either is updated: a colour's rows share no
            // particle, so the second's reads see what they would after the first's writes (the same
            // bits), and a thread has twice the loads in flight.
            int64_t e = a.colourStart[c] + first;
            for (; e + stride < end; e += 2 * stride) {
                const LoadedRow<Real> w0 = loadOwnRow(a, e), w1 = loadOwnRow(a, e + stride);
                relaxLoadedRow(a, w0, r);
                relaxLoadedRow(a, w1, r);
            }
            if (e < end) relaxOwnRow(a, e, r);
            grid.sync();
        }
        ++done;
        if (!measured) continue;
        addBlockResidual(double(r.speedChange), double(r.overlap), slot);
        grid.sync();
        // The other slot is written again only after a colour's barrier: no barrier needed here.
        if (checkListingResidual(plan, done, checks, slot, words, first == 0, &firstOverlap)) return;
    }
}

// Per row: it takes its pair's impulse from the packed own row (as Jacobi leaves both rows). A thread a
// row, not a particle: a particle's rows one after another were a chain of three dependent reads each,
// behind the stores of the row before. The settled 10^6-ball pile's listing (an H200, fp32, CUPTI kernel
// times, the same bits): 71 us here and 66 for the virials (pairVirialsKernel, then summing the packed
// virials; 82 us now that it reads the positions, c84958f) against 320 for both in one kernel a thread a
// particle.
// Tried and not kept: both in one launch, a block's rows a thread a row and then its particles' virials a
// thread a particle: 94.5 us a listing on average against 47.0 and 48.5 (the same pile over its 5 s).
template <class Real>
__global__ void mirrorImpulsesKernel(ContactArgs<Real> a, int64_t rows) {
    const int64_t s = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (s >= rows) return;
    const Real lambda = a.packedLambda[a.rowRank[a.mirror[s]]];
    a.lambda[s] = lambda;
    a.applied[s] = lambda;
}

// Per particle i: the pair virial of i's own rows, summed in row order, joins i's impulse row: each pair's
// net impulse of the sweeps (its packed impulse less the one it began with, which the rows hold until
// mirrorImpulsesKernel, after this) times the pair's separation where the sweeps left it. The sweeps'
// updates each act at the separation of their moment, which the position level changes by a fraction of
// the overlaps (a settled pile's are within 3e-4 of a diameter), so the sum differs from theirs by about
// that fraction.
// Before, each update added its r . J to a packed virial of the row (8 bytes read and written a pushing
// row a sweep). The loop only reads, so a thread's rows are read in flight together.
template <class Real>
__global__ void pairVirialsKernel(ContactArgs<Real> a) {
    const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= a.p.n) return;
    const Vec3<Real> xi = a.p.x[i];
    double virial = 0;
    for (int64_t s = a.contactStart[i]; s < a.contactStart[i + 1]; ++s) {
        const int64_t p = a.partner[s];
        if (a.mirror[s] != s || isWallContact(p)) continue;
        const double impulse = double(a.packedLambda[a.rowRank[s]]) - double(a.lambda[s]);
        if (impulse != 0) virial += double(realSqrt(norm2(xi - a.p.x[p]))) * impulse;
    }
    if (virial != 0) a.impulses[size_t(kPairVirialRow) * size_t(a.p.n) + size_t(i)] += virial;
}

struct ColouringScratch {
    unsigned long long* used;
    uint8_t* candidate;
    int32_t* lists;                    // the colouring's two lists of rows left, rows each
    int32_t *tileCounts, *tileStarts;  // the packing's: kMaxContactColours x tiles + 1 each
    int64_t tiles;
    void* scan;
    size_t scanBytes;
};

size_t align256(size_t bytes) { return (bytes + 255) / 256 * 256; }

int64_t packTiles(int64_t rows) { return (rows + kPackTileRows - 1) / kPackTileRows; }

// The packing's counts: one a colour and tile, and a zero after them (its scan is every packed row).
int64_t packCountSlots(int64_t rows) { return int64_t(kMaxContactColours) * packTiles(rows) + 1; }

size_t packScanBytes(int64_t rows) {
    size_t bytes = 0;
    cub::DeviceScan::ExclusiveSum(nullptr, bytes, static_cast<const int32_t*>(nullptr), static_cast<int32_t*>(nullptr),
                                  int(packCountSlots(rows)));
    return bytes;
}

// Where the scratch's parts begin (bytes from its start), and its size, for n particles and `rows` rows:
// the one layout that both sizes the scratch (contactColouringScratchBytes) and carves it.
struct ColouringLayout {
    size_t used, candidate, lists, tileCounts, tileStarts, scan, scanBytes, bytes;
};

ColouringLayout colouringLayout(int64_t n, int64_t rows) {
    ColouringLayout l{};
    const size_t countBytes = align256(size_t(packCountSlots(rows)) * sizeof(int32_t));
    l.candidate = l.used + align256(size_t(n) * sizeof(unsigned long long));
    l.lists = l.candidate + align256(size_t(rows));
    l.tileCounts = l.lists + align256(2 * size_t(rows) * sizeof(int32_t));
    l.tileStarts = l.tileCounts + countBytes;
    l.scan = l.tileStarts + countBytes;
    l.scanBytes = packScanBytes(rows);
    l.bytes = l.scan + l.scanBytes;
    return l;
}

ColouringScratch carve(void* scratch, const ColouringLayout& l, int64_t rows) {
    char* at = static_cast<char*>(scratch);
    ColouringScratch c{};
    c.used = reinterpret_cast<unsigned long long*>(at + l.used);
    c.candidate = reinterpret_cast<uint8_t*>(at + l.candidate);
    c.lists = reinterpret_cast<int32_t*>(at + l.lists);
    c.tileCounts = reinterpret_cast<int32_t*>(at + l.tileCounts);
    c.tileStarts = reinterpret_cast<int32_t*>(at + l.tileStarts);
    c.tiles = packTiles(rows);
    c.scan = at + l.scan;
    c.scanBytes = l.scanBytes;
    return c;
}

}  // namespace

size_t contactColouringScratchBytes(int64_t n, int64_t rows) { return colouringLayout(n, rows).bytes; }

template <class Real>
bool launchColourContacts(const ContactArgs<Real>& a, int64_t rows, void* scratch, size_t scratchBytes, unsigned int* words,
                          unsigned long long* deepest, cudaStream_t stream) {
    // Packed rows and the lists hold particles and rows as 32-bit indices.
    if (a.p.n == 0 || rows == 0 || a.p.n > INT32_MAX || rows > INT32_MAX) return false;
    static const int resident = cooperativeResidentBlocks(colourRowsKernel<Real>);
    if (resident < 1) return false;
    const ColouringLayout layout = colouringLayout(a.p.n, rows);
    if (scratchBytes < layout.bytes) throw DeviceError("contact colouring: scratch too small");
    ColouringScratch c = carve(scratch, layout, rows);
    cudaError_t e = cudaMemsetAsync(words, 0, 6 * sizeof(unsigned int), stream);
    if (e != cudaSuccess) throw DeviceError(std::string("contact colouring words: ") + cudaGetErrorString(e));
    e = cudaMemsetAsync(deepest, 0, sizeof(unsigned long long), stream);
    if (e != cudaSuccess) throw DeviceError(std::string("contact colouring: ") + cudaGetErrorString(e));
    // The candidates of rows never looked at (not own) stay out of every contest.
    e = cudaMemsetAsync(c.candidate, kUncoloured, size_t(rows), stream);
    if (e != cudaSuccess) throw DeviceError(std::string("contact colouring: ") + cudaGetErrorString(e));
    prepareRowsKernel<Real><<<blocksFor(a.p.n), kBlock, 0, stream>>>(a, c.candidate, c.used, words, deepest);
    checkLaunch("contact row kernel");
    ContactArgs<Real> args = a;
    unsigned long long* used = c.used;
    uint8_t* candidate = c.candidate;
    int32_t* lists = c.lists;
    int64_t listRows = rows;
    int spread = rows >= kSpreadRows ? kSpreadColours : 1;
    void* params[] = {&args, &used, &candidate, &lists, &listRows, &spread, &words};
    const int64_t blocks = std::min<int64_t>(resident, blocksFor(rows));
    e = cudaLaunchCooperativeKernel(reinterpret_cast<const void*>(colourRowsKernel<Real>), dim3(unsigned(blocks)), dim3(kBlock), params, 0,
                                    stream);
    if (e != cudaSuccess) throw DeviceError(std::string("contact colouring kernel: ") + cudaGetErrorString(e));
    const unsigned tileBlocks = unsigned(c.tiles);
    e = cudaMemsetAsync(c.tileCounts + (packCountSlots(rows) - 1), 0, sizeof(int32_t), stream);
    if (e != cudaSuccess) throw DeviceError(std::string("contact packing: ") + cudaGetErrorString(e));
    colourTileCountsKernel<Real><<<tileBlocks, kBlock, 0, stream>>>(a, rows, c.tiles, c.tileCounts);
    checkLaunch("contact colour count kernel");
    size_t scanBytes = c.scanBytes;
    e = cub::DeviceScan::ExclusiveSum(c.scan, scanBytes, c.tileCounts, c.tileStarts, int(packCountSlots(rows)), stream);
    if (e != cudaSuccess) throw DeviceError(std::string("contact packing scan: ") + cudaGetErrorString(e));
    packColouredRowsKernel<Real><<<tileBlocks, kBlock, 0, stream>>>(a, rows, c.tiles, c.tileCounts, c.tileStarts);
    checkLaunch("contact row packing kernel");
    return true;
}

template <class Real>
void launchGaussSeidelSweeps(const ContactArgs<Real>& a, const std::vector<int32_t>& colourStart, int sweeps, cudaStream_t stream) {
    const int colours = int(colourStart.size()) - 1;
    if (a.p.n == 0 || sweeps < 1) return;
    launchPackBodies(a, stream);
    for (int sweep = 0; sweep < sweeps; ++sweep) {
        const bool last = sweep == sweeps - 1;
        if (last) cudaMemsetAsync(a.residual, 0, 2 * sizeof(unsigned long long), stream);
        for (int c = 0; c < colours; ++c) {
            const int64_t rows = colourStart[size_t(c) + 1] - colourStart[size_t(c)];
            if (rows == 0) continue;
            gaussSeidelColourKernel<Real><<<blocksFor(rows), kBlock, 0, stream>>>(a, c, last);
            checkLaunch("contact Gauss-Seidel kernel");
        }
    }
    launchUnpackBodies(a, stream);
}

template <class Real>
bool launchGaussSeidelListing(const ContactArgs<Real>& a, const std::vector<int32_t>& colourStart, const RelaxationPlan& plan,
                              unsigned long long* words, cudaStream_t stream) {
    int colours = int(colourStart.size()) - 1;
    if (a.p.n == 0 || colours < 1 || plan.maxSweeps < 1 || plan.batch < 1) return false;
    int64_t largest = 0;
    for (int c = 0; c < colours; ++c) largest = std::max<int64_t>(largest, colourStart[size_t(c) + 1] - colourStart[size_t(c)]);
    static const int resident = cooperativeResidentBlocks(gaussSeidelListingKernel<Real>);
    if (resident < 1) return false;
    const cudaError_t cleared = cudaMemsetAsync(words, 0, 4 * sizeof(unsigned long long), stream);
    if (cleared != cudaSuccess) throw DeviceError(std::string("contact relaxation words: ") + cudaGetErrorString(cleared));
    ContactArgs<Real> args = a;
    // Streamed rows where rows and bodies overflow L2 (rowLoad). An H200, fp32, `corebox bench pile`, the
    // settled 10^6-ball pile (93 MB of rows a sweep, 32 MB of bodies; CUPTI kernel times): 16 sweeps in
    // 4.37 ms against 4.56; at 10^5 balls, where both fit, the rows stay in L2 from sweep to sweep and
    // streaming them made the sandbox example's contact phase slower (4.8 ms a frame against 4.5).
    // Tried and not kept: the bodies kept in L2 by an access-policy window (persisting lines): the sweeps
    // took 3.96 ms, but the set-aside L2 made the listing's kernels two to three times slower (the pile
    // 56.8 ms a frame against 41.1, both under the kernel-time tracer); blocks of 1024 and 512 threads
    // instead of 256 (fewer blocks at each grid barrier), rows not streamed: 4.70 and 4.60 ms against
    // 4.58 in the same call.
    const size_t rowBytes = size_t(colourStart.back()) * (2 * sizeof(int32_t) + 2 * sizeof(Real));
    args.streamRows = rowBytes + 2 * size_t(a.p.n) * sizeof(PackedBody<Real>) > l2CacheBytes();
    RelaxationPlan schedule = plan;
    void* params[] = {&args, &colours, &schedule, &words};
    // A thread a row of the largest colour, no more than fit: the barriers cost more with more blocks
    // (a thread a particle instead: the 10^5-ball pile 38.3 ms a frame against 34.1, an H200, fp32). Tried
    // and not kept: fewer blocks, a grid for 2 or 4 rows a thread of the largest colour, so that each
    // barrier waits on fewer: the sandbox example at 10^5 balls spent 4.49 / 4.21 and 5.30 / 5.25 ms a
    // frame in its contact phase against 4.12 / 3.89, the 10^5-ball pile 8.78 and 10.38 ms a frame against
    // 8.18 (an H200, fp32, one call, the same bits).
    int64_t blocks = std::min<int64_t>(resident, std::max<int64_t>(1, blocksFor(largest)));
    if (a.sweepBlocks > 0) blocks = std::min<int64_t>(blocks, a.sweepBlocks);
    launchPackBodies(a, stream);
    const cudaError_t e = cudaLaunchCooperativeKernel(reinterpret_cast<const void*>(gaussSeidelListingKernel<Real>), dim3(unsigned(blocks)),
                                                      dim3(kBlock), params, 0, stream);
    if (e != cudaSuccess) throw DeviceError(std::string("contact Gauss-Seidel kernel: ") + cudaGetErrorString(e));
    launchUnpackBodies(a, stream);
    return true;
}

template <class Real>
void launchMirrorImpulses(const ContactArgs<Real>& a, int64_t rows, cudaStream_t stream) {
    if (a.p.n == 0 || rows == 0) return;
    pairVirialsKernel<Real><<<blocksFor(a.p.n), kBlock, 0, stream>>>(a);  // before the rows take the packed impulses
    checkLaunch("contact pair virial kernel");
    mirrorImpulsesKernel<Real><<<blocksFor(rows), kBlock, 0, stream>>>(a, rows);
    checkLaunch("contact mirror kernel");
}

#define COREBOX_INSTANTIATE(Real)                                                                             \
    template bool launchColourContacts<Real>(const ContactArgs<Real>&, int64_t, void*, size_t, unsigned int*, \
                                             unsigned long long*, cudaStream_t);                              \
    template void launchGaussSeidelSweeps<Real>(const ContactArgs<Real>&, const std::vector<int32_t>&, int,   \
                                                cudaStream_t);                                                \
    template bool launchGaussSeidelListing<Real>(const ContactArgs<Real>&, const std::vector<int32_t>&,       \
                                                 const RelaxationPlan&, unsigned long long*, cudaStream_t);   \
    template void launchMirrorImpulses<Real>(const ContactArgs<Real>&, int64_t, cudaStream_t);
COREBOX_INSTANTIATE(float)
COREBOX_INSTANTIATE(double)
#undef COREBOX_INSTANTIATE

}  // namespace corebox::gpu
