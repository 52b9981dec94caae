#include "initial_conditions.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <sstream>
#include <thread>

#include "errors.h"
#include "host_cell_list.h"
#include "memory_estimate.h"
#include "packing.h"
#include "rng.h"
#include "state_csv.h"

namespace corebox {
namespace {

// Closest allowed centre distance when placing i and j: hard-core contact, and for LJ pairs also
// 0.9 sigma_ij so the first force evaluation is not a huge repulsion.
double placementDistance(const SpeciesDef& a, const SpeciesDef& b) {
    double d = a.radius + b.radius;
    if (a.epsilon > 0 && b.epsilon > 0) d = std::max(d, 0.9 * 0.5 * (a.sigma + b.sigma));
    return d;
}

std::vector<int32_t> speciesOfIds(const Scene& scene) {
    std::vector<int32_t> species;
    species.reserve(size_t(scene.particleCount()));
    for (size_t s = 0; s < scene.species.size(); ++s) species.insert(species.end(), size_t(scene.species[s].count), int32_t(s));
    return species;
}

// Progress every this many particles.
constexpr int64_t kProgressEvery = 1 << 16;

void report(const SetupProgress& progress, const char* stage, int64_t done, int64_t total) {
    if (progress && (done % kProgressEvery == 0 || done == total)) progress(stage, done, total);
}

// The sites come from latticeSites(), the lattice that packingProblem() checked the scene against.
void placeOnLattice(const Scene& scene, ParticleState& state, const SetupProgress& progress) {
    const int64_t n = int64_t(state.size());
    const std::array<double, 3>& box = scene.box.size;
    const std::array<int64_t, 3> sites = latticeSites(scene);
    // A random subset of the sites (Fisher-Yates on counter-based draws), so species mix.
    const int64_t total = sites[0] * sites[1] * sites[2];
    std::vector<int64_t> order(static_cast<size_t>(total));
    for (int64_t k = 0; k < total; ++k) order[size_t(k)] = k;
    for (int64_t k = total - 1; k > 0; --k) {
        const Philox4 r = drawBlock(scene.init.seed, 0, uint64_t(k), RngPurpose::LatticeShuffle);
        const int64_t j = int64_t(uniformOpen(r.v[0], r.v[1]) * double(k + 1));
        std::swap(order[size_t(k)], order[size_t(std::min(j, k))]);
        report(progress, "lattice placement", total - k, total);
    }
    report(progress, "lattice placement", total, total);
    for (int64_t i = 0; i < n; ++i) {
        const int64_t site = order[size_t(i)];
        const int64_t ix = site % sites[0], iy = (site / sites[0]) % sites[1], iz = site / (sites[0] * sites[1]);
        state.position[size_t(i)] = {(double(ix) + 0.5) * box[0] / double(sites[0]), (double(iy) + 0.5) * box[1] / double(sites[1]),
                                     (double(iz) + 0.5) * box[2] / double(sites[2])};
    }
}

void placeRandomly(const Scene& scene, ParticleState& state, const SetupProgress& progress) {
    const int64_t n = int64_t(state.size());
    double maxDistance = 0;
    for (const SpeciesDef& a : scene.species)
        for (const SpeciesDef& b : scene.species) maxDistance = std::max(maxDistance, placementDistance(a, b));
    const Vec3<double> box{scene.box.size[0], scene.box.size[1], scene.box.size[2]};
    IncrementalCellList grid(cellGeometry(box, n, maxDistance), n);
    constexpr int kAttempts = 2000;
    for (int64_t i = 0; i < n; ++i) {
        report(progress, "random placement", i, n);
        const SpeciesDef& si = scene.species[size_t(state.species[size_t(i)])];
        bool placed = false;
        for (int attempt = 0; attempt < kAttempts && !placed; ++attempt) {
            const Philox4 r0 = drawBlock(scene.init.seed, uint32_t(i), uint64_t(attempt) * 2, RngPurpose::Placement);
            const Philox4 r1 = drawBlock(scene.init.seed, uint32_t(i), uint64_t(attempt) * 2 + 1, RngPurpose::Placement);
            const double u[3] = {uniformOpen(r0.v[0], r0.v[1]), uniformOpen(r0.v[2], r0.v[3]), uniformOpen(r1.v[0], r1.v[1])};
            Vec3<double> p{};
            for (int a = 0; a < 3; ++a) p[a] = si.radius + u[a] * (scene.box.size[size_t(a)] - 2 * si.radius);
            bool free = true;
            grid.forNeighbours(p, [&](int64_t j) {
                const double d = placementDistance(si, scene.species[size_t(state.species[size_t(j)])]);
                if (norm2(p - state.position[size_t(j)]) < d * d) free = false;
            });
            if (free) {
                state.position[size_t(i)] = p;
                grid.insert(i, p);
                placed = true;
            }
        }
        if (!placed) {
            throw InputError(locatedMessage(scene.sourcePath, 0, "init.placement",
                                            "random placement found no free spot for particle " + std::to_string(i) + " of " +
                                                std::to_string(n) + " after " + std::to_string(kAttempts) +
                                                " tries: the box is too full for random insertion; use placement = \"lattice\" or a larger box"));
        }
    }
    report(progress, "random placement", n, n);
}

}  // namespace

void assignMaxwellBoltzmannVelocities(const Scene& scene, ParticleState& state) {
    const double kT = scene.init.temperature;
    Vec3<double> momentum{0, 0, 0};
    double totalMass = 0;
    for (size_t i = 0; i < state.size(); ++i) {
        const double m = scene.species[size_t(state.species[i])].mass;
        const double sd = std::sqrt(kT / m);
        double g[4];
        gaussianPair(drawBlock(scene.init.seed, uint32_t(i), 0, RngPurpose::InitialVelocity), &g[0], &g[1]);
        gaussianPair(drawBlock(scene.init.seed, uint32_t(i), 1, RngPurpose::InitialVelocity), &g[2], &g[3]);
        state.velocity[i] = {sd * g[0], sd * g[1], sd * g[2]};
        momentum += m * state.velocity[i];
        totalMass += m;
    }
    if (totalMass <= 0) return;
    const Vec3<double> drift = (1.0 / totalMass) * momentum;
    for (Vec3<double>& v : state.velocity) v -= drift;
}

void checkPlacement(const Scene& scene, const ParticleState& state, const std::string& source,
                    const SetupProgress& progress) {
    const double slack = kRestingOverlapAccepted;
    for (size_t i = 0; i < state.size(); ++i) {
        const double a = scene.species[size_t(state.species[i])].radius;
        for (int ax = 0; ax < 3; ++ax) {
            const double x = state.position[i][ax];
            if (x < a - slack * a || x > scene.box.size[size_t(ax)] - a + slack * a) {
                std::ostringstream msg;
                msg << "particle " << i << " lies outside the box: "
                    << "xyz"[ax] << " = " << x << " but its centre must be in [" << a << ", "
                    << scene.box.size[size_t(ax)] - a << "] (radius " << a << ")";
                throw InputError(locatedMessage(source, 0, "", msg.str()));
            }
        }
    }
    double maxContact = 0;
    for (const SpeciesDef& s : scene.species) maxContact = std::max(maxContact, 2 * s.radius);
    CellList grid;
    grid.build(state.position, Vec3<double>{scene.box.size[0], scene.box.size[1], scene.box.size[2]}, maxContact);
    // Each pair is checked once, from its higher index. Blocks of particles go to the threads in
    // turn; each thread keeps the first overlap of its blocks, and the one with the lowest index is
    // reported: the overlap a check in file order meets first, whatever the thread count.
    const int64_t n = int64_t(state.size());
    constexpr int64_t kBlock = 4096;
    const int64_t blocks = (n + kBlock - 1) / kBlock;
    struct Overlap {
        int64_t i = -1, j = -1;
        double r = 0, d = 0;
    };
    std::atomic<int64_t> nextBlock{0}, checked{0};
    // Only the calling thread reports (the callback need not be thread-safe), with every thread's count.
    int64_t reported = 0;
    auto work = [&](Overlap& first, bool reporting) {
        for (int64_t b = nextBlock++; b < blocks; b = nextBlock++) {
            const int64_t end = std::min(n, (b + 1) * kBlock);
            for (int64_t i = b * kBlock; i < end && (first.i < 0 || i < first.i); ++i) {
                const double ai = scene.species[size_t(state.species[size_t(i)])].radius;
                grid.forNeighbours(state.position[size_t(i)], [&](int64_t j) {
                    if (j >= i || (first.i == i && j >= first.j)) return;
                    const double d = ai + scene.species[size_t(state.species[size_t(j)])].radius;
                    const double r = std::sqrt(norm2(state.position[size_t(i)] - state.position[size_t(j)]));
                    if (r < d * (1 - slack)) first = Overlap{i, j, r, d};
                });
            }
            const int64_t done = checked += end - b * kBlock;
            if (reporting && progress && done - reported >= kProgressEvery) {
                progress("overlap check", done, n);
                reported = done;
            }
        }
    };
    const int threads = int(std::max<int64_t>(1, std::min<int64_t>(std::thread::hardware_concurrency(), blocks)));
    std::vector<Overlap> firsts(static_cast<size_t>(threads));
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(work, std::ref(firsts[size_t(t)]), false);
    work(firsts[0], true);
    for (std::thread& t : pool) t.join();
    if (progress) progress("overlap check", n, n);
    const Overlap* found = nullptr;
    for (const Overlap& o : firsts)
        if (o.i >= 0 && (!found || o.i < found->i || (o.i == found->i && o.j < found->j))) found = &o;
    if (found) {
        std::ostringstream msg;
        msg << "particles " << found->j << " and " << found->i << " overlap: centre distance " << found->r
            << " < contact distance " << found->d;
        throw InputError(locatedMessage(source, 0, "", msg.str()));
    }
}

ParticleState makeInitialState(const Scene& scene, const SetupProgress& progress) {
    // The rule scene validation applies: a scene from a file passed it already; one built in code
    // (a test, a benchmark, the panel's staged edits) meets it here.
    if (const std::optional<PackingProblem> problem = packingProblem(scene)) {
        throw InputError(locatedMessage(scene.sourcePath, 0, problem->key, problem->message));
    }
    checkHostMemory(scene);  // before the first allocation sized by N or by the box
    if (!scene.init.particlesFile.empty()) {
        ParticleState state = readStateCsv(scene.init.particlesFile);
        std::vector<int64_t> counts(scene.species.size(), 0);
        for (int32_t s : state.species) {
            if (size_t(s) >= scene.species.size()) {
                throw InputError(locatedMessage(scene.init.particlesFile, 0, "species",
                                                "species index " + std::to_string(s) + " but the scene defines " +
                                                    std::to_string(scene.species.size()) + " species"));
            }
            ++counts[size_t(s)];
        }
        for (size_t s = 0; s < counts.size(); ++s) {
            if (counts[s] != scene.species[s].count) {
                throw InputError(locatedMessage(scene.sourcePath, 0, "species[" + std::to_string(s) + "].count",
                                                "is " + std::to_string(scene.species[s].count) + " but " + scene.init.particlesFile +
                                                    " holds " + std::to_string(counts[s]) + " particles of species " + std::to_string(s)));
            }
        }
        checkPlacement(scene, state, scene.init.particlesFile, progress);
        return state;
    }
    ParticleState state;
    state.resize(size_t(scene.particleCount()));
    state.species = speciesOfIds(scene);
    if (scene.init.placement == Placement::Lattice) placeOnLattice(scene, state, progress);
    else placeRandomly(scene, state, progress);
    assignMaxwellBoltzmannVelocities(scene, state);
    checkPlacement(scene, state, scene.sourcePath.empty() ? "placement" : scene.sourcePath, progress);
    return state;
}

}  // namespace corebox
