// The GPU cell list (kernels/cell_list_kernels.cu: keys, stable radix sort, cell starts by binary
// search) must give exactly the host's counting-sort arrays (src/core/host_cell_list.h), which the unit
// tests check against brute force and a stable sort, and the same arrays on every build. Exact
// equality, no tolerance: both sides compute cell keys from the same values with the same function.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "device_buffer.h"
#include "device_cell_list.h"
#include "gpu_fixture.h"
#include "gpu_launch.h"
#include "host_cell_list.h"

using namespace corebox;

namespace {

// Builds on the device through the backend's DeviceCellList and reads back (cellStart, sorted).
template <class Real>
struct DeviceBuild {
    DeviceBuffer<Vec3<Real>> x;
    DeviceCellList<Real> cells;

    std::pair<std::vector<int32_t>, std::vector<int32_t>> build(const std::vector<Vec3<Real>>& positions,
                                                                const CellGeometry& geometry) {
        const int64_t n = int64_t(positions.size());
        x.upload(positions.data(), positions.size());
        // Build once to size the buffers, poison the outputs so that an entry the build fails to
        // write shows up, then build again and read that.
        CellListView view = cells.build(x.data(), n, geometry, nullptr);
        cudaCheck(cudaDeviceSynchronize(), "cell list build");
        const size_t cellsPlusOne = size_t(geometry.cellCount()) + 1;
        cudaCheck(cudaMemset(const_cast<int32_t*>(view.cellStart), 0xff, cellsPlusOne * sizeof(int32_t)), "memset");
        if (n > 0) cudaCheck(cudaMemset(const_cast<int32_t*>(view.sorted), 0xff, size_t(n) * sizeof(int32_t)), "memset");
        view = cells.build(x.data(), n, geometry, nullptr);
        cudaCheck(cudaDeviceSynchronize(), "cell list build");
        std::vector<int32_t> starts(static_cast<size_t>(geometry.cellCount()) + 1);
        std::vector<int32_t> order(static_cast<size_t>(n));
        cudaCheck(cudaMemcpy(starts.data(), view.cellStart, starts.size() * sizeof(int32_t), cudaMemcpyDeviceToHost), "download");
        if (n > 0) cudaCheck(cudaMemcpy(order.data(), view.sorted, order.size() * sizeof(int32_t), cudaMemcpyDeviceToHost), "download");
        return {starts, order};
    }
};

template <class Real>
std::vector<Vec3<Real>> randomPositions(int64_t n, const Vec3<double>& box, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::vector<Vec3<Real>> x(static_cast<size_t>(n));
    for (Vec3<Real>& p : x) {
        for (int a = 0; a < 3; ++a) {
            // A few percent outside the box on each side, as during collision resolution.
            std::uniform_real_distribution<double> u(-0.03 * box[a], 1.03 * box[a]);
            p[a] = Real(u(rng));
        }
    }
    return x;
}

template <class Real>
void expectSameAsHost(const std::vector<Vec3<Real>>& x, const Vec3<double>& box, double minCell) {
    const CellGeometry g = cellGeometry(box, int64_t(x.size()), minCell);
    CellList host;
    host.build(x.data(), int64_t(x.size()), g);
    DeviceBuild<Real> device;
    const auto first = device.build(x, g);
    EXPECT_EQ(first.first, host.cellStart());
    EXPECT_EQ(first.second, host.sorted());
    // Again after a build over other data (stale buffers), and once more from scratch.
    device.build(randomPositions<Real>(int64_t(x.size()) / 2 + 3, box, 99), cellGeometry(box, int64_t(x.size()) / 2 + 3, minCell));
    const auto second = device.build(x, g);
    EXPECT_EQ(second, first);
    DeviceBuild<Real> fresh;
    EXPECT_EQ(fresh.build(x, g), first);
}

}  // namespace

