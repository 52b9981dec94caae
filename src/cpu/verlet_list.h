// Verlet neighbour lists of the CPU backend (DESIGN.md sec. 2, forces with a cutoff).
//
// Design note.
// - Built on the one grid (src/core/host_cell_list.h) with cells at least r_c + skin wide, so every
//   pair within reach lies in adjacent cells. Half lists: row i holds the partners j > i closer than
//   r_c + skin at the build, by ascending index; every pair once (Newton's third law).
// - Rebuilt when some particle has moved more than skin / 2 since the last build (then no pair can
//   have come from beyond r_c + skin to within r_c), never on a schedule; also when the reach, the
//   particle count, the box or the thread count changed.
// - The pass writes each pair's force straight into both of its particles, and yet every particle sums
//   its pairs in one order, by ascending partner index, whatever the thread count and whenever the
//   list was built (a listed pair beyond the cutoff adds an exact zero). That is what lets 1 and 2
//   threads give the same bits, and a run restarted from a checkpoint, whose list is built afresh, go
//   on bit for bit. How: the particles are cut into chunks, contiguous runs of the grid's order (slabs
//   of space), one per thread, and a chunk writes only its own particles. It walks (walkChunk), by
//   ascending owner index, its own rows and the incoming pairs: those whose owner lies in another
//   chunk and whose partner lies in it. A particle k thus takes -F_ik from every owner i < k by
//   ascending i, then adds its own row by ascending partner: ascending partner index throughout. A
//   pair across two chunks is evaluated in both; slabs are thick against r_c + skin, so that is a few
//   per cent of the pairs.
// - Per-particle values of a pass live in slots, the particles in the grid's order at the build: a
//   chunk's slots are contiguous (no two threads write one cache line; with particle indices, which a
//   shuffled lattice scatters through space, they did, and two threads ran slower than one), and a
//   row's partners, spatial neighbours, lie near each other. The rows are found in the grid's order
//   (consecutive particles walk mostly the same cells) and then laid out by index.
// - Measured on 2 cores (fp64, the LJ fluid of `corebox bench md`, N = 32000, LAMMPS in the same run
//   at 7.0 ms a step): the layout before, pair values written into per-pair slots and gathered per
//   particle through a merge plan, took 19.6 ms a step (forces 13.1 ms); this one 6.5 ms (5.6 ms).
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
    // A row entry: the partner's slot, with the top bit set when the partner lies in another chunk
    // (its chunk adds the pair from its incoming list).
    static constexpr uint32_t kOtherChunk = 0x80000000u;
    static int64_t entrySlot(uint32_t entry) { return int64_t(entry & ~kOtherChunk); }
    static bool inThisChunk(uint32_t entry) { return (entry & kOtherChunk) == 0; }

    // Makes the list valid for positions x; returns true when it was rebuilt.
    bool update(const std::vector<Vec3<Real>>& x, const Vec3<Real>& box, double cutoff, double skin, int threads) {
        const int64_t n = int64_t(x.size());
        const bool sameGeometry = m_valid && n == int64_t(m_xBuilt.size()) && cutoff == m_cutoff && skin == m_skin &&
                                  box.x == m_box.x && box.y == m_box.y && box.z == m_box.z && chunksFor(n, threads) == chunkCount();
        if (sameGeometry && maxDisplacement2(x, threads) <= 0.25 * skin * skin) return false;
        build(x, box, cutoff, skin, threads);
        return true;
    }
    int64_t builds() const { return m_builds; }
    int64_t chunkCount() const { return int64_t(m_chunkBegin.size()) - 1; }

    // Slots: the particles in the grid's order at the build, where a pass keeps its per-particle values
    // (a chunk's particles are the contiguous slots chunkBegin .. chunkEnd, which no other chunk writes).
    int64_t particleAt(int64_t slot) const { return m_grid.sorted()[size_t(slot)]; }
    int64_t slotOf(int64_t particle) const { return m_slot[size_t(particle)]; }
    int64_t chunkBegin(int64_t chunk) const { return m_chunkBegin[size_t(chunk)]; }
    int64_t chunkEnd(int64_t chunk) const { return m_chunkBegin[size_t(chunk) + 1]; }

    // The chunk's pairs by ascending owner index: ownRow(slot, begin, end) for each of its particles,
    // with the row's entries (entrySlot, inThisChunk) by ascending partner index, and incoming(ownerSlot,
    // partnerSlot) for each pair whose owner lies in another chunk and whose partner in this one. Add
    // a pair to the partner only when inThisChunk.
    template <class OwnRow, class Incoming>
    void walkChunk(int64_t chunk, OwnRow&& ownRow, Incoming&& incoming) const {
        int64_t p = m_chunkBegin[size_t(chunk)], q = m_inBegin[size_t(chunk)];
        const int64_t pEnd = m_chunkBegin[size_t(chunk) + 1], qEnd = m_inBegin[size_t(chunk) + 1];
        const uint32_t* row = m_partner.data();
        while (p < pEnd || q < qEnd) {
            if (q == qEnd || (p < pEnd && m_member[size_t(p)] < m_inOwner[size_t(q)])) {
                ownRow(int64_t(m_slot[size_t(m_member[size_t(p)])]), row + m_rowStart[size_t(p)], row + m_rowStart[size_t(p) + 1]);
                ++p;
            } else {
                incoming(int64_t(m_inOwnerSlot[size_t(q)]), int64_t(m_inPartnerSlot[size_t(q)]));
                ++q;
            }
        }
    }

    // fn(j) for every listed partner j of i, own and incoming, by ascending j: the pairs within reach at
    // the build, found again from the build's grid (a few hundred candidates; for the particles a
    // collision stage resolves, not for whole passes). `scratch` holds the partners meanwhile.
    template <class Fn>
    void forEachPartner(int64_t i, std::vector<int32_t>& scratch, Fn&& fn) const {
        scratch.clear();
        const Vec3<Real> xi = m_xBuilt[size_t(i)];
        const CellListView grid = m_grid.view();
        forEachNeighbourCell(grid.geometry, cellCoords(grid.geometry, xi), [&](int cell) {
            for (int32_t k = grid.cellStart[cell]; k < grid.cellStart[cell + 1]; ++k) {
                if (grid.sorted[k] != i && norm2(xi - m_xCell[size_t(k)]) < m_reach2) scratch.push_back(grid.sorted[k]);
            }
        });
        std::sort(scratch.begin(), scratch.end());
        for (int32_t j : scratch) fn(int64_t(j));
    }

