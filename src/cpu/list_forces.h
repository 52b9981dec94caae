// The CPU backend's passes over its Verlet lists (verlet_list.h): forces with the pair energies and
// the collision screen, and the pair virial.
//
// Design note. Each chunk of the list is one task: it zeroes its slots, walks its pairs by ascending
// owner (VerletList::walkChunk) adding each pair's value to both particles where they are its own;
// the results then go back by particle. Every particle's sum runs by ascending partner index, so the
// bits depend neither on the thread count nor on when the list was built, and equal what
// VerletList::forEachPartner gives for one particle (listAccelerationOf in the backend): for a pair
// with j < i the pass subtracts F (x_j - x_i), which is the same number as adding F (x_i - x_j).
// With one species on a CPU with AVX2, the own rows go W pairs at a time (list_row_simd.h), each lane
// the scalar arithmetic, so the bits are the same either way.
//
// The screen (Backend::screenStage, kernels/collision_screen.h) rides along the end-of-step pass: the
// smallest R^2 / reach^2 over the listed pairs, the deepest wall approach, and whether every position
// is finite, from positions the pass reads anyway.
#pragma once

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "collision_screen.h"
#include "list_row_simd.h"
#include "pair_potential.h"
#include "verlet_list.h"

namespace corebox {

template <class Real>
struct ListPassInputs {
    const Vec3<Real>* x = nullptr;
    const int32_t* species = nullptr;
    const PairCoefficients<Real>* pairs = nullptr;  // speciesCount^2, row-major
    int speciesCount = 1;
    const Real* invMass = nullptr;
    const Vec3<Real>* field = nullptr;  // per species: gravity plus the species' own acceleration
    int threads = 1;
    bool simd = simdListRowsAvailable();  // one species: rows W pairs at a time (list_row_simd.h), the same bits
};

// What the screen found: nearest < 0 when no pair was listed.
struct ListScreen {
    double nearest = -1;           // smallest R^2 / reach^2 over the listed pairs
    double deepestWallDepth = 0;   // > 0 when some particle is within its wall reach
    bool finite = true;
};

// What the screen needs: the reaches' inverse squares by species pair, the wall reach by species.
template <class Real>
struct ListScreenReach {
    std::vector<Real> inverseReach2;  // speciesCount^2
    std::vector<Real> wallReach;      // speciesCount
    Vec3<Real> box{0, 0, 0};
};

// Per-slot copies a pass works on (VerletList: slots are the particles in the grid's order, a chunk's
// contiguous), kept by the caller to reuse their memory: positions and species gathered into slots,
// so that a row's partners, spatial neighbours, lie near each other in memory, and sums by slot, so
// that no two threads write one cache line.
template <class Real>
struct ListPassScratch {
    std::vector<Vec3<Real>> x, force;
    std::vector<int32_t> species;
    std::vector<double> value;
};

// a_i = sum_j F_ij / m_i + field into out, each particle's pair energy (both sides of every pair) into
// pairEnergy when given; with `reach`, the screen. Three phases in one thread team: gather into slots,
// the chunks' walks, then the results back by particle (each thread a contiguous run of particles).
template <class Real, bool kEnergy, bool kSingleSpecies>
ListScreen listForcePass(const VerletList<Real>& list, const ListPassInputs<Real>& in, ListPassScratch<Real>& scratch, int64_t n,
                         Vec3<Real>* out, double* pairEnergy, const ListScreenReach<Real>* reach) {
    using List = VerletList<Real>;
    const int64_t chunks = list.chunkCount();
    scratch.x.resize(size_t(n));
    scratch.force.resize(size_t(n));
    if (!kSingleSpecies) scratch.species.resize(size_t(n));
    if (kEnergy) scratch.value.resize(size_t(n));
    Vec3<Real>* const xs = scratch.x.data();
    Vec3<Real>* const force = scratch.force.data();
    int32_t* const speciesOf = scratch.species.data();
    double* const energy = scratch.value.data();
    std::vector<double> nearestOf(static_cast<size_t>(chunks), -1.0);  // by chunk, as ListScreen::nearest
    std::vector<ListScreen> wallsOf;
#pragma omp parallel num_threads(in.threads) if (chunks > 1)
    {
#pragma omp for schedule(static)
        for (int64_t k = 0; k < n; ++k) {
            const int64_t i = list.particleAt(k);
            xs[k] = in.x[i];
            if (!kSingleSpecies) speciesOf[k] = in.species[i];
        }
#pragma omp for schedule(static, 1)
        for (int64_t c = 0; c < chunks; ++c) {
            // Locals the compiler can keep in registers across the writes to force[] (which it cannot
            // prove do not alias the inputs).
            const PairCoefficients<Real>* const pairs = in.pairs;
            const int s = in.speciesCount;
            const PairCoefficients<Real> single = pairs[0];
            const bool screen = reach != nullptr;
            const Real* const inverseReach2 = screen ? reach->inverseReach2.data() : nullptr;
            const Real singleInverse = screen ? inverseReach2[0] : Real(0);
            Real nearest = std::numeric_limits<Real>::infinity();
            bool listed = false;
            // The value of the pair of slots (a, b) for a: F_ab (x_a - x_b), its energy into u, the
            // screen's ratio noted.
            auto pairValue = [&](int64_t a, int64_t b, Real& u) {
                const int sa = kSingleSpecies ? 0 : speciesOf[a], sb = kSingleSpecies ? 0 : speciesOf[b];
                const Vec3<Real> d = xs[a] - xs[b];
                const Real r2 = norm2(d);
                if (screen) {
                    nearest = std::min(nearest, r2 * (kSingleSpecies ? singleInverse : inverseReach2[sa * s + sb]));
                    listed = true;
                }
                return pairForceOverR(kSingleSpecies ? single : pairs[sa * s + sb], r2, kEnergy ? &u : nullptr) * d;
            };
            for (int64_t k = list.chunkBegin(c); k < list.chunkEnd(c); ++k) {
                force[k] = Vec3<Real>{0, 0, 0};
                if (kEnergy) energy[k] = 0;
            }
            list.walkChunk(
                c,
                [&](int64_t a, const uint32_t* begin, const uint32_t* end) {
                    Vec3<Real> fa = force[a];
                    double ua = kEnergy ? energy[a] : 0.0;
                    const uint32_t* e = begin;
                    if (kSingleSpecies && in.simd) {
                        RowSums<Real> row{fa, ua, nearest};
                        e = screen ? simdListRow<Real, kEnergy, true>(xs, force, energy, a, begin, end, List::kOtherChunk, single, singleInverse, row)
                                   : simdListRow<Real, kEnergy, false>(xs, force, energy, a, begin, end, List::kOtherChunk, single, singleInverse, row);
                        fa = row.force;
                        ua = row.energy;
                        nearest = row.nearest;
                        listed = listed || (screen && e != begin);
                    }
                    for (; e < end; ++e) {
                        const int64_t b = List::entrySlot(*e);
                        Real u = 0;
                        const Vec3<Real> fd = pairValue(a, b, u);
                        fa += fd;
                        if (kEnergy) ua += double(u);
                        if (List::inThisChunk(*e)) {
                            force[b] -= fd;
                            if (kEnergy) energy[b] += double(u);
                        }
                    }
                    force[a] = fa;
                    if (kEnergy) energy[a] = ua;
                },
                [&](int64_t a, int64_t b) {
                    Real u = 0;
                    force[b] -= pairValue(a, b, u);
                    if (kEnergy) energy[b] += double(u);
                });
            if (listed) nearestOf[size_t(c)] = double(nearest);
        }
        // The results by particle, and the screen's walls: each thread a fixed run of particles.
#pragma omp single
        wallsOf.resize(static_cast<size_t>(omp_get_num_threads()));
        ListScreen walls;
#pragma omp for schedule(static)
        for (int64_t i = 0; i < n; ++i) {
            const int64_t k = list.slotOf(i);
            const int si = in.species[i];
            out[i] = in.invMass[si] * force[k] + in.field[si];
            if (kEnergy) pairEnergy[i] = energy[k];
            if (!reach) continue;
            const Vec3<Real> xi = in.x[i];
            if (!(std::isfinite(xi.x) && std::isfinite(xi.y) && std::isfinite(xi.z))) {
                walls.finite = false;
                continue;
            }
            walls.deepestWallDepth = std::max(walls.deepestWallDepth, double(deepestWallApproach(xi, reach->wallReach[size_t(si)], reach->box)));
        }
        wallsOf[size_t(omp_get_thread_num())] = walls;
    }
    ListScreen total;
    for (double nearest : nearestOf) {
        if (nearest >= 0) total.nearest = total.nearest < 0 ? nearest : std::min(total.nearest, nearest);
    }
    for (const ListScreen& w : wallsOf) {
        total.deepestWallDepth = std::max(total.deepestWallDepth, w.deepestWallDepth);
        total.finite = total.finite && w.finite;
    }
    return total;
}

// Half of sum_i sum_j R_ij F_ij over the listed pairs: each particle's pairs by ascending partner
// (as the force pass), the particles' sums in index order.
template <class Real>
double listPairVirial(const VerletList<Real>& list, const ListPassInputs<Real>& in, ListPassScratch<Real>& scratch, int64_t n) {
    using List = VerletList<Real>;
    const int64_t chunks = list.chunkCount();
    const int s = in.speciesCount;
    scratch.value.resize(size_t(n));
    double* const w = scratch.value.data();
    auto pairValue = [&](int64_t a, int64_t b) {
        const int64_t i = list.particleAt(a), j = list.particleAt(b);
        const Real r2 = norm2(in.x[i] - in.x[j]);
        return double(pairForceOverR(in.pairs[in.species[i] * s + in.species[j]], r2, static_cast<Real*>(nullptr))) * double(r2);
    };
#pragma omp parallel for schedule(static, 1) num_threads(in.threads) if (chunks > 1)
    for (int64_t c = 0; c < chunks; ++c) {
        for (int64_t k = list.chunkBegin(c); k < list.chunkEnd(c); ++k) w[k] = 0;
        list.walkChunk(
            c,
            [&](int64_t a, const uint32_t* begin, const uint32_t* end) {
                double wa = w[a];
                for (const uint32_t* e = begin; e < end; ++e) {
                    const int64_t b = List::entrySlot(*e);
                    const double value = pairValue(a, b);
                    wa += value;
                    if (List::inThisChunk(*e)) w[b] += value;
                }
                w[a] = wa;
            },
            [&](int64_t a, int64_t b) { w[b] += pairValue(a, b); });
    }
    return 0.5 * deterministicSum<double>(in.threads, n, [&](int64_t i) { return w[list.slotOf(i)]; });
}

}  // namespace corebox