TEST(CudaCellList, MatchesTheHostBuildExactlyAndRepeats) {
    COREBOX_REQUIRE_GPU();
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    struct Case {
        Vec3<double> box;
        int64_t n;
        double minCell;
    };
    // Dense, dilute, the DESIGN.md conformance size, a flat box (the cell-count bound), one particle; and
    // the builds in one block (kernels/cell_list_kernels.cu): the shared-memory counting sort up to 1024
    // particles (about one a cell, and a dozen a cell, whose order inside a cell it restores), the
    // block radix sort up to 4096; the device-wide sort beyond.
    for (const Case& c : {Case{{10, 10, 10}, 3000, 1.0}, Case{{40, 30, 50}, 1234, 0.8}, Case{{60, 60, 1}, 4000, 1.0},
                          Case{{5, 5, 5}, 1, 1.0}, Case{{200, 200, 200}, 100000, 1.0}, Case{{10, 10, 10}, 1000, 1.0},
                          Case{{4, 4, 4}, 1024, 1.0}, Case{{12, 12, 12}, 700, 1.3}}) {
        SCOPED_TRACE(::testing::Message() << "n " << c.n);
        std::vector<Vec3<double>> xd = randomPositions<double>(c.n, c.box, uint64_t(c.n));
        if (c.n > 10) {
            xd[1] = {nan, 1, 1};
            xd[7] = {inf, -inf, nan};
        }
        expectSameAsHost(xd, c.box, c.minCell);
        std::vector<Vec3<float>> xf(xd.size());
        for (size_t i = 0; i < xd.size(); ++i) xf[i] = vec3Cast<float>(xd[i]);
        expectSameAsHost(xf, c.box, c.minCell);
    }
}

TEST(CudaCellList, EmptyBuildHasEmptyCells) {
    COREBOX_REQUIRE_GPU();
    const CellGeometry g = cellGeometry({10, 10, 10}, 0, 1.0);
    DeviceBuild<double> device;
    const auto built = device.build({}, g);
    EXPECT_EQ(built.first, std::vector<int32_t>(size_t(g.cellCount()) + 1, 0));
    EXPECT_TRUE(built.second.empty());
}

// Positions, species and radii on the device.
template <class Real>
struct DeviceParticles {
    DeviceBuffer<Vec3<Real>> x;
    DeviceBuffer<int32_t> species;
    DeviceBuffer<Real> radius;
    DeviceParticles(const std::vector<Vec3<Real>>& xs, const std::vector<int32_t>& ss, const std::vector<Real>& rs) {
        x.upload(xs.data(), xs.size());
        species.upload(ss.data(), ss.size());
        radius.upload(rs.data(), rs.size());
    }
};

// A non-blocking stream of a test's own (graph builds need one: none on the legacy default stream),
// destroyed however the test ends.
struct TestStream {
    cudaStream_t stream = nullptr;
    TestStream() { cudaCheck(cudaStreamCreateWithFlags(&stream, cudaStreamNonBlocking), "stream"); }
    ~TestStream() { cudaStreamDestroy(stream); }
    TestStream(const TestStream&) = delete;
    TestStream& operator=(const TestStream&) = delete;
};

// A device build's arrays (finished) against the host's.
void expectViewEquals(const CellListView& view, const CellList& host, int64_t n) {
    std::vector<int32_t> starts(size_t(view.geometry.cellCount()) + 1);
    std::vector<int32_t> order(static_cast<size_t>(n));
    cudaCheck(cudaMemcpy(starts.data(), view.cellStart, starts.size() * sizeof(int32_t), cudaMemcpyDeviceToHost), "download");
    if (n > 0) cudaCheck(cudaMemcpy(order.data(), view.sorted, order.size() * sizeof(int32_t), cudaMemcpyDeviceToHost), "download");
    EXPECT_EQ(starts, host.cellStart());
    EXPECT_EQ(order, host.sorted());
}

// With large particles kept out of the cells (cell_list.h, CellSplit): the same arrays as the host's
// build, in every build path (the shared-memory counting sort, the block radix sort, the device-wide
// sort), the tail after the cells in ascending index.
template <class Real>
void expectSplitSameAsHost(int64_t n, const Vec3<double>& box, uint64_t seed) {
    std::vector<Vec3<Real>> x = randomPositions<Real>(n, box, seed);
    std::vector<int32_t> species(size_t(n), 0);
    for (int64_t i = 3; i < n; i += 97) species[size_t(i)] = 1 + int32_t(i % 2);
    const std::vector<Real> radius{Real(0.5), Real(1.0), Real(2.0)};
    const CellSplitChoice choice = chooseCellSplit({0.5, 1.0, 2.0}, speciesCounts(species, 3));
    const int64_t large = int64_t(std::count_if(species.begin(), species.end(), [](int32_t s) { return s > 0; }));
    ASSERT_LE(large, kMaxLargeParticles);
    ASSERT_EQ(choice.largeAbove, 0.75);
    const CellGeometry g = cellGeometry(box, n, 2 * choice.gridRadius);
    CellList host;
    host.build(x.data(), n, g, CellSplit<Real>{species.data(), radius.data(), choice.largeAbove}, choice.gridRadius);
    EXPECT_EQ(host.cellStart()[size_t(g.cellCount())], int32_t(n - large));
    const DeviceParticles<Real> d(x, species, radius);
    DeviceCellList<Real> cells;
    const CellListView view =
        cells.build(d.x.data(), n, g, CellSplit<Real>{d.species.data(), d.radius.data(), choice.largeAbove}, choice.gridRadius, nullptr);
    cudaCheck(cudaDeviceSynchronize(), "cell list build");
    expectViewEquals(view, host, n);
    EXPECT_EQ(view.count, int32_t(n));
    EXPECT_EQ(view.largeAbove, 0.75);
    EXPECT_DOUBLE_EQ(view.largeReach, largeReachOf(g, 0.5));
}