private:
    // One chunk below a few thousand particles: waking a thread team costs more than the pairs.
    static int64_t chunksFor(int64_t n, int threads) { return n >= 2 * kReductionChunk ? std::max(1, threads) : 1; }

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

    // Each chunk, in parallel: its particles by ascending index, their rows (the 27 cells around each,
    // read from the slots' copy of the positions so that a cell's candidates stream), and the pairs it
    // hands to other chunks, by ascending owner. Then the rows are copied into place and each chunk's
    // incoming pairs are gathered from the others, by ascending owner.
    void build(const std::vector<Vec3<Real>>& x, const Vec3<Real>& box, double cutoff, double skin, int threads) {
        const int64_t n = int64_t(x.size());
        const double reach = cutoff + skin;
        m_reach2 = Real(reach * reach);
        m_grid.build(x, box, reach);
        const CellListView grid = m_grid.view();
        const int64_t chunks = chunksFor(n, threads);
        m_xCell.resize(size_t(n));
        m_slot.resize(size_t(n));
        m_member.resize(size_t(n));
        m_chunkBegin.resize(size_t(chunks) + 1);
        for (int64_t c = 0; c <= chunks; ++c) m_chunkBegin[size_t(c)] = n * c / chunks;
        m_rowStart.assign(size_t(n) + 1, 0);
        m_chunkRows.resize(size_t(chunks));
        m_chunkScratch.resize(size_t(chunks));
        m_handed.resize(size_t(chunks * chunks));
#pragma omp parallel num_threads(threads) if (chunks > 1)
        {
#pragma omp for schedule(static)
            for (int64_t k = 0; k < n; ++k) {
                const int32_t i = grid.sorted[k];
                m_xCell[size_t(k)] = x[size_t(i)];
                m_slot[size_t(i)] = int32_t(k);
            }
#pragma omp for schedule(static, 1)
            for (int64_t c = 0; c < chunks; ++c) buildChunk(c, x, grid);
        }
        for (int64_t p = 0; p < n; ++p) m_rowStart[size_t(p) + 1] += m_rowStart[size_t(p)];
        m_partner.resize(size_t(m_rowStart[size_t(n)]));
        m_inBegin.assign(size_t(chunks) + 1, 0);
        for (int64_t c = 0; c < chunks; ++c) {
            int64_t incoming = 0;
            for (int64_t s = 0; s < chunks; ++s) incoming += int64_t(m_handed[size_t(s * chunks + c)].size() / 2);
            m_inBegin[size_t(c) + 1] = m_inBegin[size_t(c)] + incoming;
        }
        m_inOwner.resize(size_t(m_inBegin[size_t(chunks)]));
        m_inOwnerSlot.resize(m_inOwner.size());
        m_inPartnerSlot.resize(m_inOwner.size());
#pragma omp parallel for schedule(static, 1) num_threads(threads) if (chunks > 1)
        for (int64_t c = 0; c < chunks; ++c) {
            const std::vector<uint32_t>& rows = m_chunkRows[size_t(c)];
            std::copy(rows.begin(), rows.end(), m_partner.begin() + m_rowStart[size_t(m_chunkBegin[size_t(c)])]);
            gatherIncoming(c);
        }
        m_xBuilt = x;
        m_box = box;
        m_cutoff = cutoff;
        m_skin = skin;
        m_valid = true;
        ++m_builds;
    }

    // The rows are found in the grid's order (consecutive particles walk mostly the same cells, which
    // stay in cache; walking them by index left the LJ fluid's step at N = 32000 10-25% slower) into
    // scratch, then laid out by index.
    void buildChunk(int64_t c, const std::vector<Vec3<Real>>& x, const CellListView& grid) {
        const int64_t chunks = chunkCount();
        const int64_t begin = m_chunkBegin[size_t(c)], end = m_chunkBegin[size_t(c) + 1];
        std::copy(grid.sorted + begin, grid.sorted + end, m_member.begin() + begin);
        std::sort(m_member.begin() + begin, m_member.begin() + end);
        ChunkScratch& scratch = m_chunkScratch[size_t(c)];
        scratch.start.assign(size_t(end - begin) + 1, 0);
        size_t count = 0;  // entries of found in use (its size is room)
        for (int64_t k = begin; k < end; ++k) {
            const int32_t i = grid.sorted[k];
            const Vec3<Real> xi = x[size_t(i)];
            // Every candidate is written and kept only when it qualifies (no branch on the test, which
            // follows no pattern: a third of the later candidates are within reach).
            const size_t rowBegin = count;
            forEachNeighbourCell(grid.geometry, cellCoords(grid.geometry, xi), [&](int cell) {
                const int32_t first = grid.cellStart[cell], last = grid.cellStart[cell + 1];
                if (scratch.found.size() < count + size_t(last - first)) scratch.found.resize(2 * (count + size_t(last - first)));
                uint64_t* out = scratch.found.data();
                for (int32_t q = first; q < last; ++q) {
                    const int32_t j = grid.sorted[q];
                    out[count] = (uint64_t(uint32_t(j)) << 32) | uint32_t(q);
                    count += size_t((j > i) & (norm2(xi - m_xCell[size_t(q)]) < m_reach2));
                }
            });
            sortRow(scratch.found.data() + rowBegin, scratch.found.data() + count);  // by partner index
            scratch.start[size_t(k - begin) + 1] = int64_t(count);
        }
        std::vector<uint32_t>& rows = m_chunkRows[size_t(c)];
        rows.clear();
        for (int64_t s = 0; s < chunks; ++s) m_handed[size_t(c * chunks + s)].clear();
        for (int64_t p = begin; p < end; ++p) {
            const int32_t i = m_member[size_t(p)];
            const int64_t k = m_slot[size_t(i)] - begin;
            for (int64_t e = scratch.start[size_t(k)]; e < scratch.start[size_t(k) + 1]; ++e) {
                const uint32_t slot = uint32_t(scratch.found[size_t(e)]);
                if (slot >= uint32_t(begin) && slot < uint32_t(end)) {
                    rows.push_back(slot);
                    continue;
                }
                rows.push_back(slot | kOtherChunk);
                const int64_t other = int64_t(std::upper_bound(m_chunkBegin.begin() + 1, m_chunkBegin.end(), int64_t(slot)) - m_chunkBegin.begin()) - 1;
                std::vector<int32_t>& handed = m_handed[size_t(c * chunks + other)];
                handed.push_back(i);
                handed.push_back(int32_t(slot));
            }
            m_rowStart[size_t(p) + 1] = scratch.start[size_t(k) + 1] - scratch.start[size_t(k)];
        }
    }

    // A row's entries by ascending partner (the high half): insertion, for the few dozen of a row,
    // which come as runs already (a cell's particles are by ascending index); std::sort took 17% of the
    // build.
    static void sortRow(uint64_t* first, uint64_t* last) {
        for (uint64_t* p = first + (first < last ? 1 : 0); p < last; ++p) {
            const uint64_t value = *p;
            uint64_t* q = p;
            for (; q > first && q[-1] > value; --q) *q = q[-1];
            *q = value;
        }
    }

    // Chunk c's incoming pairs: each other chunk's handed pairs are by ascending owner already; merged.
    void gatherIncoming(int64_t c) {
        const int64_t chunks = chunkCount();
        int64_t out = m_inBegin[size_t(c)];
        std::vector<Incoming> scratch;
        for (int64_t s = 0; s < chunks; ++s) {
            const std::vector<int32_t>& handed = m_handed[size_t(s * chunks + c)];
            for (size_t e = 0; e < handed.size(); e += 2, ++out) {
                m_inOwner[size_t(out)] = handed[e];
                m_inOwnerSlot[size_t(out)] = m_slot[size_t(handed[e])];
                m_inPartnerSlot[size_t(out)] = handed[e + 1];
            }
            if (s > 0) mergeByOwner(m_inBegin[size_t(c)], out - int64_t(handed.size() / 2), out, scratch);
        }
    }

    // The runs [first, middle) and [middle, last) are each by ascending owner: one run after the merge
    // (the owners of two chunks differ, so the order within an owner's pairs is kept as it was).
    struct Incoming {
        int32_t owner, ownerSlot, partnerSlot;
    };
    void mergeByOwner(int64_t first, int64_t middle, int64_t last, std::vector<Incoming>& scratch) {
        if (first == middle || middle == last) return;
        scratch.resize(size_t(last - first));
        int64_t a = first, b = middle, out = 0;
        while (a < middle || b < last) {
            const bool takeA = b == last || (a < middle && m_inOwner[size_t(a)] < m_inOwner[size_t(b)]);
            const int64_t from = takeA ? a++ : b++;
            scratch[size_t(out++)] = Incoming{m_inOwner[size_t(from)], m_inOwnerSlot[size_t(from)], m_inPartnerSlot[size_t(from)]};
        }
        for (int64_t e = 0; e < out; ++e) {
            m_inOwner[size_t(first + e)] = scratch[size_t(e)].owner;
            m_inOwnerSlot[size_t(first + e)] = scratch[size_t(e)].ownerSlot;
            m_inPartnerSlot[size_t(first + e)] = scratch[size_t(e)].partnerSlot;
        }
    }

    CellList m_grid;                    // at the build's positions
    std::vector<Vec3<Real>> m_xCell;    // the build's positions by slot
    std::vector<int32_t> m_slot;        // the slot of each particle
    std::vector<int64_t> m_chunkBegin;  // chunks + 1 offsets into the slots and m_member
    std::vector<int32_t> m_member;      // each chunk's particles, by ascending index
    std::vector<int64_t> m_rowStart;    // by place in m_member: the row's entries in m_partner
    std::vector<uint32_t> m_partner;
    std::vector<int64_t> m_inBegin;     // chunks + 1 offsets into the incoming pairs
    std::vector<int32_t> m_inOwner, m_inOwnerSlot, m_inPartnerSlot;  // the incoming pairs, by ascending owner
    std::vector<std::vector<uint32_t>> m_chunkRows;  // build scratch, kept to reuse its memory
    struct ChunkScratch {
        std::vector<uint64_t> found;  // (partner index, partner slot) of the rows, in the grid's order
        std::vector<int64_t> start;   // by slot from the chunk's first: each row's first entry in found
    };
    std::vector<ChunkScratch> m_chunkScratch;
    std::vector<std::vector<int32_t>> m_handed;      // build scratch: (owner, partner slot) from chunk s to chunk c at s * chunks + c
    std::vector<Vec3<Real>> m_xBuilt;
    Vec3<Real> m_box{0, 0, 0};
    Real m_reach2 = 0;
    double m_cutoff = 0, m_skin = 0;
    bool m_valid = false;
    int64_t m_builds = 0;
};

}  // namespace corebox
