// The one cell list (kernels/cell_list.h, src/core/host_cell_list.h): the cell-size rule gives
// today's dims wherever they fit the bound, the cell count stays bounded, non-finite positions land
// in valid cells, the host build visits exactly the pairs brute force finds (each once, from both
// sides, in ascending cell then index order), and a build is reproducible.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

#include "cell_list.h"
#include "host_cell_list.h"

using namespace corebox;

namespace {

// The rule as it was written twice before (CPU contact grid, CUDA backend), kept here as the oracle.
std::array<int, 3> formerDims(const Vec3<double>& box, int64_t n, double reach) {
    const double volume = box.x * box.y * box.z;
    const double cell = std::max(reach, std::cbrt(volume / double(std::max<int64_t>(2 * n, 1))));
    return {std::max(1, int(box.x / cell)), std::max(1, int(box.y / cell)), std::max(1, int(box.z / cell))};
}

void expectDims(const CellGeometry& g, std::array<int, 3> dims) {
    EXPECT_EQ(g.dims[0], dims[0]);
    EXPECT_EQ(g.dims[1], dims[1]);
    EXPECT_EQ(g.dims[2], dims[2]);
}

// Every cell at least minCell wide and the cell count within the bound, computed without overflow.
void expectValidGeometry(const CellGeometry& g, const Vec3<double>& box, int64_t n, double minCell) {
    int64_t cells = 1;
    for (int a = 0; a < 3; ++a) {
        ASSERT_GE(g.dims[a], 1);
        ASSERT_LE(g.dims[a], kMaxCellCount);
        cells *= g.dims[a];
        ASSERT_LE(cells, kMaxCellCount);
        // One cell along an axis holds every pair along it, however narrow the box is.
        if (g.dims[a] > 1) {
            EXPECT_GE(box[a] / g.dims[a], minCell) << "axis " << a;
        }
    }
    EXPECT_LE(cells, maxCellCount(n));
    EXPECT_EQ(int64_t(g.cellCount()), cells);
}

template <class Real>
std::vector<Vec3<Real>> randomPositions(int64_t n, const Vec3<double>& box, uint64_t seed, double outside = 0.0) {
    std::mt19937_64 rng(seed);
    std::vector<Vec3<Real>> x(static_cast<size_t>(n));
    for (Vec3<Real>& p : x) {
        for (int a = 0; a < 3; ++a) {
            std::uniform_real_distribution<double> u(-outside * box[a], (1 + outside) * box[a]);
            p[a] = Real(u(rng));
        }
    }
    return x;
}

// Brute force: every j != i closer than `reach` is visited exactly once from i, the visit sequence is
// ascending in (cell key, index), and i itself is visited (it lies in its own cell). Returns the
// number of close pairs seen (i < j), so callers can require the test to have had something to find.
template <class Real>
int64_t expectMatchesBruteForce(const CellList& list, const std::vector<Vec3<Real>>& x, double reach) {
    const int64_t n = int64_t(x.size());
    const CellGeometry& g = list.geometry();
    int64_t closePairs = 0;
    std::vector<int> seen(size_t(n), 0);
    for (int64_t i = 0; i < n; ++i) {
        std::fill(seen.begin(), seen.end(), 0);
        int64_t previousKey = -1, previousIndex = -1;
        bool ordered = true;
        list.forNeighbours(x[size_t(i)], [&](int64_t j) {
            ++seen[size_t(j)];
            const int64_t key = cellKeyOf(g, x[size_t(j)]);
            if (key < previousKey || (key == previousKey && j <= previousIndex)) ordered = false;
            previousKey = key;
            previousIndex = j;
        });
        EXPECT_TRUE(ordered) << "particle " << i;
        EXPECT_EQ(seen[size_t(i)], 1) << "particle " << i << " not in its own neighbourhood";
        for (int64_t j = 0; j < n; ++j) {
            EXPECT_LE(seen[size_t(j)], 1) << i << " visits " << j << " twice";
            if (j == i) continue;
            const Vec3<double> r = vec3Cast<double>(x[size_t(i)]) - vec3Cast<double>(x[size_t(j)]);
            if (norm2(r) < reach * reach) {
                EXPECT_EQ(seen[size_t(j)], 1) << "pair " << i << ", " << j << " at distance " << std::sqrt(norm2(r));
                if (i < j) ++closePairs;
            }
        }
        if (::testing::Test::HasFailure()) break;  // one broken particle says enough
    }
    return closePairs;
}

}  // namespace

