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