TEST(CudaCellList, KeepsLargeParticlesOutOfTheCellsAsTheHostDoes) {
    COREBOX_REQUIRE_GPU();
    for (const int64_t n : {int64_t(900), int64_t(3000), int64_t(6000)}) {
        SCOPED_TRACE(::testing::Message() << "n " << n);
        expectSplitSameAsHost<float>(n, {14, 12, 13}, uint64_t(n));
        expectSplitSameAsHost<double>(n, {14, 12, 13}, uint64_t(n) + 1);
    }
}

// On a stream of its own a build of more than one block is a CUDA graph, captured the first time its
// arguments are seen and launched again while they are the same (src/cuda/device_cell_list.h): builds
// that alternate geometries, counts and splits, and a list swapped with another, give the host's arrays
// every time.
TEST(CudaCellList, GraphBuildsFollowEveryChangeOfTheirArguments) {
    COREBOX_REQUIRE_GPU();
    const TestStream owned;
    const cudaStream_t stream = owned.stream;
    const Vec3<double> box{20, 16, 18};
    const int64_t n = 9000;
    std::vector<Vec3<float>> x = randomPositions<float>(n, box, 5);
    std::vector<int32_t> species(size_t(n), 0);
    for (int64_t i = 7; i < n; i += 301) species[size_t(i)] = 1;
    const std::vector<float> radius{0.5f, 1.0f};
    DeviceParticles<float> d(x, species, radius);
    DeviceCellList<float> cells, other;
    auto check = [&](DeviceCellList<float>& list, int64_t count, double minCell, bool split, const char* what) {
        SCOPED_TRACE(what);
        const CellGeometry g = cellGeometry(box, count, minCell);
        const CellSplit<float> hostSplit = split ? CellSplit<float>{species.data(), radius.data(), 0.75} : CellSplit<float>{};
        const CellSplit<float> deviceSplit = split ? CellSplit<float>{d.species.data(), d.radius.data(), 0.75} : CellSplit<float>{};
        CellList host;
        host.build(x.data(), count, g, hostSplit, 0.5);
        const CellListView view = list.build(d.x.data(), count, g, deviceSplit, 0.5, stream);
        cudaCheck(cudaStreamSynchronize(stream), "build");
        expectViewEquals(view, host, count);
    };
    check(cells, n, 1.0, true, "first build (captured)");
    check(cells, n, 1.0, true, "again (launched)");
    check(cells, n, 1.3, true, "wider cells");
    check(cells, n, 1.0, true, "the first geometry again");
    check(cells, n, 1.0, false, "no split");
    check(cells, n - 2500, 1.0, true, "fewer particles");
    // New positions in the same buffer: the graph reads them.
    x = randomPositions<float>(n, box, 6);
    d.x.upload(x.data(), x.size());
    check(cells, n, 1.0, true, "new positions");
    check(other, n, 1.3, true, "another list");
    swap(cells, other);
    check(cells, n, 1.3, true, "swapped in");
    check(other, n, 1.0, true, "swapped out");
}