TEST(CellListRule, KeepsTheFormerDimsWhereverTheyFitTheBound) {
    // Hand-checked: cell = max(reach, cbrt(V / 2n)), dims = floor(L / cell).
    expectDims(cellGeometry({10, 10, 10}, 1000, 1.0), {10, 10, 10});   // cbrt(0.5) < 1: reach decides
    expectDims(cellGeometry({10, 10, 10}, 100, 1.0), {5, 5, 5});       // cell = cbrt(5) = 1.71
    expectDims(cellGeometry({20, 10, 5}, 500, 0.5), {20, 10, 5});      // cell = cbrt(1) = 1
    expectDims(cellGeometry({10, 10, 10}, 1000, 3.3), {3, 3, 3});      // reach 3.3
    expectDims(cellGeometry({10, 10, 10}, 0, 1.0), {1, 1, 1});         // no particles: cbrt(V) = L
    expectDims(cellGeometry({3, 4, 5}, 1, 0.0), {1, 1, 1});            // one particle
    // And against the former formula over a sweep of boxes, counts and reaches.
    for (const Vec3<double> box : {Vec3<double>{10, 10, 10}, Vec3<double>{37.5, 12.25, 80}, Vec3<double>{1, 2, 3}}) {
        for (int64_t n : {1, 2, 7, 64, 1000, 1234, 65536, 1000000}) {
            for (double reach : {0.0, 0.1, 1.0, 2.5, 50.0}) {
                SCOPED_TRACE(::testing::Message() << "box " << box.x << "x" << box.y << "x" << box.z << " n " << n << " reach " << reach);
                const CellGeometry g = cellGeometry(box, n, reach);
                const std::array<int, 3> former = formerDims(box, n, reach);
                ASSERT_LE(int64_t(former[0]) * former[1] * former[2], maxCellCount(n)) << "sweep left the bound";
                expectDims(g, former);
                for (int a = 0; a < 3; ++a) EXPECT_EQ(g.inverseCell[a], double(g.dims[a]) / box[a]);
                expectValidGeometry(g, box, n, reach);
            }
        }
    }
}

TEST(CellListRule, BoundsTheCellCountForFlatAndHugeBoxes) {
    // A flat box: z shorter than a cell left x and y with 58 x 58 = 3364 cells for 1000 particles.
    const Vec3<double> flat{100, 100, 1};
    ASSERT_GT(int64_t(formerDims(flat, 1000, 1.0)[0]) * formerDims(flat, 1000, 1.0)[1], maxCellCount(1000));
    const CellGeometry g = cellGeometry(flat, 1000, 1.0);
    // The smallest uniform cell with floor(100/c)^2 <= 2064 has floor(100/c) = 45.
    expectDims(g, {45, 45, 1});
    expectValidGeometry(g, flat, 1000, 1.0);

    // One huge axis: the former rule asked for ~2.7e8 cells (and int overflow beyond) for 10 particles.
    const Vec3<double> line{1e12, 1, 1};
    expectValidGeometry(cellGeometry(line, 10, 1.0), line, 10, 1.0);
    EXPECT_GT(cellGeometry(line, 10, 1.0).dims[0], 1);  // still splits the long axis

    // Extremes that would overflow int in the former formula.
    struct Case {
        Vec3<double> box;
        int64_t n;
        double minCell;
    };
    for (const Case& c : {Case{{1e300, 1e-300, 1}, 5, 0.0}, Case{{1e4, 1e4, 1e4}, int64_t(1) << 40, 1e-9},
                          Case{{1e30, 1e30, 1e30}, 3, 1e-30}, Case{{1, 1, 1}, 1000, 0.0}}) {
        SCOPED_TRACE(::testing::Message() << "n " << c.n);
        expectValidGeometry(cellGeometry(c.box, c.n, c.minCell), c.box, c.n, c.minCell);
    }
    EXPECT_EQ(maxCellCount(int64_t(1) << 40), kMaxCellCount);
    EXPECT_LT(kMaxCellCount, int64_t(std::numeric_limits<int32_t>::max()));
}

