// Verlet neighbour lists of the CPU backend (DESIGN.md sec. 2, forces with a cutoff).
//
// Design note.
// - Built on the one grid (src/core/host_cell_list.h) with cells at least r_c + skin wide, so every
//   pair within reach lies in adjacent cells. Particle i lists the later particles of its own cell and
//   those of the 13 cells of the half-shell stencil closer than r_c + skin: a half list, every pair
//   once (Newton's third law), found by one walk over half the neighbourhood.
// - Rebuilt when some particle has moved more than skin / 2 since the last build (then no pair can
//   have come from beyond r_c + skin to within r_c), never on a schedule; also when the reach, the
//   particle count or the box changed.
// - Layout: compressed rows, placed in memory in the cell list's order (particleAt). Row i holds its
//   partners by ascending index, slots rowBegin(i) .. rowEnd(i). The transposed index lists, for every j, the slots of the pairs whose partner it
//   is, by ascending owner index. The force pass evaluates each pair once into its slot; then every
//   particle gathers its own and its incoming slots merged by ascending partner index
//   (forEachPartner; the merged order is kept per particle as a gather plan, built with the list), so
//   no two threads write one particle and a particle's sum depends neither on
//   the thread count nor on when the list was built: a pair's value is the same from either side,
//   and a listed pair beyond the cutoff adds an exact zero. That is what lets a run restarted from a
//   checkpoint, whose list is built afresh, go on bit for bit.
#pragma once

#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "cpu_parallel.h"
#include "host_cell_list.h"
#include "vec3.h"

namespace corebox {

template <class Real>
class VerletList {
public:
    // Makes the list valid for positions x; returns true when it was rebuilt.
    bool update(const std::vector<Vec3<Real>>& x, const Vec3<Real>& box, double cutoff, double skin, int threads) {
        const int64_t n = int64_t(x.size());
        const bool sameGeometry = m_valid && n == int64_t(m_xBuilt.size()) && cutoff == m_cutoff && skin == m_skin &&
                                  box.x == m_box.x && box.y == m_box.y && box.z == m_box.z;
        if (sameGeometry && maxDisplacement2(x, threads) <= 0.25 * skin * skin) return false;
        build(x, box, cutoff, skin, threads);
        return true;
    }
    void invalidate() { m_valid = false; }

    int64_t builds() const { return m_builds; }
    int64_t pairCount() const { return int64_t(m_partner.size()); }
    // Rows, incoming lists and gather plans lie in memory in the cell list's order (particleAt(r) is the
    // r-th particle of that order): the slots a particle gathers belong to its spatial neighbours and
    // lie near its own, and loops over r walk memory in order.
    int64_t particleAt(int64_t r) const { return m_order[size_t(r)]; }
    int64_t rowBegin(int64_t i) const { return m_rowStart[size_t(m_rank[size_t(i)])]; }
    int64_t rowEnd(int64_t i) const { return m_rowStart[size_t(m_rank[size_t(i)]) + 1]; }
    int32_t partner(int64_t slot) const { return m_partner[size_t(slot)]; }
    // Pairs whose partner is j: entries inBegin(j) .. inEnd(j) of inSlot / inOwner.
    int64_t inBegin(int64_t j) const { return m_inStart[size_t(m_rank[size_t(j)])]; }
    int64_t inEnd(int64_t j) const { return m_inStart[size_t(m_rank[size_t(j)]) + 1]; }
    int64_t inSlot(int64_t k) const { return m_inSlot[size_t(k)]; }
    int32_t inOwner(int64_t k) const { return m_inOwner[size_t(k)]; }

    // The gather plan of i: entries gatherBegin(i) .. gatherEnd(i) of gatherEntry, one per listed
    // partner by ascending index: 2 * slot for an own pair, 2 * slot + 1 for an incoming one.
    int64_t gatherBegin(int64_t i) const { return rowBegin(i) + inBegin(i); }
    int64_t gatherEnd(int64_t i) const { return rowEnd(i) + inEnd(i); }
    int64_t gatherEntry(int64_t e) const { return m_gather[size_t(e)]; }