// Graph builds sort by counting (gpu::launchCountedCellList) and fall back to the radix sort inside the
// graph where a cell holds more than kCountedCellMost particles: cells of exactly that many and of one
// more, every particle in one cell (a blow-up), and a crowded tail of large particles, each against the
// host's arrays, in fp32 and fp64.
template <class Real>
void expectCrowdedSameAsHost(cudaStream_t stream) {
    const Vec3<double> box{20, 16, 18};
    const int64_t n = 9000;
    const int most = int(gpu::kCountedCellMost);
    struct Case {
        int crowd;       // particles put at one point
        int largeEvery;  // every this many a large particle (0: none)
        const char* what;
    };
    for (const Case& c : {Case{most, 0, "a cell at the counted sort's most"},
                          Case{most + 1, 0, "one more: the fallback"}, Case{int(n), 0, "every particle in one cell"},
                          Case{0, 100, "90 large particles after the cells"}, Case{0, 0, "no crowd"}}) {
        SCOPED_TRACE(c.what);
        std::vector<Vec3<Real>> x = randomPositions<Real>(n, box, uint64_t(c.crowd) + 11);
        // The crowd at a cell's centre; the cell's random residents make it fuller still but for the
        // first case, whose cell is emptied of them first.
        const Vec3<Real> point{Real(5.5), Real(5.5), Real(5.5)};
        std::vector<int32_t> species(size_t(n), 0);
        const CellGeometry g = cellGeometry(box, n, 1.0);
        const int pointKey = cellKeyOf(g, point);
        for (Vec3<Real>& p : x)
            if (cellKeyOf(g, p) == pointKey) p = Vec3<Real>{Real(15.5), Real(12.5), Real(0.5)};
        for (int k = 0; k < c.crowd; ++k) x[size_t(k * (n / std::max(c.crowd, 1)))] = point;
        if (c.largeEvery > 0)
            for (int64_t i = 0; i < n; i += c.largeEvery) species[size_t(i)] = 1;
        const std::vector<Real> radius{Real(0.5), Real(1.0)};
        const CellSplit<Real> hostSplit{species.data(), radius.data(), 0.75};
        CellList host;
        host.build(x.data(), n, g, hostSplit, 0.5);
        DeviceParticles<Real> d(x, species, radius);
        DeviceCellList<Real> cells;
        for (int build = 0; build < 2; ++build) {  // captured, then launched
            const CellListView view =
                cells.build(d.x.data(), n, g, CellSplit<Real>{d.species.data(), d.radius.data(), 0.75}, 0.5, stream);
            cudaCheck(cudaStreamSynchronize(stream), "build");
            expectViewEquals(view, host, n);
        }
        EXPECT_TRUE(cells.buildsByCounting()) << "the graph builds fell back to the radix sort for good";
    }
}

TEST(CudaCellList, CountedGraphBuildsFallBackToTheRadixSortWhereACellIsCrowded) {
    COREBOX_REQUIRE_GPU();
    const TestStream owned;
    const cudaStream_t stream = owned.stream;
    expectCrowdedSameAsHost<float>(stream);
    expectCrowdedSameAsHost<double>(stream);
}

// rebuildIfMoved's build (one cooperative launch, gpu::launchCellListIfMoved) sorts a crowded cell itself:
// from an uncrowded build, the particles moved into the crowded cases above and flagged, each against the
// host's arrays, in fp32 and fp64.
template <class Real>
void expectCrowdedRebuildSameAsHost(cudaStream_t stream) {
    const Vec3<double> box{20, 16, 18};
    const int64_t n = 9000;
    const int most = int(gpu::kCountedCellMost);
    const CellGeometry g = cellGeometry(box, n, 1.0);
    const Vec3<Real> point{Real(5.5), Real(5.5), Real(5.5)};
    const int pointKey = cellKeyOf(g, point);
    for (const auto& [crowd, what] : {std::pair<int, const char*>{most, "a cell at the counted sort's most"},
                                      {most + 1, "one more"},
                                      {int(n), "every particle in one cell"}}) {
        SCOPED_TRACE(what);
        const std::vector<Vec3<Real>> start = randomPositions<Real>(n, box, 31);
        std::vector<Vec3<Real>> x = start;
        for (Vec3<Real>& p : x)
            if (cellKeyOf(g, p) == pointKey) p = Vec3<Real>{Real(15.5), Real(12.5), Real(0.5)};
        for (int k = 0; k < crowd; ++k) x[size_t(k * (n / crowd))] = point;
        const std::vector<int32_t> species(size_t(n), 0);
        const std::vector<Real> radius{Real(0.5)};
        DeviceParticles<Real> d(start, species, radius);
        DeviceBuffer<unsigned int> moved;
        const unsigned int one = 1;
        moved.upload(&one, 1);
        DeviceCellList<Real> cells;
        cells.build(d.x.data(), n, g, CellSplit<Real>{}, 0.5, stream);
        cudaCheck(cudaStreamSynchronize(stream), "build");  // before the positions change under it
        d.x.upload(x.data(), x.size());
        const CellListView view = cells.rebuildIfMoved(d.x.data(), n, g, CellSplit<Real>{}, 0.5, moved.data(), stream);
        cudaCheck(cudaStreamSynchronize(stream), "rebuild");
        unsigned int flag = 7;
        cudaCheck(cudaMemcpy(&flag, moved.data(), sizeof flag, cudaMemcpyDeviceToHost), "download");
        EXPECT_EQ(flag, 0u) << "the gated build did not run (a plain build leaves the flag)";
        CellList host;
        host.build(x.data(), n, g, CellSplit<Real>{}, 0.5);
        expectViewEquals(view, host, n);
    }
}