TEST(CellListRule, NonFiniteInputsGiveValidGeometryAndCells) {
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    for (const Vec3<double> box : {Vec3<double>{nan, 10, 10}, Vec3<double>{inf, 10, 10}, Vec3<double>{inf, 0, 10}}) {
        for (double minCell : {1.0, nan, inf, 0.0}) {
            const CellGeometry g = cellGeometry(box, 100, minCell);
            for (int a = 0; a < 3; ++a) {
                EXPECT_GE(g.dims[a], 1);
                EXPECT_LE(g.dims[a], maxCellCount(100));
            }
            EXPECT_LE(int64_t(g.cellCount()), maxCellCount(100));
        }
    }

    const CellGeometry g = cellGeometry({10, 10, 10}, 1000, 1.0);  // 10 x 10 x 10
    ASSERT_EQ(g.dims[0], 10);
    // NaN and -inf clamp to the first cell, +inf and huge values to the last, like any outside position.
    EXPECT_EQ(cellCoord(nan, g.inverseCell[0], g.dims[0]), 0);
    EXPECT_EQ(cellCoord(-inf, g.inverseCell[0], g.dims[0]), 0);
    EXPECT_EQ(cellCoord(inf, g.inverseCell[0], g.dims[0]), 9);
    EXPECT_EQ(cellCoord(1e300, g.inverseCell[0], g.dims[0]), 9);
    EXPECT_EQ(cellCoord(-1e300, g.inverseCell[0], g.dims[0]), 0);
    EXPECT_EQ(cellCoord(std::numeric_limits<float>::quiet_NaN(), g.inverseCell[0], g.dims[0]), 0);
    EXPECT_EQ(cellCoord(-0.5, g.inverseCell[0], g.dims[0]), 0);
    EXPECT_EQ(cellCoord(9.99, g.inverseCell[0], g.dims[0]), 9);
    EXPECT_EQ(cellCoord(10.0, g.inverseCell[0], g.dims[0]), 9);
    EXPECT_EQ(cellCoord(3.5, g.inverseCell[0], g.dims[0]), 3);
    const int key = cellKeyOf(g, Vec3<double>{nan, inf, -inf});
    EXPECT_EQ(key, cellKey(g, CellCoords{0, 9, 0}));

    // A build with non-finite positions puts them in cells and still finds the finite pairs.
    std::vector<Vec3<double>> x = randomPositions<double>(300, {10, 10, 10}, 7);
    x[3] = {nan, 5, 5};
    x[100] = {inf, -inf, nan};
    CellList list;
    list.build(x, Vec3<double>{10, 10, 10}, 1.0);
    EXPECT_GT(expectMatchesBruteForce(list, x, 1.0), 0);
}

TEST(CellList, VisitsExactlyTheBruteForcePairsInAscendingOrder) {
    struct Case {
        Vec3<double> box;
        int64_t n;
        double reach;
        double outside;  // fraction of the box by which positions may lie outside it
    };
    // Dense (reach decides), dilute (density decides), flat (the bound decides), and particles
    // outside the box (clamped into the edge cells, as during collision resolution).
    for (const Case& c : {Case{{10, 10, 10}, 1500, 1.0, 0.0}, Case{{30, 20, 25}, 800, 0.7, 0.0}, Case{{40, 40, 1.5}, 900, 1.2, 0.0},
                          Case{{8, 9, 10}, 700, 1.5, 0.05}, Case{{5, 5, 5}, 40, 4.0, 0.0}}) {
        SCOPED_TRACE(::testing::Message() << "box " << c.box.x << "x" << c.box.y << "x" << c.box.z << " n " << c.n);
        const std::vector<Vec3<double>> xd = randomPositions<double>(c.n, c.box, uint64_t(c.n));
        CellList list;
        list.build(xd, c.box, c.reach);
        EXPECT_GT(expectMatchesBruteForce(list, xd, c.reach), 10);
        const std::vector<Vec3<float>> xf = randomPositions<float>(c.n, c.box, uint64_t(c.n) + 1, c.outside);
        list.build(xf, vec3Cast<float>(c.box), c.reach);
        EXPECT_GT(expectMatchesBruteForce(list, xf, c.reach), 10);
    }
}