    // fn(j, slot) for every listed partner j of i, own and incoming, by ascending j.
    template <class Fn>
    void forEachPartner(int64_t i, Fn&& fn) const {
        int64_t k = rowBegin(i), q = inBegin(i);
        const int64_t kEnd = rowEnd(i), qEnd = inEnd(i);
        while (k < kEnd || q < qEnd) {
            if (q == qEnd || (k < kEnd && m_partner[size_t(k)] < m_inOwner[size_t(q)])) {
                fn(int64_t(m_partner[size_t(k)]), k);
                ++k;
            } else {
                fn(int64_t(m_inOwner[size_t(q)]), m_inSlot[size_t(q)]);
                ++q;
            }
        }
    }

private:
    double maxDisplacement2(const std::vector<Vec3<Real>>& x, int threads) const {
        const int64_t n = int64_t(x.size());
        double worst = 0;
#pragma omp parallel for schedule(static) num_threads(threads) reduction(max : worst) if (n >= kParallelThreshold)
        for (int64_t i = 0; i < n; ++i) {
            const Vec3<double> d = vec3Cast<double>(x[size_t(i)]) - vec3Cast<double>(m_xBuilt[size_t(i)]);
            const double d2 = norm2(d);
            // NaN compares false: a non-finite particle forces a rebuild (and the health check reports it).
            worst = d2 <= worst ? worst : (d2 == d2 ? d2 : 1e300);
        }
        return worst;
    }

    // fn(j) for the partners of i: later particles of i's own cell, then every particle of the 13
    // cells after it in the half-shell stencil (each pair of adjacent cells once), within reach.
    template <class Fn>
    void forPartners(const std::vector<Vec3<Real>>& x, int64_t i, Real reach2, Fn&& fn) const {
        const CellListView grid = m_grid.view();
        const Vec3<Real> xi = x[size_t(i)];
        const CellCoords c = cellCoords(grid.geometry, xi);
        auto visit = [&](int key, bool ownCell) {
            for (int32_t k = grid.cellStart[key]; k < grid.cellStart[key + 1]; ++k) {
                const int64_t j = grid.sorted[k];
                if (ownCell && j <= i) continue;
                if (norm2(xi - x[size_t(j)]) < reach2) fn(j);
            }
        };
        visit(cellKey(grid.geometry, c), true);
        for (const CellCoords& d : kHalfShell) {
            const CellCoords n{c.x + d.x, c.y + d.y, c.z + d.z};
            if (n.x < 0 || n.y < 0 || n.z < 0 || n.x >= grid.geometry.dims[0] || n.y >= grid.geometry.dims[1] || n.z >= grid.geometry.dims[2])
                continue;
            visit(cellKey(grid.geometry, n), false);
        }
    }

    // The 13 neighbour offsets after (0, 0, 0) in (z, y, x) order: with their mirror images, all 26.
    static constexpr CellCoords kHalfShell[13] = {{1, 0, 0},   {-1, 1, 0}, {0, 1, 0},  {1, 1, 0},  {-1, -1, 1}, {0, -1, 1}, {1, -1, 1},
                                                  {-1, 0, 1},  {0, 0, 1},  {1, 0, 1},  {-1, 1, 1}, {0, 1, 1},   {1, 1, 1}};

