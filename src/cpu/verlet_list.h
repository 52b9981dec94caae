// Verlet neighbour lists of the CPU backend (DESIGN.md sec. 2, forces with a cutoff).
//
// Design note.
// - Built on the one grid (src/core/host_cell_list.h) with cells at least r_c + skin wide, so every
//   pair within reach lies in adjacent cells; each particle's 27-cell walk keeps the partners j > i
//   closer than r_c + skin: a half list, every pair once (Newton's third law).
// - Rebuilt when some particle has moved more than skin / 2 since the last build (then no pair can
//   have come from beyond r_c + skin to within r_c), never on a schedule; also when the reach, the
//   particle count or the box changed.
// - Layout: compressed rows. Row i holds its partners in the walk's order (ascending cell key, then
//   ascending index), slots rowStart[i] .. rowStart[i + 1]. The transposed index lists, for every j,
//   the slots of the pairs whose partner it is, by ascending owner: the force pass evaluates each
//   pair once into its slot and then every particle gathers its own slots and its incoming ones in
//   this fixed order, so the sums do not depend on the thread count and no two threads write one
//   particle.
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
    int64_t rowBegin(int64_t i) const { return m_rowStart[size_t(i)]; }
    int64_t rowEnd(int64_t i) const { return m_rowStart[size_t(i) + 1]; }
    int32_t partner(int64_t slot) const { return m_partner[size_t(slot)]; }
    // Pairs whose partner is j: entries inBegin(j) .. inEnd(j) of inSlot / inOwner.
    int64_t inBegin(int64_t j) const { return m_inStart[size_t(j)]; }
    int64_t inEnd(int64_t j) const { return m_inStart[size_t(j) + 1]; }
    int64_t inSlot(int64_t k) const { return m_inSlot[size_t(k)]; }
    int32_t inOwner(int64_t k) const { return m_inOwner[size_t(k)]; }

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

    template <class Fn>
    void forPartners(const std::vector<Vec3<Real>>& x, int64_t i, Real reach2, Fn&& fn) const {
        const Vec3<Real> xi = x[size_t(i)];
        m_grid.forNeighbours(xi, [&](int64_t j) {
            if (j > i && norm2(xi - x[size_t(j)]) < reach2) fn(j);
        });
    }

    void build(const std::vector<Vec3<Real>>& x, const Vec3<Real>& box, double cutoff, double skin, int threads) {
        const int64_t n = int64_t(x.size());
        const double reach = cutoff + skin;
        const Real reach2 = Real(reach * reach);
        m_grid.build(x, box, reach);
        m_rowStart.assign(size_t(n) + 1, 0);
        parallelForDynamic(threads, n, [&](int64_t i) {
            int64_t count = 0;
            forPartners(x, i, reach2, [&](int64_t) { ++count; });
            m_rowStart[size_t(i) + 1] = count;
        });
        for (int64_t i = 0; i < n; ++i) m_rowStart[size_t(i) + 1] += m_rowStart[size_t(i)];
        m_partner.resize(size_t(m_rowStart[size_t(n)]));
        parallelForDynamic(threads, n, [&](int64_t i) {
            int64_t slot = m_rowStart[size_t(i)];
            forPartners(x, i, reach2, [&](int64_t j) { m_partner[size_t(slot++)] = int32_t(j); });
        });
        // Transpose by a counting sort over the slots in ascending order: ascending owner per partner.
        m_inStart.assign(size_t(n) + 1, 0);
        for (int32_t j : m_partner) ++m_inStart[size_t(j) + 1];
        for (int64_t j = 0; j < n; ++j) m_inStart[size_t(j) + 1] += m_inStart[size_t(j)];
        m_inSlot.resize(m_partner.size());
        m_inOwner.resize(m_partner.size());
        m_fill.assign(m_inStart.begin(), m_inStart.end() - 1);
        for (int64_t i = 0; i < n; ++i) {
            for (int64_t k = m_rowStart[size_t(i)]; k < m_rowStart[size_t(i) + 1]; ++k) {
                const int64_t q = m_fill[size_t(m_partner[size_t(k)])]++;
                m_inSlot[size_t(q)] = k;
                m_inOwner[size_t(q)] = int32_t(i);
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
    std::vector<int64_t> m_rowStart, m_inStart, m_inSlot, m_fill;
    std::vector<int32_t> m_partner, m_inOwner;
    std::vector<Vec3<Real>> m_xBuilt;
    Vec3<Real> m_box{0, 0, 0};
    double m_cutoff = 0, m_skin = 0;
    bool m_valid = false;
    int64_t m_builds = 0;
};

}  // namespace corebox