TEST(CellList, PairsStraddlingCellFacesAreFound) {
    // Lattice points on the cell faces and pairs just closer than the reach across them: the cases a
    // cell coordinate rounded the wrong way would lose. reach = 1 in a 10-box gives 1-wide cells.
    std::vector<Vec3<double>> x;
    for (int k = 0; k <= 10; ++k) {
        const double f = double(k);
        x.push_back({f, 5.5, 5.5});
        x.push_back({f + 0.999, 5.5, 5.5});
        x.push_back({f - 0.999, 5.5, 5.5});
        x.push_back({5.5, f * 0.999, 5.5});
    }
    CellList list;
    list.build(x.data(), int64_t(x.size()), cellGeometry({10, 10, 10}, 1000, 1.0));
    ASSERT_EQ(list.geometry().dims[0], 10);
    EXPECT_GT(expectMatchesBruteForce(list, x, 1.0), 20);
}

TEST(CellList, LayoutIsTheStableSortByCellKey) {
    const Vec3<double> box{12, 7, 9};
    const std::vector<Vec3<double>> x = randomPositions<double>(2000, box, 11, 0.1);
    CellList list;
    list.build(x, box, 0.9);
    const CellGeometry& g = list.geometry();
    // Independent reference: indices stably sorted by cell key, start offsets by lower_bound.
    std::vector<int32_t> expected(x.size());
    std::iota(expected.begin(), expected.end(), 0);
    std::stable_sort(expected.begin(), expected.end(),
                     [&](int32_t a, int32_t b) { return cellKeyOf(g, x[size_t(a)]) < cellKeyOf(g, x[size_t(b)]); });
    EXPECT_EQ(list.sorted(), expected);
    ASSERT_EQ(list.cellStart().size(), size_t(g.cellCount()) + 1);
    for (int c = 0; c <= g.cellCount(); ++c) {
        const auto first = std::find_if(expected.begin(), expected.end(),
                                        [&](int32_t i) { return cellKeyOf(g, x[size_t(i)]) >= c; });
        EXPECT_EQ(list.cellStart()[size_t(c)], int32_t(first - expected.begin())) << "cell " << c;
    }
}

TEST(CellList, SameInputSameOrder) {
    const Vec3<double> box{10, 10, 10};
    const std::vector<Vec3<double>> x = randomPositions<double>(5000, box, 3);
    CellList a, b;
    a.build(x, box, 1.0);
    // b is rebuilt over other data first, so leftovers in its buffers would show.
    b.build(randomPositions<double>(777, box, 4), box, 2.0);
    b.build(x, box, 1.0);
    EXPECT_EQ(a.sorted(), b.sorted());
    EXPECT_EQ(a.cellStart(), b.cellStart());
    // The build depends on the position values only, not on the precision they are stored in: the
    // same values as float and as double give the same order.
    std::vector<Vec3<float>> xf(x.size());
    for (size_t i = 0; i < x.size(); ++i) xf[i] = vec3Cast<float>(x[i]);
    std::vector<Vec3<double>> xd(x.size());
    for (size_t i = 0; i < x.size(); ++i) xd[i] = vec3Cast<double>(xf[i]);
    CellList fromFloat, fromDouble;
    fromFloat.build(xf, vec3Cast<float>(box), 1.0);
    fromDouble.build(xd, box, 1.0);
    EXPECT_EQ(fromFloat.sorted(), fromDouble.sorted());
}

TEST(CellList, EmptyListVisitsNothing) {
    CellList list;
    int visits = 0;
    list.forNeighbours(Vec3<double>{1, 2, 3}, [&](int64_t) { ++visits; });
    list.build(std::vector<Vec3<double>>{}, Vec3<double>{10, 10, 10}, 1.0);
    list.forNeighbours(Vec3<double>{1, 2, 3}, [&](int64_t) { ++visits; });
    EXPECT_EQ(visits, 0);
    EXPECT_EQ(list.cellStart().back(), 0);
}

// The GPU list build walks the 27 cells as 9 runs of consecutive keys: together they are exactly the
// cells forEachNeighbourCell visits, each once, at every cell of grids with edges of one to four cells.
TEST(CellList, TheNineRunsAreTheTwentySevenCells) {
    for (int dx = 1; dx <= 4; ++dx)
        for (int dy = 1; dy <= 3; ++dy)
            for (int dz = 1; dz <= 4; ++dz) {
                CellGeometry g{};
                g.dims[0] = dx;
                g.dims[1] = dy;
                g.dims[2] = dz;
                for (int z = 0; z < dz; ++z)
                    for (int y = 0; y < dy; ++y)
                        for (int x = 0; x < dx; ++x) {
                            const CellCoords c{x, y, z};
                            std::vector<int> walked, runs;
                            forEachNeighbourCell(g, c, [&](int key) { walked.push_back(key); });
                            for (int r = 0; r < 9; ++r) {
                                int first = -1, last = -1;
                                if (!neighbourCellRun(g, c, r, &first, &last)) continue;
                                ASSERT_LE(first, last);
                                for (int key = first; key <= last; ++key) runs.push_back(key);
                            }
                            std::sort(runs.begin(), runs.end());
                            EXPECT_EQ(runs, walked) << "grid " << dx << "x" << dy << "x" << dz << ", cell " << x << "," << y << "," << z;
                        }
            }
}