TEST(CudaCellList, RebuildIfMovedSortsACrowdedCellAsTheHost) {
    COREBOX_REQUIRE_GPU();
    const TestStream owned;
    expectCrowdedRebuildSameAsHost<float>(owned.stream);
    expectCrowdedRebuildSameAsHost<double>(owned.stream);
}

// rebuildIfMoved (the impact rounds' builds after the first): with the flag clear the build is skipped,
// the arrays left as they were (here poisoned, to see it), and with it set the build runs and gives the
// host's arrays at the new positions; either way the flag is cleared. Other arguments than the last
// build's make it build whatever the flag says.
TEST(CudaCellList, RebuildIfMovedBuildsOnlyWhereFlagged) {
    COREBOX_REQUIRE_GPU();
    const TestStream owned;
    const cudaStream_t stream = owned.stream;
    const Vec3<double> box{20, 16, 18};
    const int64_t n = 9000;
    std::vector<Vec3<float>> x = randomPositions<float>(n, box, 21);
    DeviceBuffer<Vec3<float>> dx;
    dx.upload(x.data(), x.size());
    DeviceBuffer<unsigned int> moved;
    const unsigned int zero = 0, one = 1;
    moved.upload(&zero, 1);
    const CellGeometry g = cellGeometry(box, n, 1.0);
    DeviceCellList<float> cells;
    auto hostOf = [&](const std::vector<Vec3<float>>& at, const CellGeometry& geometry) {
        CellList host;
        host.build(at.data(), n, geometry, CellSplit<float>{}, 0.5);
        return host;
    };
    auto flag = [&]() {
        unsigned int v = 7;
        cudaCheck(cudaMemcpy(&v, moved.data(), sizeof v, cudaMemcpyDeviceToHost), "download");
        return v;
    };
    CellListView view = cells.build(dx.data(), n, g, CellSplit<float>{}, 0.5, stream);
    ASSERT_NE(cells.keys(), nullptr);
    cudaCheck(cudaStreamSynchronize(stream), "build");
    expectViewEquals(view, hostOf(x, g), n);
    for (int pass = 0; pass < 2; ++pass) {  // twice: the second from the first's arrays
        SCOPED_TRACE(pass);
        // Not flagged: skipped. The poison (on the build's stream, so ordered before it) stays.
        cudaCheck(cudaMemsetAsync(const_cast<int32_t*>(view.sorted), 0xff, size_t(n) * sizeof(int32_t), stream),
                  "memset");
        view = cells.rebuildIfMoved(dx.data(), n, g, CellSplit<float>{}, 0.5, moved.data(), stream);
        cudaCheck(cudaStreamSynchronize(stream), "skipped build");
        std::vector<int32_t> order(static_cast<size_t>(n));
        cudaCheck(cudaMemcpy(order.data(), view.sorted, order.size() * sizeof(int32_t), cudaMemcpyDeviceToHost),
                  "download");
        EXPECT_EQ(order, std::vector<int32_t>(size_t(n), -1)) << "the build ran without the flag";
        // Flagged, at new positions: built, the flag cleared.
        x = randomPositions<float>(n, box, 22 + uint64_t(pass));
        dx.upload(x.data(), x.size());
        moved.upload(&one, 1);
        view = cells.rebuildIfMoved(dx.data(), n, g, CellSplit<float>{}, 0.5, moved.data(), stream);
        cudaCheck(cudaStreamSynchronize(stream), "flagged build");
        expectViewEquals(view, hostOf(x, g), n);
        EXPECT_EQ(flag(), 0u) << "the flag was not cleared";
    }
    // Another geometry than the last build's: built without the flag.
    const CellGeometry wider = cellGeometry(box, n, 1.3);
    view = cells.rebuildIfMoved(dx.data(), n, wider, CellSplit<float>{}, 0.5, moved.data(), stream);
    cudaCheck(cudaStreamSynchronize(stream), "new geometry");
    expectViewEquals(view, hostOf(x, wider), n);
}