    // One walk: each fixed chunk of particles (its size independent of the thread count) collects its
    // rows, then the chunks are copied into place after the prefix sum.
    void build(const std::vector<Vec3<Real>>& x, const Vec3<Real>& box, double cutoff, double skin, int threads) {
        const int64_t n = int64_t(x.size());
        const double reach = cutoff + skin;
        const Real reach2 = Real(reach * reach);
        m_grid.build(x, box, reach);
        const CellListView grid = m_grid.view();
        m_order.assign(grid.sorted, grid.sorted + n);
        m_rank.resize(size_t(n));
        for (int64_t r = 0; r < n; ++r) m_rank[size_t(m_order[size_t(r)])] = int32_t(r);
        m_rowStart.assign(size_t(n) + 1, 0);
        const int64_t chunks = (n + kReductionChunk - 1) / kReductionChunk;
        m_chunkPartners.resize(size_t(chunks));
#pragma omp parallel for schedule(dynamic) num_threads(threads) if (chunks > 1)
        for (int64_t chunk = 0; chunk < chunks; ++chunk) {
            std::vector<int32_t>& partners = m_chunkPartners[size_t(chunk)];
            partners.clear();
            const int64_t end = std::min(n, (chunk + 1) * kReductionChunk);
            for (int64_t r = chunk * kReductionChunk; r < end; ++r) {
                const size_t before = partners.size();
                forPartners(x, m_order[size_t(r)], reach2, [&](int64_t j) { partners.push_back(int32_t(j)); });
                std::sort(partners.begin() + std::ptrdiff_t(before), partners.end());
                m_rowStart[size_t(r) + 1] = int64_t(partners.size() - before);
            }
        }
        for (int64_t r = 0; r < n; ++r) m_rowStart[size_t(r) + 1] += m_rowStart[size_t(r)];
        m_partner.resize(size_t(m_rowStart[size_t(n)]));
#pragma omp parallel for schedule(static) num_threads(threads) if (chunks > 1)
        for (int64_t chunk = 0; chunk < chunks; ++chunk) {
            const std::vector<int32_t>& partners = m_chunkPartners[size_t(chunk)];
            std::copy(partners.begin(), partners.end(), m_partner.begin() + m_rowStart[size_t(chunk * kReductionChunk)]);
        }
        // Transpose by a counting sort (incoming lists by the partner's rank), filled from the owners in
        // ascending index: ascending owner per partner.
        m_inStart.assign(size_t(n) + 1, 0);
        for (int32_t j : m_partner) ++m_inStart[size_t(m_rank[size_t(j)]) + 1];
        for (int64_t r = 0; r < n; ++r) m_inStart[size_t(r) + 1] += m_inStart[size_t(r)];
        m_inSlot.resize(m_partner.size());
        m_inOwner.resize(m_partner.size());
        m_fill.assign(m_inStart.begin(), m_inStart.end() - 1);
        for (int64_t i = 0; i < n; ++i) {
            for (int64_t k = rowBegin(i); k < rowEnd(i); ++k) {
                const int64_t q = m_fill[size_t(m_rank[size_t(m_partner[size_t(k)])])]++;
                m_inSlot[size_t(q)] = k;
                m_inOwner[size_t(q)] = int32_t(i);
            }
        }
        m_gather.resize(2 * m_partner.size());
#pragma omp parallel for schedule(static) num_threads(threads) if (chunks > 1)
        for (int64_t r = 0; r < n; ++r) {
            const int64_t i = m_order[size_t(r)];
            int64_t e = gatherBegin(i);
            int64_t k = rowBegin(i), q = inBegin(i);
            while (k < rowEnd(i) || q < inEnd(i)) {
                if (q == inEnd(i) || (k < rowEnd(i) && m_partner[size_t(k)] < m_inOwner[size_t(q)])) m_gather[size_t(e++)] = 2 * k++;
                else m_gather[size_t(e++)] = 2 * m_inSlot[size_t(q++)] + 1;
            }
        }
        m_xBuilt = x;
        m_box = box;
        m_cutoff = cutoff;
        m_skin = skin;
        m_valid = true;
        ++m_builds;
    }

    CellList m_grid;
    std::vector<int64_t> m_rowStart, m_inStart, m_inSlot, m_fill, m_gather;
    std::vector<int32_t> m_partner, m_inOwner;
    std::vector<int32_t> m_order, m_rank;  // the cell list's order of the particles, and each one's place in it
    std::vector<std::vector<int32_t>> m_chunkPartners;  // build scratch, kept to reuse its memory
    std::vector<Vec3<Real>> m_xBuilt;
    Vec3<Real> m_box{0, 0, 0};
    double m_cutoff = 0, m_skin = 0;
    bool m_valid = false;
    int64_t m_builds = 0;
};

}  // namespace corebox