TEST(IncrementalCellList, VisitsWhatASortedListOfTheInsertedParticlesVisits) {
    const Vec3<double> box{10, 10, 10};
    const std::vector<Vec3<double>> x = randomPositions<double>(1200, box, 5);
    const CellGeometry g = cellGeometry(box, int64_t(x.size()), 1.0);
    IncrementalCellList growing(g, int64_t(x.size()));
    CellList full;
    full.build(x.data(), int64_t(x.size()), g);
    for (int64_t i = 0; i < int64_t(x.size()); ++i) {
        std::vector<int64_t> got, want;
        growing.forNeighbours(x[size_t(i)], [&](int64_t j) { got.push_back(j); });
        full.forNeighbours(x[size_t(i)], [&](int64_t j) {
            if (j < i) want.push_back(j);
        });
        ASSERT_EQ(got, want) << "before inserting " << i;
        growing.insert(i, x[size_t(i)]);
    }
}

// ---- large particles kept out of the cells (cell_list.h: CellSplit, chooseCellSplit) ----

TEST(CellSplit, ChoosesTheSmallestRadiusWithFewParticlesAbove) {
    const double any = std::numeric_limits<double>::quiet_NaN();  // threshold not looked at
    struct Case {
        const char* why;
        std::vector<double> radius;
        std::vector<int64_t> count;
        double gridRadius, largeAbove;
    };
    for (const Case& k : std::vector<Case>{
             {"monodisperse: nothing to split", {0.5}, {100000}, 0.5, kNoLargeParticles},
             {"a few heavy balls twice as large: kept out, the cells sized for the small ones", {0.5, 1.0}, {100000, 3}, 0.5, 0.75},
             {"none of them yet: still large, so that a ball added later is never in cells too narrow for it",
              {0.5, 1.0},
              {100000, 0},
              0.5,
              0.75},
             {"too many to visit from every walk: one grid for all", {0.5, 1.0}, {100000, kMaxLargeParticles + 1}, 1.0, kNoLargeParticles},
             {"as many as every walk may visit", {0.5, 1.0}, {100000, kMaxLargeParticles}, 0.5, any},
             {"little larger: the cells would narrow by little", {0.5, 0.6}, {100000, 3}, 0.6, kNoLargeParticles},
             {"three sizes, in no order: the middle one too numerous to leave out, the threshold between it and the largest",
              {2.0, 0.5, 0.8},
              {5, 100000, 1000},
              0.8,
              1.4},
             // A radius a hair above another is no place for a threshold (float rounding would put it on
             // either side): the next place up, or none.
             {"a hair above: no place", {0.5, 0.50001}, {100000, 3}, 0.50001, kNoLargeParticles},
             {"a hair above: the next place up", {0.5, 0.50001, 1.0}, {100000, 3, 3}, 0.50001, 0.5 * (0.50001 + 1.0)},
             {"a hair above, both numerous", {0.5, 0.50001, 2.0}, {100000, 100000, 3}, 0.50001, 0.5 * (0.50001 + 2.0)},
             {"point particles with a few hard spheres: the spheres are large", {0.0, 0.5}, {1000, 2}, 0.0, 0.25}}) {
        SCOPED_TRACE(k.why);
        const CellSplitChoice c = chooseCellSplit(k.radius, k.count);
        EXPECT_EQ(c.gridRadius, k.gridRadius);
        if (!std::isnan(k.largeAbove)) {
            EXPECT_EQ(c.largeAbove, k.largeAbove);
        }
    }
    EXPECT_EQ(chooseCellSplit({}, {}).largeAbove, kNoLargeParticles);
    EXPECT_EQ(speciesCounts({0, 1, 1, 0, 0, 3, -1}, 3), (std::vector<int64_t>{3, 2, 0}));
}

namespace {

// Builds with the large particles split off and checks that every particle's walk (its radius passed)
// visits each particle within r_i + r_j + gap exactly once, and the large ones last in ascending index.
template <class Real>
int64_t expectSplitWalksFindEveryPair(const std::vector<Vec3<Real>>& x, const std::vector<int32_t>& species,
                                      const std::vector<Real>& radius, const Vec3<double>& box, double gap) {
    std::vector<double> radii(radius.begin(), radius.end());
    const CellSplitChoice choice = chooseCellSplit(radii, speciesCounts(species, int(radius.size())));
    EXPECT_LT(choice.largeAbove, kNoLargeParticles);
    const int64_t n = int64_t(x.size());
    CellList list;
    const CellGeometry g = cellGeometry(box, n, 2 * choice.gridRadius + gap);
    list.build(x.data(), n, g, CellSplit<Real>{species.data(), radius.data(), choice.largeAbove}, choice.gridRadius);
    const int32_t tail = list.cellStart()[size_t(g.cellCount())];
    int64_t pairs = 0, large = 0;
    for (int64_t i = 0; i < n; ++i) large += double(radius[size_t(species[size_t(i)])]) > choice.largeAbove ? 1 : 0;
    EXPECT_EQ(n - tail, large);
    for (int32_t k = tail; k + 1 < int32_t(n); ++k) EXPECT_LT(list.sorted()[size_t(k)], list.sorted()[size_t(k) + 1]);
    for (int64_t i = 0; i < n; ++i) {
        const Real ri = radius[size_t(species[size_t(i)])];
        std::vector<int> seen(size_t(n), 0);
        list.forNeighbours(x[size_t(i)], ri, [&](int64_t j) { ++seen[size_t(j)]; });
        for (int64_t j = 0; j < n; ++j) {
            EXPECT_LE(seen[size_t(j)], 1) << i << " visits " << j << " twice";
            const double reach = double(ri) + double(radius[size_t(species[size_t(j)])]) + gap;
            if (j != i && norm2(vec3Cast<double>(x[size_t(i)]) - vec3Cast<double>(x[size_t(j)])) < reach * reach) {
                EXPECT_EQ(seen[size_t(j)], 1) << i << " misses " << j;
                ++pairs;
            }
        }
    }
    return pairs;
}

}  // namespace

TEST(CellSplit, EveryPairIsVisitedOnceFromBothSides) {
    // 3000 balls of radius 0.5, a few of radius 1, 2.5 and 6 (one larger than a dozen cells), some just
    // outside the box (being resolved): every pair within the contact distance plus a gap is walked.
    for (const double gap : {0.0, 0.05}) {
        const Vec3<double> box{18, 14, 16};
        std::vector<Vec3<double>> x = randomPositions<double>(3000, box, 17, 0.02);
        std::vector<int32_t> species(x.size(), 0);
        for (size_t k : {3u, 500u, 501u, 1700u, 2999u}) species[k] = 1;
        for (size_t k : {10u, 2000u}) species[k] = 2;
        species[1234] = 3;
        x[1234] = {9, 7, 8};
        const std::vector<double> radius{0.5, 1.0, 2.5, 6.0};
        EXPECT_GT(expectSplitWalksFindEveryPair(x, species, radius, box, gap), 1000);
        std::vector<Vec3<float>> xf(x.size());
        for (size_t i = 0; i < x.size(); ++i) xf[i] = vec3Cast<float>(x[i]);
        EXPECT_GT(expectSplitWalksFindEveryPair(xf, species, std::vector<float>{0.5f, 1.0f, 2.5f, 6.0f}, box, gap), 1000);
    }
    // A slab thinner than a cell (one cell across it, narrower than minCell): the large particles'
    // reach is set by the axes of several cells. Radii 0.5 and 0.6 (60 balls) and 2 (none).
    const Vec3<double> slab{18, 14, 1.0};
    const std::vector<Vec3<double>> x = randomPositions<double>(1500, slab, 23, 0.02);
    std::vector<int32_t> species(x.size(), 0);
    for (size_t k = 3; k < x.size(); k += 25) species[k] = 1;
    EXPECT_GT(expectSplitWalksFindEveryPair(x, species, std::vector<double>{0.5, 0.6, 2.0}, slab, 0.4), 1000);
}
