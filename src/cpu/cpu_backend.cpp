#include "cpu_backend.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstring>

#include "collision_resolution.h"
#include "cpu_parallel.h"
#include "energy_terms.h"
#include "errors.h"
#include "host_cell_list.h"
#include "host_info.h"
#include "list_forces.h"
#include "pair_table.h"
#include "rk_stage.h"
#include "state_conversions.h"
#include "verlet_list.h"

namespace corebox {
namespace {

using Clock = std::chrono::steady_clock;
double secondsBetween(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

template <class Real>
class CpuBackendImpl final : public Backend {
public:
    explicit CpuBackendImpl(const CpuBackendOptions& options)
        : m_threads(options.threads > 0 ? options.threads : omp_get_max_threads()),
          m_moversFirst(options.moversFirst) {}

    // ---- identity ----
    std::string name() const override { return "cpu"; }
    std::string deviceName() const override { return cpuModelName() + " (" + std::to_string(m_threads) + " threads)"; }
    Precision precision() const override { return std::is_same<Real, float>::value ? Precision::Fp32 : Precision::Fp64; }

    // ---- model and state ----
    void setModel(const DeviceModel& model) override {
        m_model = model;
        m_pairs = convertPairTable<Real>(model.pairs);
        const size_t s = model.mass.size();
        m_mass.resize(s);
        m_invMass.resize(s);
        m_radius.resize(s);
        for (size_t k = 0; k < s; ++k) {
            m_mass[k] = Real(model.mass[k]);
            m_invMass[k] = Real(1.0 / model.mass[k]);
            m_radius[k] = Real(model.radius[k]);
        }
        fillPairMassTable();
        m_gravity = vec3Cast<Real>(model.gravity);
        m_field.clear();
        for (const Vec3<double>& g : model.acceleration) m_field.push_back(vec3Cast<Real>(g));
        m_boxLength = vec3Cast<Real>(model.box);
        m_useList = model.anyPairForce && model.forces == ForceModel::NeighbourList && model.cutoff > 0;
        m_screenReachGap = -1;  // the screen's reaches follow the radii and the box
        forgetForces();
        m_contacts.clear();  // no warm start across a change of masses or radii
        m_candidatesValid = false;
        chooseContactCellSplit();
    }

    void setTableau(const ButcherTableau& tableau) override { m_tableau = tableau; }

    void setState(const ParticleState& state) override {
        const size_t n = state.size();
        m_x.resize(n);
        m_v.resize(n);
        m_species = state.species;
        for (size_t i = 0; i < n; ++i) {
            m_x[i] = vec3Cast<Real>(state.position[i]);
            m_v[i] = vec3Cast<Real>(state.velocity[i]);
        }
        m_acceleration.assign(n, Vec3<Real>{0, 0, 0});
        forgetForces();
        m_contacts.clear();  // indices may now mean other particles: no warm start
        m_candidatesValid = false;
        chooseContactCellSplit();
    }

    ParticleState state() const override { return toHost(m_x, m_v); }

    void readPositions(const PositionSink& sink) const override {
        handPositions(m_x.data(), m_x.size(), sink, m_threads);
    }

    void keepSnapshot() override {
        m_snapshotX = m_x;
        m_snapshotV = m_v;
    }

    ParticleState snapshot() const override { return toHost(m_snapshotX, m_snapshotV); }

    // ---- integration ----
    void computeAccelerations() override {
        // The end-of-step pass with lists also screens the collision stage to come (screenStage), with
        // the resting gap the last stage asked for.
        const bool screen = m_useList && m_screenGap >= 0 && screenReach(2 * m_model.maxRadius(), m_screenGap) < m_model.cutoff;
        accelerations(m_x, m_acceleration.data(), nullptr, screen);
        ++m_counters.fullPasses;
        m_accelerationMatchesX = true;
        m_accelerationIncremental = false;
        m_screenPending = screen;
    }

    std::vector<Vec3<double>> cachedAccelerations() const override {
        if (!m_accelerationIncremental) return {};
        std::vector<Vec3<double>> a(m_acceleration.size());
        for (size_t i = 0; i < a.size(); ++i) a[i] = vec3Cast<double>(m_acceleration[i]);
        return a;
    }

    // The values were this precision's before the round trip through double: restored exactly.
    void restoreAccelerations(const std::vector<Vec3<double>>& a) override {
        m_acceleration.resize(a.size());
        for (size_t i = 0; i < a.size(); ++i) m_acceleration[i] = vec3Cast<Real>(a[i]);
        m_accelerationMatchesX = true;
        m_accelerationIncremental = true;
        m_screenPending = false;
    }

    void kick(double h) override {
        const Real half = Real(h);
        parallelFor(m_threads, size(), [&](int64_t i) { verletKick(m_v[size_t(i)], m_acceleration[size_t(i)], half); });
    }

    void drift(double dtStep) override {
        const Real dt = Real(dtStep);
        parallelFor(m_threads, size(), [&](int64_t i) { verletDrift(m_x[size_t(i)], m_v[size_t(i)], dt); });
        forgetForces();
    }

    void rkStage(int stage, double dtStep) override {
        const Real dt = Real(dtStep);
        const size_t n = m_x.size();
        m_kx.resize(size_t(m_tableau.stages) * n);
        m_kv.resize(size_t(m_tableau.stages) * n);
        m_xStage.resize(n);
        m_vStage.resize(n);
        parallelFor(m_threads, int64_t(n), [&](int64_t i) {
            m_xStage[size_t(i)] = rkCombine(m_tableau.a[stage], stage, dt, m_x[size_t(i)], m_kx.data(), n, size_t(i));
            m_vStage[size_t(i)] = rkCombine(m_tableau.a[stage], stage, dt, m_v[size_t(i)], m_kv.data(), n, size_t(i));
            m_kx[size_t(stage) * n + size_t(i)] = m_vStage[size_t(i)];
        });
    }

    void stageForces(int stage) override {
        accelerations(m_xStage, m_kv.data() + size_t(stage) * m_x.size(), nullptr);
        ++m_counters.fullPasses;
    }

    void rkSolution(int stages, double dtStep) override {
        const Real dt = Real(dtStep);
        const size_t n = m_x.size();
        parallelFor(m_threads, int64_t(n), [&](int64_t i) {
            m_xStage[size_t(i)] = rkCombine(m_tableau.b, stages, dt, m_x[size_t(i)], m_kx.data(), n, size_t(i));
            m_vStage[size_t(i)] = rkCombine(m_tableau.b, stages, dt, m_v[size_t(i)], m_kv.data(), n, size_t(i));
        });
    }

    double rkErrorNorm(double dt, double tolerance) override {
        const size_t n = m_x.size();
        const double errorSum = deterministicSum<double>(m_threads, int64_t(n), [&](int64_t i) {
            const Vec3<Real> ex = rkCombine(m_tableau.bError, m_tableau.stages, Real(dt), Vec3<Real>{0, 0, 0}, m_kx.data(), n, size_t(i));
            const Vec3<Real> ev = rkCombine(m_tableau.bError, m_tableau.stages, Real(dt), Vec3<Real>{0, 0, 0}, m_kv.data(), n, size_t(i));
            double e = 0;
            for (int a = 0; a < 3; ++a) {
                e += scaledErrorSquared(ex[a], m_x[size_t(i)][a], m_xStage[size_t(i)][a], tolerance);
                e += scaledErrorSquared(ev[a], m_v[size_t(i)][a], m_vStage[size_t(i)][a], tolerance);
            }
            return e;
        });
        return std::sqrt(errorSum / double(6 * std::max<size_t>(n, 1)));
    }

    void acceptStage() override {
        std::swap(m_x, m_xStage);
        std::swap(m_v, m_vStage);
        forgetForces();
    }

    // The collision stage changed the positions of a few particles (every change is against the copy
    // taken at beginCollisions). Lists: every pair of a moved particle exchanges its old force for the
    // new one in both particles (O(M x partners)). All pairs: each moved particle sums again over
    // everyone, and everyone else exchanges the old pair force of each moved partner for the new one
    // (O(N M)). Either way A may differ from a force pass in the last bits (checkpoints carry it).
    bool refreshAccelerations() override {
        if (!m_refreshable || m_xBeforeCollisions.size() != m_x.size()) return false;
        const int64_t n = size();
        m_moved.clear();
        for (int64_t i = 0; i < n; ++i) {
            const Vec3<Real>& a = m_x[size_t(i)];
            const Vec3<Real>& b = m_xBeforeCollisions[size_t(i)];
            if (a.x != b.x || a.y != b.y || a.z != b.z) m_moved.push_back(i);
        }
        ++m_counters.refreshes;
        m_accelerationMatchesX = true;
        if (m_moved.empty() || !m_model.anyPairForce) return true;  // gravity alone does not depend on x
        if (m_useList) return refreshFromList();
        if (4 * int64_t(m_moved.size()) > n) {
            computeAccelerations();
            return true;
        }
        m_isMoved.assign(size_t(n), 0);
        for (int64_t i : m_moved) m_isMoved[size_t(i)] = 1;
        parallelFor(m_threads, n, [&](int64_t i) {
            if (m_isMoved[size_t(i)]) {
                m_acceleration[size_t(i)] = accelerationOf(i, m_x, nullptr);
                return;
            }
            const Vec3<Real> xi = m_x[size_t(i)];
            const PairCoefficients<Real>* row = &m_pairs[size_t(m_species[size_t(i)]) * m_mass.size()];
            Vec3<Real> change{0, 0, 0};
            for (int64_t j : m_moved) {
                const PairCoefficients<Real>& p = row[m_species[size_t(j)]];
                const Vec3<Real> now = xi - m_x[size_t(j)], was = xi - m_xBeforeCollisions[size_t(j)];
                change += pairForceOverR(p, norm2(now), static_cast<Real*>(nullptr)) * now;
                change -= pairForceOverR(p, norm2(was), static_cast<Real*>(nullptr)) * was;
            }
            m_acceleration[size_t(i)] += m_invMass[size_t(m_species[size_t(i)])] * change;
        });
        m_accelerationIncremental = true;
        m_counters.refreshedParticles += n;
        return true;
    }

    bool supportsNeighbourLists() const override { return true; }

    ForceCounters forceCounters() const override {
        ForceCounters c = m_counters;
        c.listBuilds = m_list.builds();
        return c;
    }

    // ---- collision stage, 0: the screen ----
    // From the end-of-step list pass (list_forces.h), with kernels/collision_screen.h's bounds: no pair
    // or wall within reach, the stage is skipped (left as an empty stage leaves it: no contacts, no log);
    // walls only, they are resolved at once (resolveWallImpacts) instead of by rounds of searches.
    StageScreen screenStage(const ImpactWindow<double>& /*window*/, double contactGap) override {
        const bool screened = m_screenPending && m_accelerationMatchesX && contactGap == m_screenGap;
        m_screenGap = contactGap;
        m_screenPending = false;
        m_pairsClear = false;
        if (!screened || !m_screen.finite) return StageScreen::Full;  // not finite: the stage and the health check say where
        const double smallestRadius = *std::min_element(m_model.radius.begin(), m_model.radius.end());
        const double clearance = pairClearanceBound(m_screen.nearest, screenReach(2 * smallestRadius, contactGap),
                                                    screenReach(2 * m_model.maxRadius(), contactGap), m_model.cutoff);
        if (!(clearance > 0)) return StageScreen::Full;
        if (m_screen.deepestWallDepth > 0) {
            m_pairsClear = wallsCannotBringPairsTogether(clearance, m_screen.deepestWallDepth);
            return m_pairsClear ? StageScreen::WallsOnly : StageScreen::Full;
        }
        m_contacts.clear();
        m_log.clear();
        return StageScreen::Quiet;
    }

    // After a WallsOnly screen: each particle's wall impacts in turn, in parallel. Particles that cannot
    // meet each other have independent sequences, and the rounds would take each particle's walls in
    // this order with the same end-of-step acceleration (A matched X when the stage began): the rounds'
    // result, without their searches.
    int resolveWallImpacts() override {
        if (!m_wallsAtOnce) return -1;
        const int64_t n = size();
        int most = 0;  // the most impacts of one particle
        int64_t walls = 0;
#pragma omp parallel for schedule(static) num_threads(m_threads) reduction(max : most) reduction(+ : walls) if (n >= kParallelThreshold)
        for (int64_t i = 0; i < n; ++i) {
            const Real radius = m_radius[size_t(m_species[size_t(i)])];
            int impacts = 0;
            // At most one impact per wall plane: a rebound puts the centre inside on that axis.
            for (; impacts < 2 * 3; ++impacts) {
                CollisionEvent e = noEvent();
                considerWalls(m_x[size_t(i)], m_v[size_t(i)], radius, m_boxLength, m_window, e);
                if (!isValid(e)) break;
                walls += resolveWallOf(i, e, m_acceleration[size_t(i)]) == kWallCollision ? 1 : 0;
            }
            most = std::max(most, impacts);
            // Pairs cannot be within the contact gap (the screen); a wall may be.
            m_near[size_t(i)] = nearAWall(m_x[size_t(i)], radius) ? 1 : 0;
        }
        m_tally.wallCollisions += walls;
        m_nearValid = true;
        return most + 1;
    }

    // ---- collision stage, 1: impact rounds ----
    void beginCollisions(const ImpactWindow<double>& window) override {
        const size_t n = m_x.size();
        m_window = ImpactWindow<Real>{Real(window.maxRewind), Real(window.restingSpeed)};
        m_events.assign(n, noEvent());
        // The first round's active particles: the movers (startsActive), the same events as every particle.
        m_active.resize(n);
        parallelFor(m_threads, int64_t(n), [&](int64_t i) {
            m_active[size_t(i)] = !m_moversFirst || startsActive(m_v[size_t(i)], m_window.restingSpeed) ? 1 : 0;
        });
        clearImpactRows(n);
        m_contactAcceleration.resize(n);
        m_hasContactAcceleration.assign(n, 0);
        m_kind.resize(n);
        m_tally = CollisionTally{};
        m_near.assign(n, 1);
        m_nearValid = false;
        m_nearGap = Real(window.restingSpeed * window.maxRewind);  // >= the resting gap listContacts uses (maxRewind > dt)
        m_round = 0;
        m_candidatesValid = m_candidatesValid && candidatesStillHold();  // the integration moved everyone
        m_refreshable = m_accelerationMatchesX;
        m_buildsAtStage = m_list.builds();
        m_wallsAtOnce = m_pairsClear && m_refreshable && !m_logContacts;
        m_pairsClear = false;
        if (m_refreshable) m_xBeforeCollisions = m_x;
        m_accelerationMatchesX = false;  // until refreshAccelerations or a full pass
        m_log.clear();
        m_logRound = 0;
        m_stepDt = window.maxRewind / 1.1;  // collision_rounds.cpp: the window is 1.1 dt
        if (m_logContacts) m_detail.resize(n);
        keepWarmStart(false);
        m_firstListing = true;
    }

    // The last relaxation's contacts and impulses, by particle (a counting sort of m_contacts by i),
    // for the next listing to start from (contact_relaxation.h): the first listing of the next step
    // (every impulse), or a later listing of this step (`carry`: the stopping contacts' impulses; a
    // bounce is an impact, not a support to take back).
    void keepWarmStart(bool carry) {
        const size_t n = m_x.size();
        auto kept = [&](const Contact& c) { return c.lambda > Real(0) && size_t(c.i) < n && !(carry && c.target > Real(0)); };
        m_warmStart.assign(n + 1, 0);
        for (const Contact& c : m_contacts) {
            if (kept(c)) ++m_warmStart[size_t(c.i) + 1];
        }
        for (size_t i = 0; i < n; ++i) m_warmStart[i + 1] += m_warmStart[i];
        m_warmPartner.resize(size_t(m_warmStart[n]));
        m_warmLambda.resize(size_t(m_warmStart[n]));
        std::vector<int64_t> slot(m_warmStart.begin(), m_warmStart.end() - 1);
        for (const Contact& c : m_contacts) {
            if (!kept(c)) continue;
            const size_t k = size_t(slot[size_t(c.i)]++);
            m_warmPartner[k] = c.partner;
            m_warmLambda[k] = c.lambda;
        }
        m_contacts.clear();
    }

    // Particle i's impulse on `partner` at the end of the last step, or 0.
    Real warmLambdaOf(int64_t i, int64_t partner) const {
        if (m_warmStart.size() != m_x.size() + 1) return Real(0);
        for (int64_t k = m_warmStart[size_t(i)]; k < m_warmStart[size_t(i) + 1]; ++k) {
            if (m_warmPartner[size_t(k)] == partner) return m_warmLambda[size_t(k)];
        }
        return Real(0);
    }

    bool relaxesGaussSeidel() const override { return true; }

    // No colours: the CPU sweeps its contacts bottom-up, in an order each listing makes afresh.
    ContactCarryOver contactWarmStart() const override {
        ContactCarryOver kept;
        for (const Contact& c : m_contacts) {
            if (c.lambda > Real(0)) kept.impulses.push_back(ContactWarmStart{c.i, c.partner, double(c.lambda)});
        }
        return kept;
    }

    // The values were this precision's before the round trip through double: restored exactly.
    void restoreContactWarmStart(const ContactCarryOver& carried) override {
        m_contacts.clear();
        for (const ContactWarmStart& w : carried.impulses) {
            if (isUsableWarmStart(w, size())) m_contacts.push_back(Contact{w.i, w.partner, 0.0, Real(w.lambda), Real(0)});
        }
    }

    int64_t findEvents(EventScope scope) override {
        const int64_t n = size();
        if (scope == EventScope::All) std::fill(m_active.begin(), m_active.end(), 1);
        // A step that needs a third round is a dense one (a pile, a cluster): from then on the rounds
        // read per-particle candidate lists instead of walking the cells (buildCandidates).
        if (++m_round >= 3 || m_candidatesValid) return findEventsAmongCandidates();
        // Cells also wide enough for the pairs within the resting gap bound (earliestEvent's `near`).
        buildContactGrid(double(m_nearGap));
        // Few particles are active after the first round, and in a settled pile in the first (startsActive).
        // An inactive particle had no event in the previous round and has not changed since (or is too slow
        // for an impact with another such), so it can only have one with an active particle in its walk (cell_list.h:
        // walks are symmetric): only the active particles and their grid neighbours look (the same events as every
        // particle looking, without walking the whole fluid again).
        const int64_t active = int64_t(std::count(m_active.begin(), m_active.end(), char(1)));
        if (4 * active >= n) {
            // In the grid's order: consecutive particles walk overlapping cells (cache reuse).
            const std::vector<int32_t>& order = m_grid.sorted();
            parallelForDynamic(m_threads, n, [&](int64_t k) {
                const int64_t i = order[size_t(k)];
                m_events[size_t(i)] = earliestEvent(i, m_near[size_t(i)]);
            });
        } else {
            m_lookers.assign(size_t(n), 0);
            for (int64_t i = 0; i < n; ++i) {
                if (!m_active[size_t(i)]) continue;
                m_lookers[size_t(i)] = 1;
                m_grid.forNeighbours(m_x[size_t(i)], radiusOf(i), [&](int64_t j) { m_lookers[size_t(j)] = 1; });
            }
            parallelForDynamic(m_threads, n, [&](int64_t i) {
                m_events[size_t(i)] = m_lookers[size_t(i)] ? earliestEvent(i, m_near[size_t(i)]) : noEvent();
            });
        }
        m_nearValid = true;
        return int64_t(std::count_if(m_events.begin(), m_events.end(), [](const CollisionEvent& e) { return isValid(e); }));
    }

    // The rounds of a dense step (findEvents): every particle's candidates are the particles within
    // the largest contact distance plus the near gap plus a margin, listed once; a round reads them,
    // and the list is made again when a resolution has moved some particle by more than half the
    // margin since. The same events as the grid walk: every pair that can overlap or come within the
    // near gap is a candidate, and isBetter orders events whatever the order they are visited in.
    int64_t findEventsAmongCandidates() {
        const int64_t n = size();
        if (!m_candidatesValid) buildCandidates();
        const int64_t active = int64_t(std::count(m_active.begin(), m_active.end(), char(1)));
        if (4 * active >= n) {
            parallelForDynamic(m_threads, n, [&](int64_t k) {
                const int64_t i = m_candidateOrder[size_t(k)];
                m_events[size_t(i)] = earliestEventAmongCandidates(i, m_near[size_t(i)]);
            });
        } else {
            m_lookers.assign(size_t(n), 0);
            for (int64_t i = 0; i < n; ++i) {
                if (!m_active[size_t(i)]) continue;
                m_lookers[size_t(i)] = 1;
                for (int64_t c = m_candidateStart[size_t(i)]; c < m_candidateStart[size_t(i) + 1]; ++c) m_lookers[size_t(m_candidates[size_t(c)])] = 1;
            }
            parallelForDynamic(m_threads, n, [&](int64_t i) {
                m_events[size_t(i)] = m_lookers[size_t(i)] ? earliestEventAmongCandidates(i, m_near[size_t(i)]) : noEvent();
            });
        }
        m_nearValid = true;
        return int64_t(std::count_if(m_events.begin(), m_events.end(), [](const CollisionEvent& e) { return isValid(e); }));
    }

    void buildCandidates() {
        const int64_t n = size();
        const double margin = kCandidateMargin * 2.0 * m_model.maxRadius();
        buildContactGrid(double(m_nearGap) + margin);
        m_candidateOrder = m_grid.sorted();
        const Real gap = m_nearGap + Real(margin);
        auto within = [&](int64_t i, int64_t j) {
            const Real reach = m_radius[size_t(m_species[size_t(i)])] + m_radius[size_t(m_species[size_t(j)])] + gap;
            return j != i && norm2(m_x[size_t(i)] - m_x[size_t(j)]) < reach * reach;
        };
        // One walk a particle: its candidates go to a row of kCandidateRow slots as they are found, then
        // are copied into place once the starts are known; a row that overflowed walks again.
        m_candidateStart.assign(size_t(n) + 1, 0);
        m_candidateRows.resize(size_t(n) * size_t(kCandidateRow));
        parallelFor(m_threads, n, [&](int64_t i) {
            int64_t count = 0;
            int32_t* row = m_candidateRows.data() + size_t(i) * size_t(kCandidateRow);
            m_grid.forNeighbours(m_x[size_t(i)], radiusOf(i), [&](int64_t j) {
                if (!within(i, j)) return;
                if (count < kCandidateRow) row[count] = int32_t(j);
                ++count;
            });
            m_candidateStart[size_t(i) + 1] = count;
        });
        for (int64_t i = 0; i < n; ++i) m_candidateStart[size_t(i) + 1] += m_candidateStart[size_t(i)];
        m_candidates.resize(size_t(m_candidateStart[size_t(n)]));
        parallelFor(m_threads, n, [&](int64_t i) {
            int64_t slot = m_candidateStart[size_t(i)];
            const int64_t count = m_candidateStart[size_t(i) + 1] - slot;
            if (count <= kCandidateRow) {
                const int32_t* row = m_candidateRows.data() + size_t(i) * size_t(kCandidateRow);
                std::copy(row, row + count, m_candidates.begin() + slot);
                return;
            }
            m_grid.forNeighbours(m_x[size_t(i)], radiusOf(i), [&](int64_t j) {
                if (within(i, j)) m_candidates[size_t(slot++)] = int32_t(j);
            });
        });
        m_xCandidates = m_x;
        m_candidateSlack2 = Real(0.25 * margin * margin);
        m_candidateNearGap = m_nearGap;
        m_candidatesValid = true;
    }

    // The candidate lists outlive their step while they still hold every pair that can overlap or
    // come within the near gap: nobody has moved half the margin since they were made (a Verlet
    // list's rule) and the near gap has not grown. A settled pile keeps them for many steps.
    bool candidatesStillHold() const {
        if (m_xCandidates.size() != m_x.size() || m_nearGap > m_candidateNearGap) return false;
        for (size_t i = 0; i < m_x.size(); ++i) {
            if (norm2(m_x[i] - m_xCandidates[i]) > m_candidateSlack2) return false;
        }
        return true;
    }

    void setContactLog(bool on, double minImpulse) override {
        m_logContacts = on;
        m_logMinImpulse = minImpulse;
    }
    void readContactLog(std::vector<ContactRecord>& out) const override { out.assign(m_log.begin(), m_log.end()); }

    void applyEvents() override {
        const int64_t n = size();
        // End-of-step accelerations of the particles about to be resolved (second-order rewind),
        // once per particle and step: resolution moves a particle by a small fraction of a step.
        m_needAcceleration.clear();
        for (int64_t i = 0; i < n; ++i) {
            if (isValid(m_events[size_t(i)]) && !m_hasContactAcceleration[size_t(i)]) m_needAcceleration.push_back(i);
        }
        if (m_useList && !m_needAcceleration.empty()) {
            updateList(m_x);
            m_listMatchesX = true;  // within the skin of m_x until the end of this call
        }
        parallelFor(m_threads, int64_t(m_needAcceleration.size()), [&](int64_t k) {
            const int64_t i = m_needAcceleration[size_t(k)];
            m_contactAcceleration[size_t(i)] = accelerationOf(i, m_x, nullptr);
            m_hasContactAcceleration[size_t(i)] = 1;
        });
        m_listMatchesX = false;
        std::fill(m_kind.begin(), m_kind.end(), kNoCollision);
        parallelFor(m_threads, n, [&](int64_t i) { m_kind[size_t(i)] = resolveEventOf(i); });
        for (int64_t i = 0; i < n; ++i) {
            m_active[size_t(i)] = isValid(m_events[size_t(i)]);  // resolved now or still pending: look again
            if (m_kind[size_t(i)] == kPairCollision) ++m_tally.pairCollisions;
            if (m_kind[size_t(i)] == kWallCollision) ++m_tally.wallCollisions;
            // Only particles with an event moved: the candidates stay complete while none has gone
            // half the margin since they were listed.
            if (m_candidatesValid && m_active[size_t(i)] && norm2(m_x[size_t(i)] - m_xCandidates[size_t(i)]) > m_candidateSlack2)
                m_candidatesValid = false;
            if (m_logContacts && m_kind[size_t(i)] != kNoCollision && loggedImpact(m_detail[size_t(i)], m_logMinImpulse))
                m_log.push_back(contactRecordOf(i));
        }
        ++m_logRound;
    }

    // The rows in index order (deterministic); the rows this stage did not write are zero, and adding
    // +0.0 changes no sum (none of these sums is ever -0.0), so only the written rows are read.
    CollisionTally collisionTally() override {
        m_tally.dissipated = 0;
        m_tally.impulses = ImpulseSums{};
        for (size_t i = 0; i < m_impactWritten.size(); ++i) {
            if (!m_impactWritten[i]) continue;
            m_tally.dissipated += m_loss[i];
            m_tally.impulses += m_impulses[i];
        }
        return m_tally;
    }

    // Zero rows of loss and impulses for a stage of n particles: only the rows the last stage wrote,
    // not 112 bytes a particle (an LJ fluid of 32000 in a walled box: a few dozen wall hits a step,
    // and the stage's clearing and tally of every row were most of its time).
    void clearImpactRows(size_t n) {
        if (m_loss.size() != n || m_impulses.size() != n || m_impactWritten.size() != n) {
            m_loss.assign(n, 0.0);
            m_impulses.assign(n, ImpulseSums{});
            m_impactWritten.assign(n, 0);
            return;
        }
        for (size_t i = 0; i < n; ++i) {
            if (!m_impactWritten[i]) continue;
            m_loss[i] = 0;
            m_impulses[i] = ImpulseSums{};
            m_impactWritten[i] = 0;
        }
    }

    // ---- collision stage, 2: contact relaxation ----
    // The CPU runs the Gauss-Seidel form of contact_relaxation.h: contacts one at a time, ordered from
    // the bottom of the pile up (by height against gravity, then by index), so that support reaches
    // the top of a pile within a sweep, the stopping updates over-relaxed (kGaussSeidelOverRelaxation)
    // so that a deep pile's momentum reaches the floor within the sweep cap.
    int64_t listContacts(const RestingContact<double>& resting) override {
        const int64_t n = size();
        // The impact search just looked at every pair and wall this listing could take: none was
        // within reach (a fluid's usual step), so there is nothing to list, and no grid to walk.
        if (m_nearValid && Real(resting.gap) <= m_nearGap && std::none_of(m_near.begin(), m_near.end(), [](char c) { return c != 0; })) {
            m_contacts.clear();
            return 0;
        }
        const RestingContact<Real> rest{Real(resting.speed), Real(resting.gap)};
        if (!m_firstListing) keepWarmStart(true);  // a later listing carries this step's impulses so far
        // The impact rounds' candidate lists hold every pair within the resting gap while they still
        // hold (the sweeps of an earlier listing of this step moved particles: checked again); else
        // cells wide enough for resting pairs a resting gap apart.
        bool fromCandidates = m_candidatesValid && rest.gap <= m_candidateNearGap && candidatesStillHold();
        // A settled pile's rounds end before their third, where candidate lists are made (findEvents), so
        // every listing walked the cells. Made here, the lists serve this listing and, while they hold,
        // the next steps' listings and rounds: the same contacts and events. A sparse scene pays a build
        // where they do not hold; here assets/bouncing.toml (300 balls raining on a floor, 20,000 steps)
        // took 4.41 and 4.48 s against 4.48 and 4.53, assets/pile.toml (600 steps) 3.79 and 3.82 against
        // 3.78 and 3.78, with the same final states.
        if (!fromCandidates && rest.gap <= m_nearGap) {
            buildCandidates();
            fromCandidates = true;
        }
        if (!fromCandidates) buildContactGrid(resting.gap);
        const Vec3<double> up = vec3Cast<double>(upOf(m_gravity));
        // Each pair once, from its lower index: counted, offsets, then filled in place (no allocation
        // per particle in this per-step path). The count keeps up to kListedPartners partners a particle,
        // which the fill copies instead of walking the cells (or the candidates) again.
        auto ownContact = [&](int64_t i, int64_t partner) { return partner < 0 || partner > i; };
        m_contactStart.assign(size_t(n) + 1, 0);
        const bool keepsPartners = n <= INT32_MAX;  // partners and wall codes as 32-bit numbers
        if (keepsPartners) m_listedPartners.resize(size_t(n) * kListedPartners);
        parallelFor(m_threads, n, [&](int64_t i) {
            int64_t count = 0;
            int32_t* listed = keepsPartners ? &m_listedPartners[size_t(i) * kListedPartners] : nullptr;
            forEachContactOf(i, rest, fromCandidates, [&](int64_t partner) {
                if (!ownContact(i, partner)) return;
                if (listed && count < kListedPartners) listed[count] = int32_t(partner);
                ++count;
            });
            m_contactStart[size_t(i) + 1] = count;
        });
        for (int64_t i = 0; i < n; ++i) m_contactStart[size_t(i) + 1] += m_contactStart[size_t(i)];
        m_contacts.resize(size_t(m_contactStart[size_t(n)]));
        if (m_contacts.empty()) return 0;  // nothing to fill, sort or relax (a fluid's usual step)
        parallelFor(m_threads, n, [&](int64_t i) {
            int64_t slot = m_contactStart[size_t(i)];
            const double height = dot(up, vec3Cast<double>(m_x[size_t(i)]));
            auto fill = [&](int64_t partner) {
                if (!ownContact(i, partner)) return;
                const Real lambda = warmLambdaOf(i, partner);
                Contact c{i, partner, height, lambda, Real(0), m_firstListing ? Real(0) : lambda};
                if (partner >= 0) c.height = std::min(c.height, dot(up, vec3Cast<double>(m_x[size_t(partner)])));
                m_contacts[size_t(slot++)] = c;
            };
            const int64_t count = m_contactStart[size_t(i) + 1] - m_contactStart[size_t(i)];
            if (keepsPartners && count <= kListedPartners) {
                const int32_t* listed = &m_listedPartners[size_t(i) * kListedPartners];
                for (int64_t c = 0; c < count; ++c) fill(int64_t(listed[c]));
            } else {
                forEachContactOf(i, rest, fromCandidates, fill);
            }
            // By partner: the same list whether the candidates or the grid were walked (the order
            // breaks the sweep order's ties, so a restart, which builds its candidates afresh, stays
            // bit-identical).
            std::sort(m_contacts.begin() + m_contactStart[size_t(i)], m_contacts.begin() + slot,
                      [](const Contact& a, const Contact& b) { return a.partner < b.partner; });
        });
        // Bottom-up; at one height the walls first, since they are what holds everything else.
        // Tried and not kept: the count's and the fill's walks skipping the partners below i before the
        // contact test (the pair is listed from its lower index anyway), and one std::sort by (height,
        // walls first, i, partner) instead of the sort by partner within each particle and the stable
        // sort (the same order; perf gave the sorts 11% of the sandbox's world thread in its settled
        // pile): the same state hash, but the sandbox at 2,000 balls (this 2-core machine, three runs
        // each, interleaved with separate libraries) spent 2.52 to 2.71 ms a frame in its listings
        // against 2.59 to 2.70.
        sortBottomUp();
        setBounceTargets(rest.speed);
        // The first listing's impulses are the last step's: applied before its first sweep. A later
        // listing's are this step's, already in the velocities: carried, so that its sweeps may take
        // back a push an earlier listing overdid (lambda >= 0 bounds the step's whole impulse, not what
        // each listing adds), and so that the next step starts from the step's whole impulse. Started
        // from 0 instead, every listing could only push more, and the next step began from the last
        // listing's share alone (contact_relaxation.h: a pile 40 layers deep kept twenty times the
        // kinetic energy).
        m_warmPending = m_firstListing;
        m_firstListing = false;
        m_xListed = m_x;
        return int64_t(m_contacts.size());
    }

    // m_contacts in the order std::stable_sort gives them by (height; at one height walls first): a
    // stable radix sort of 65-bit keys (the height's bits made unsigned-monotone, then the wall flag),
    // 11 bits a pass, passes whose digit every key shares skipped, in kept buffers. The settled pile of
    // the sandbox at 2,000 balls (this 2-core machine, fp64, host timers) spent 227 us a listing in
    // std::stable_sort, whose temporary buffer (288 KiB) was mapped afresh each time (the page faults perf
    // showed). With this sort (three runs each, interleaved, separate libraries, under Xvfb; the same state
    // hash): its contact phase 3.9 to 4.2 ms a frame against 4.5 to 4.7, frames 8.2 to 9.0 ms against 9.0
    // to 9.4, and 1, 0 and 1 frames past 1/60 s against 4, 2 and 1.
    // The order is held in 32-bit indices (a listing of 2^32 contacts would need 200 GB); the buffers keep
    // the largest listing's memory.
    void sortBottomUp() {
        const size_t m = m_contacts.size();
        m_sortKey.resize(m);
        m_sortOrder.resize(m);
        m_sortKeyB.resize(m);
        m_sortOrderB.resize(m);
        for (size_t k = 0; k < m; ++k) {
            const double h = m_contacts[k].height + 0.0;  // -0 as +0: equal heights, equal keys
            uint64_t bits;
            std::memcpy(&bits, &h, sizeof bits);
            bits = (bits >> 63) ? ~bits : (bits | (uint64_t(1) << 63));
            m_sortKey[k] = bits;
            m_sortOrder[k] = uint32_t(k);
        }
        // The wall flag first (the least significant digit): walls before pairs, each in fill order.
        size_t walls = 0;
        for (size_t k = 0; k < m; ++k) walls += isWallContact(m_contacts[k].partner) ? 1 : 0;
        size_t wall = 0, pair = walls;
        for (size_t k = 0; k < m; ++k) {
            const size_t at = isWallContact(m_contacts[k].partner) ? wall++ : pair++;
            m_sortKeyB[at] = m_sortKey[k];
            m_sortOrderB[at] = m_sortOrder[k];
        }
        m_sortKey.swap(m_sortKeyB);
        m_sortOrder.swap(m_sortOrderB);
        constexpr int kDigitBits = 11;
        constexpr size_t kBuckets = size_t(1) << kDigitBits;
        std::vector<uint32_t>& count = m_sortCount;
        for (int shift = 0; shift < 64; shift += kDigitBits) {
            count.assign(kBuckets + 1, 0);
            for (size_t k = 0; k < m; ++k) ++count[((m_sortKey[k] >> shift) & (kBuckets - 1)) + 1];
            if (std::find(count.begin(), count.end(), uint32_t(m)) != count.end())
                continue;  // one digit: nothing moves
            for (size_t b = 0; b < kBuckets; ++b) count[b + 1] += count[b];
            for (size_t k = 0; k < m; ++k) {
                const size_t at = count[(m_sortKey[k] >> shift) & (kBuckets - 1)]++;
                m_sortKeyB[at] = m_sortKey[k];
                m_sortOrderB[at] = m_sortOrder[k];
            }
            m_sortKey.swap(m_sortKeyB);
            m_sortOrder.swap(m_sortOrderB);
        }
        m_sortedContacts.resize(m);
        for (size_t k = 0; k < m; ++k) m_sortedContacts[k] = m_contacts[m_sortOrder[k]];
        m_contacts.swap(m_sortedContacts);
    }

    // Isolated contacts (the only one of both particles) approaching faster than the resting speed
    // aim at e times their approach speed (contactRestitution); every other contact stops.
    void setBounceTargets(Real restingSpeed) {
        m_contactCount.assign(m_x.size(), 0);
        for (const Contact& c : m_contacts) {
            ++m_contactCount[size_t(c.i)];
            if (!isWallContact(c.partner)) ++m_contactCount[size_t(c.partner)];
        }
        const ContactBounce<Real> bounce{Real(m_model.restitution), Real(m_model.wallRestitution), Real(m_model.elasticBelowSpeed), restingSpeed};
        for (Contact& c : m_contacts) {
            const size_t i = size_t(c.i);
            if (m_contactCount[i] != 1) continue;
            if (isWallContact(c.partner)) {
                const int code = int(-1 - c.partner);
                const Real vn = (code % 2 == 0 ? Real(1) : Real(-1)) * m_v[i][code / 2];
                c.target = isolatedContactTarget(vn, bounce.wallRestitution, bounce);
                if (c.target > Real(0)) c.lambda = c.carried = Real(0);  // an impact: nothing to warm-start
                continue;
            }
            const size_t j = size_t(c.partner);
            if (m_contactCount[j] != 1) continue;
            const Vec3<Real> rij = m_x[i] - m_x[j];
            const Real dist = std::sqrt(norm2(rij));
            if (!(dist > Real(0))) continue;
            const Real vn = dot(m_v[i] - m_v[j], rij) / dist;
            c.target = isolatedContactTarget(vn, bounce.restitution, bounce);
            if (c.target > Real(0)) c.lambda = c.carried = Real(0);
        }
    }

    // Applies the warm-start impulses the first listing of the step took over (contact_relaxation.h):
    // part of this relaxation, so the kinetic energy the core measured after the listing still
    // brackets the whole velocity level.
    void applyWarmStart() {
        for (const Contact& c : m_contacts) {
            if (!(c.lambda > Real(0))) continue;
            const size_t i = size_t(c.i);
            if (isWallContact(c.partner)) {
                const int code = int(-1 - c.partner);
                m_v[i][code / 2] += code % 2 == 0 ? c.lambda : -c.lambda;
                continue;
            }
            const size_t j = size_t(c.partner);
            const Vec3<Real> rij = m_x[i] - m_x[j];
            const Real dist = std::sqrt(norm2(rij));
            if (!(dist > Real(0))) continue;
            applyPairImpulse(m_v[i], m_v[j], pairMasses(i, j), (Real(1) / dist) * rij, c.lambda);
        }
    }

    // The mass terms of every pair of species (contact_relaxation.h: PairMasses), so that a sweep
    // multiplies where it divided; made with the model.
    void fillPairMassTable() {
        const size_t s = m_mass.size();
        m_pairMassTable.resize(s * s);
        for (size_t a = 0; a < s; ++a)
            for (size_t b = 0; b < s; ++b) m_pairMassTable[a * s + b] = pairMassesOf(m_mass[a], m_mass[b]);
    }

    const PairMasses<Real>& pairMasses(size_t i, size_t j) const {
        return m_pairMassTable[size_t(m_species[i]) * m_mass.size() + size_t(m_species[j])];
    }

    // Measured and not pursued: skipping a contact in a sweep where neither of its particles changed since
    // its last update and that update changed nothing (the same bits: the update would change nothing
    // again). In the sandbox at 2,000 balls (fp64, 600 frames, 28,000 sweeps, a settled pile most of it)
    // 9% of the updates changed nothing and fewer than 1% could have been skipped so; 36% moved positions
    // (each listing's overlaps from a step of gravity), so the sweeps are far from a fixed point at the
    // sweep cap, and a skip by a threshold would change the relaxation for little.
    ContactResidual<double> relaxContacts(int sweeps) override {
        m_nearValid = false;  // the sweeps move particles
        ContactResidual<Real> r{0, 0};
        const Vec3<Real> up = upOf(m_gravity);
        if (m_warmPending) applyWarmStart();
        m_warmPending = false;
        const Real omega = Real(kGaussSeidelOverRelaxation);
        for (int sweep = 0; sweep < sweeps; ++sweep) {
            r = ContactResidual<Real>{0, 0};
            for (Contact& c : m_contacts) {
                const size_t i = size_t(c.i);
                const Real ai = m_radius[size_t(m_species[i])];
                if (isWallContact(c.partner)) {
                    const int code = int(-1 - c.partner), axis = code / 2;
                    relaxWallContact(m_x[i][axis], m_v[i][axis], code % 2, ai, m_boxLength[axis], c.target, c.lambda, r,
                                     omega);
                    continue;
                }
                const size_t j = size_t(c.partner);
                relaxPairContact(m_x[i], m_x[j], m_v[i], m_v[j], pairMasses(i, j), ai + m_radius[size_t(m_species[j])],
                                 up, c.target, c.lambda, r, omega);
            }
        }
        return ContactResidual<double>{double(r.speedChange), double(r.overlap)};
    }

    // Each contact's accumulated impulse lambda, less what it carried from earlier listings of the step
    // (they booked it), is its net impulse of the listing (per unit mass for a wall: stopWallContact),
    // summed in the list's order.
    ImpulseSums contactImpulses() override {
        ImpulseSums sums;
        for (const Contact& c : m_contacts) {
            const size_t i = size_t(c.i);
            const double given = double(c.lambda) - double(c.carried);
            if (isWallContact(c.partner)) {
                const int code = int(-1 - c.partner);
                const Real a = m_radius[size_t(m_species[i])];
                sums.addWall(code, double(m_mass[size_t(m_species[i])]) * given, atWallCentre(m_x[i], a, m_boxLength, code / 2));
                continue;
            }
            const Vec3<Real> rij = m_x[i] - m_x[size_t(c.partner)];
            sums.pairVirial += std::sqrt(double(norm2(rij))) * given;
        }
        return sums;
    }

    double contactLiftWork() override {
        return deterministicSum<double>(m_threads, size(), [&](int64_t i) {
            const size_t sp = size_t(m_species[size_t(i)]);
            const double m = double(m_mass[sp]);
            const Vec3<double> g = vec3Cast<double>(m_field[sp]);
            return -m * dot(g, vec3Cast<double>(m_x[size_t(i)]) - vec3Cast<double>(m_xListed[size_t(i)]));
        });
    }

    // ---- reductions ----
    double kineticEnergy() override {
        return deterministicSum<double>(m_threads, size(), [&](int64_t i) {
            return kineticEnergyOf(double(m_mass[size_t(m_species[size_t(i)])]), vec3Cast<double>(m_v[size_t(i)]));
        });
    }

    double pairVirial() override {
        if (!m_model.anyPairForce) return 0;
        const int64_t n = size();
        if (m_useList) {  // every pair from both sides in ascending order, as the force pass
            updateList(m_x);
            return listPairVirial(m_list, listInputs(m_x), m_listScratch, n);
        }
        // Every pair from both sides, as the force pass: half of sum_i sum_j r_ij . F_ij.
        return 0.5 * deterministicSum<double>(m_threads, n, [&](int64_t i) {
            const Vec3<Real> xi = m_x[size_t(i)];
            const PairCoefficients<Real>* row = &m_pairs[size_t(m_species[size_t(i)]) * m_mass.size()];
            double w = 0;
            for (int64_t j = 0; j < n; ++j) {
                const Real r2 = norm2(xi - m_x[size_t(j)]);
                if (j == i || r2 == Real(0)) continue;
                w += double(pairForceOverR(row[m_species[size_t(j)]], r2, static_cast<Real*>(nullptr))) * double(r2);
            }
            return w;
        });
    }

    void scaleVelocities(double alpha) override {
        const Real a = Real(alpha);
        parallelFor(m_threads, size(), [&](int64_t i) { m_v[size_t(i)] = a * m_v[size_t(i)]; });
    }

    EnergySums energies() override {
        const size_t s = m_mass.size();
        std::vector<double> pairEnergy(m_x.size());
        m_scratchAcceleration.resize(m_x.size());
        accelerations(m_x, m_scratchAcceleration.data(), pairEnergy.data());
        struct Partial {
            double potential = 0;
            Vec3<double> momentum{0, 0, 0};
            std::vector<double> kinetic;
            Partial& operator+=(const Partial& o) {
                potential += o.potential;
                momentum += o.momentum;
                if (kinetic.size() < o.kinetic.size()) kinetic.resize(o.kinetic.size(), 0.0);
                for (size_t k = 0; k < o.kinetic.size(); ++k) kinetic[k] += o.kinetic[k];
                return *this;
            }
        };
        const Partial total = deterministicSum<Partial>(m_threads, size(), [&](int64_t i) {
            Partial p;
            const size_t sp = size_t(m_species[size_t(i)]);
            const double m = double(m_mass[sp]);
            const Vec3<double> v = vec3Cast<double>(m_v[size_t(i)]);
            // Each pair was counted from both sides; gravity: U = -m g.x.
            p.potential = 0.5 * pairEnergy[size_t(i)] + gravityPotentialOf(m, vec3Cast<double>(m_field[sp]), vec3Cast<double>(m_x[size_t(i)]));
            p.momentum = m * v;
            p.kinetic.assign(s, 0.0);
            p.kinetic[sp] = kineticEnergyOf(m, v);
            return p;
        });
        EnergySums sums;
        sums.potential = total.potential;
        sums.momentum = total.momentum;
        sums.kineticPerSpecies.assign(s, 0.0);
        for (size_t k = 0; k < total.kinetic.size(); ++k) {
            sums.kineticPerSpecies[k] = total.kinetic[k];
            sums.kinetic += total.kinetic[k];
        }
        return sums;
    }

    HealthReport health() override {
        HealthReport report;
        for (size_t i = 0; i < m_x.size(); ++i) {
            bool finite = true, inside = true;
            for (int a = 0; a < 3; ++a) {
                finite = finite && std::isfinite(double(m_x[i][a])) && std::isfinite(double(m_v[i][a]));
                inside = inside && m_x[i][a] >= Real(0) && m_x[i][a] <= m_boxLength[a];
            }
            if (!finite) ++report.nonFinite;
            else if (!inside) ++report.outsideBox;
            if ((!finite || !inside) && report.examples.size() < 5) report.examples.push_back(int64_t(i));
        }
        return report;
    }

    // ---- timing and output ----
    void markPhase(StepPhase phase) override {
        const Clock::time_point now = Clock::now();
        if (phase == StepPhase::Integrate) m_forceSeconds = 0;
        m_phaseStart[int(phase)] = now;
    }

    PhaseSeconds phaseSeconds() override {
        PhaseSeconds s;
        s.forces = m_forceSeconds;
        s.integrate = secondsBetween(m_phaseStart[0], m_phaseStart[1]) - m_forceSeconds;
        s.collide = secondsBetween(m_phaseStart[1], m_phaseStart[2]);
        return s;
    }

    void writeInstances(const InstanceTarget& target) override {
        if (target.memory != InstanceTarget::Memory::Host) throw DeviceError("the CPU backend writes instances to host memory only");
        parallelFor(m_threads, size(), [&](int64_t i) {
            const int32_t s = m_species[size_t(i)];
            target.instances[i] = particleInstanceOf(m_x[size_t(i)], m_v[size_t(i)], s, m_radius[size_t(s)], target.key);
        });
    }

    void finish() override {}

private:
    int64_t size() const { return int64_t(m_x.size()); }

    ParticleState toHost(const std::vector<Vec3<Real>>& x, const std::vector<Vec3<Real>>& v) const {
        ParticleState out;
        out.resize(x.size());
        for (size_t i = 0; i < x.size(); ++i) {
            out.position[i] = vec3Cast<double>(x[i]);
            out.velocity[i] = vec3Cast<double>(v[i]);
            out.species[i] = m_species[i];
        }
        return out;
    }

    // a_i = sum_j F_ij / m_i + g over all pairs, and sum_j U_ij into *pairEnergy when asked.
    Vec3<Real> accelerationOf(int64_t i, const std::vector<Vec3<Real>>& x, double* pairEnergy) const {
        if (!m_model.anyPairForce) {  // pure hard spheres: only the uniform fields, no pair loop
            if (pairEnergy) *pairEnergy = 0;
            return m_field[size_t(m_species[size_t(i)])];
        }
        if (m_useList && &x == &m_x && m_listMatchesX) return listAccelerationOf(i, x);
        const int64_t n = int64_t(x.size());
        const Vec3<Real> xi = x[size_t(i)];
        const PairCoefficients<Real>* row = &m_pairs[size_t(m_species[size_t(i)]) * m_mass.size()];
        Vec3<Real> force{0, 0, 0};
        double energy = 0;
        for (int64_t j = 0; j < n; ++j) {
            if (j == i) continue;
            const Vec3<Real> r = xi - x[size_t(j)];
            const Real r2 = norm2(r);
            if (r2 == Real(0)) continue;  // coincident centres carry no direction
            Real u = 0;
            const Real f = pairForceOverR(row[m_species[size_t(j)]], r2, pairEnergy ? &u : nullptr);
            force += f * r;
            energy += double(u);
        }
        if (pairEnergy) *pairEnergy = energy;
        return m_invMass[size_t(m_species[size_t(i)])] * force + m_field[size_t(m_species[size_t(i)])];
    }

    void accelerations(const std::vector<Vec3<Real>>& x, Vec3<Real>* out, double* pairEnergy, bool screen = false) {
        const Clock::time_point start = Clock::now();
        if (m_useList) {
            listAccelerations(x, out, pairEnergy, screen);
        } else {
            parallelFor(m_threads, int64_t(x.size()), [&](int64_t i) {
                out[size_t(i)] = accelerationOf(i, x, pairEnergy ? &pairEnergy[i] : nullptr);
            });
            if (m_model.anyPairForce) m_counters.allPairsEvaluations += int64_t(x.size()) * (int64_t(x.size()) - 1);
        }
        m_forceSeconds += secondsBetween(start, Clock::now());
    }

    ListPassInputs<Real> listInputs(const std::vector<Vec3<Real>>& x) const {
        return ListPassInputs<Real>{x.data(), m_species.data(), m_pairs.data(), int(m_mass.size()), m_invMass.data(), m_field.data(), m_threads};
    }

    // Neighbour-list pass (list_forces.h); with `screen`, the collision screen of these positions.
    void listAccelerations(const std::vector<Vec3<Real>>& x, Vec3<Real>* out, double* pairEnergy, bool screen) {
        updateList(x);
        const ListPassInputs<Real> in = listInputs(x);
        const int64_t n = int64_t(x.size());
        const ListScreenReach<Real>* reach = screen ? &screenReaches() : nullptr;
        const bool single = m_mass.size() == 1;
        ListScreen found;
        if (pairEnergy) {
            found = single ? listForcePass<Real, true, true>(m_list, in, m_listScratch, n, out, pairEnergy, reach)
                           : listForcePass<Real, true, false>(m_list, in, m_listScratch, n, out, pairEnergy, reach);
        } else {
            found = single ? listForcePass<Real, false, true>(m_list, in, m_listScratch, n, out, nullptr, reach)
                           : listForcePass<Real, false, false>(m_list, in, m_listScratch, n, out, nullptr, reach);
        }
        if (screen) m_screen = found;
    }

    // The screen's reaches at the gap of the last stage (kernels/collision_screen.h), kept while the gap,
    // the radii and the box stay.
    const ListScreenReach<Real>& screenReaches() {
        if (m_screenReachGap == m_screenGap) return m_screenReach;
        const size_t s = m_mass.size();
        m_screenReach.inverseReach2.resize(s * s);
        m_screenReach.wallReach.resize(s);
        for (size_t a = 0; a < s; ++a) {
            m_screenReach.wallReach[a] = Real(screenReach(double(m_radius[a]), m_screenGap));
            for (size_t b = 0; b < s; ++b) {
                const double reach = screenReach(double(m_radius[a]) + double(m_radius[b]), m_screenGap);
                m_screenReach.inverseReach2[a * s + b] = Real(1.0 / (reach * reach));
            }
        }
        m_screenReach.box = m_boxLength;
        m_screenReachGap = m_screenGap;
        return m_screenReach;
    }

    // a_i from the list's pairs of i by ascending partner (one particle: the bits of a full pass), for
    // the collision stage's accelerations of the particles it resolves.
    Vec3<Real> listAccelerationOf(int64_t i, const std::vector<Vec3<Real>>& x) const {
        const Vec3<Real> xi = x[size_t(i)];
        const PairCoefficients<Real>* row = &m_pairs[size_t(m_species[size_t(i)]) * m_mass.size()];
        Vec3<Real> force{0, 0, 0};
        std::vector<int32_t> partners;
        m_list.forEachPartner(i, partners, [&](int64_t j) {
            const Vec3<Real> r = xi - x[size_t(j)];
            force += pairForceOverR(row[m_species[size_t(j)]], norm2(r), static_cast<Real*>(nullptr)) * r;
        });
        return m_invMass[size_t(m_species[size_t(i)])] * force + m_field[size_t(m_species[size_t(i)])];
    }

    // Lists: each pair of a moved particle changes by F(now) - F(before), added to both particles; a
    // pair of two moved particles once, from the lower index. Moved particles by ascending index, each
    // one's partners by ascending index: the same bits on every run and thread count. A rebuild since
    // the stage began (the moves pushed someone past half the skin) means a full pass.
    bool refreshFromList() {
        if (updateList(m_x) || m_list.builds() != m_buildsAtStage) {
            computeAccelerations();
            return true;
        }
        m_isMoved.assign(m_x.size(), 0);
        for (int64_t i : m_moved) m_isMoved[size_t(i)] = 1;
        const size_t s = m_mass.size();
        int64_t touched = int64_t(m_moved.size());
        for (int64_t i : m_moved) {
            const size_t si = size_t(m_species[size_t(i)]);
            m_list.forEachPartner(i, m_partnerScratch, [&](int64_t j) {
                if (m_isMoved[size_t(j)] == 1 && j < i) return;  // taken from j's side
                const size_t sj = size_t(m_species[size_t(j)]);
                const PairCoefficients<Real>& p = m_pairs[si * s + sj];
                const Vec3<Real> now = m_x[size_t(i)] - m_x[size_t(j)];
                const Vec3<Real> was = m_xBeforeCollisions[size_t(i)] - m_xBeforeCollisions[size_t(j)];
                const Vec3<Real> change = pairForceOverR(p, norm2(now), static_cast<Real*>(nullptr)) * now -
                                          pairForceOverR(p, norm2(was), static_cast<Real*>(nullptr)) * was;
                m_acceleration[size_t(i)] += m_invMass[si] * change;
                m_acceleration[size_t(j)] -= m_invMass[sj] * change;
                if (m_isMoved[size_t(j)] == 0) {
                    m_isMoved[size_t(j)] = 2;
                    ++touched;
                }
            });
        }
        m_accelerationIncremental = true;
        m_counters.refreshedParticles += touched;
        return true;
    }

    bool updateList(const std::vector<Vec3<Real>>& x) { return m_list.update(x, m_boxLength, m_model.cutoff, m_model.skin, m_threads); }

    // The positions changed outside a force pass: the cached accelerations and the screen no longer match them.
    void forgetForces() {
        m_accelerationMatchesX = false;
        m_screenPending = false;
    }

    // Earliest event of particle i against its grid neighbours: an active particle looks at every
    // neighbour, an inactive one only at active neighbours (two inactive particles cannot have
    // started to overlap). `near` says whether a partner or a wall is within the resting gap bound
    // (listContacts skips its walk when no particle is): set afresh by an active particle, and by every
    // particle that walks in a stage's first round; an inactive one of a later round only adds what its
    // active neighbours bring (its other pairs have not moved).
    CollisionEvent earliestEvent(int64_t i, char& near) const {
        return earliestEventAmong(i, near, [&](auto&& fn) { m_grid.forNeighbours(m_x[size_t(i)], radiusOf(i), fn); });
    }

    CollisionEvent earliestEventAmongCandidates(int64_t i, char& near) const {
        return earliestEventAmong(i, near, [&](auto&& fn) {
            for (int64_t c = m_candidateStart[size_t(i)]; c < m_candidateStart[size_t(i) + 1]; ++c) fn(int64_t(m_candidates[size_t(c)]));
        });
    }

    // Particle i's earliest event among the partners forNeighbours(fn) visits and the walls; notes
    // in `near` whether a partner or wall is within the near gap.
    template <class ForNeighbours>
    CollisionEvent earliestEventAmong(int64_t i, char& near, ForNeighbours&& forNeighbours) const {
        CollisionEvent best = noEvent();
        const bool checkAll = m_active[size_t(i)] != 0;
        const Vec3<Real> xi = m_x[size_t(i)], vi = m_v[size_t(i)];
        const Real ai = m_radius[size_t(m_species[size_t(i)])];
        // `near` found afresh: an active particle's, and in a stage's first round (only the movers
        // active, startsActive) every walking particle's, over every neighbour it walks, so that the
        // listing can still skip a step where nothing is near.
        const bool afresh = checkAll || m_round == 1;
        bool close = !afresh && near != 0;
        forNeighbours([&](int64_t j) {
            if (j == i) return;
            const bool looks = checkAll || m_active[size_t(j)];
            if (!looks && !afresh) return;
            const Vec3<Real> xj = m_x[size_t(j)];
            const Real aj = m_radius[size_t(m_species[size_t(j)])];
            const Real reach = ai + aj + m_nearGap;
            close = close || norm2(xi - xj) < reach * reach;
            if (looks) considerPair(xi, vi, ai, xj, m_v[size_t(j)], aj, j, m_window, best);
        });
        considerWalls(xi, vi, ai, m_boxLength, m_window, best);
        near = close || nearAWall(xi, ai) ? 1 : 0;
        return best;
    }

    // Whether a particle of this radius at x is within the near gap of a wall.
    bool nearAWall(const Vec3<Real>& x, Real radius) const {
        for (int axis = 0; axis < 3; ++axis) {
            if (wallClearance(x[axis], radius, m_boxLength[axis], 0) < m_nearGap || wallClearance(x[axis], radius, m_boxLength[axis], 1) < m_nearGap)
                return true;
        }
        return false;
    }

    struct Contact {
        int64_t i, partner;  // partner: particle index > i, or a wall code
        double height;       // of the lower of the two against gravity: the sweep order
        Real lambda;         // accumulated normal impulse of the velocity level
        Real target;         // separation speed the velocity level aims at: 0, or a bounce (contactRestitution)
        // Of lambda, what earlier listings of this step gave (carried, not applied again): booked by them.
        Real carried = 0;
    };

    // fn(partner) for each contact of particle i that the relaxation acts on (contact_relaxation.h:
    // pairContactActive, wallContactActive): neighbours in the candidate list's or the cell list's
    // order, then walls.
    template <class Fn>
    void forEachContactOf(int64_t i, const RestingContact<Real>& rest, bool fromCandidates, Fn&& fn) const {
        const Vec3<Real> xi = m_x[size_t(i)], vi = m_v[size_t(i)];
        const Real ai = m_radius[size_t(m_species[size_t(i)])];
        auto visit = [&](int64_t j) {
            if (j != i && pairContactActive(xi, vi, m_x[size_t(j)], m_v[size_t(j)], ai + m_radius[size_t(m_species[size_t(j)])], rest)) fn(j);
        };
        if (fromCandidates) {
            for (int64_t c = m_candidateStart[size_t(i)]; c < m_candidateStart[size_t(i) + 1]; ++c) visit(int64_t(m_candidates[size_t(c)]));
        } else {
            m_grid.forNeighbours(xi, ai, visit);
        }
        for (int axis = 0; axis < 3; ++axis) {
            for (int side = 0; side < 2; ++side) {
                if (wallContactActive(xi[axis], vi[axis], ai, m_boxLength[axis], side, rest)) fn(wallCode(axis, side));
            }
        }
    }

    // Resolves particle i's event when it is the earliest of every particle it touches and i is its
    // lower index; returns the CollisionKind applied.
    int resolveEventOf(int64_t i) {
        const CollisionEvent e = m_events[size_t(i)];
        if (!isValid(e)) return kNoCollision;
        const size_t si = size_t(m_species[size_t(i)]);
        const Real eParticle = Real(m_model.restitution);
        const Real elasticBelow = Real(m_model.elasticBelowSpeed);
        if (e.partner >= 0) {
            const int64_t j = e.partner;
            if (j < i || m_events[size_t(j)].partner != i) return kNoCollision;
            const size_t sj = size_t(m_species[size_t(j)]);
            m_impactWritten[size_t(i)] = 1;
            return resolvePairEvent(m_x[size_t(i)], m_v[size_t(i)], m_contactAcceleration[size_t(i)], m_mass[si], m_x[size_t(j)],
                                    m_v[size_t(j)], m_contactAcceleration[size_t(j)], m_mass[sj], m_radius[si] + m_radius[sj], e.key,
                                    m_window.maxRewind, eParticle, elasticBelow, &m_loss[size_t(i)], &m_impulses[size_t(i)].pairVirial,
                                    m_logContacts ? &m_detail[size_t(i)] : nullptr);
        }
        return resolveWallOf(i, e, m_contactAcceleration[size_t(i)]);
    }

    // Particle i's wall event e, with its end-of-step acceleration a; returns the CollisionKind applied.
    int resolveWallOf(int64_t i, const CollisionEvent& e, const Vec3<Real>& a) {
        const size_t si = size_t(m_species[size_t(i)]);
        const int code = int(-1 - e.partner), axis = code / 2;
        double impulse = 0;
        const int kind = resolveWallEvent(m_x[size_t(i)][axis], m_v[size_t(i)][axis], a[axis], m_mass[si], m_radius[si], m_boxLength[axis],
                                          code % 2, e.key, m_window.maxRewind, Real(m_model.wallRestitution),
                                          Real(m_model.elasticBelowSpeed), &m_loss[size_t(i)], &impulse,
                                          m_logContacts ? &m_detail[size_t(i)] : nullptr);
        if (m_logContacts) m_detail[size_t(i)].normal[axis] = code % 2 == 0 ? Real(1) : Real(-1);  // into the box
        m_impactWritten[size_t(i)] = 1;
        m_impulses[size_t(i)].addWall(code, impulse, atWallCentre(m_x[size_t(i)], m_radius[si], m_boxLength, axis));
        return kind;
    }

    // The contact log entry of particle i's impact resolved in this round.
    ContactRecord contactRecordOf(int64_t i) const {
        const ImpactDetail<Real>& d = m_detail[size_t(i)];
        ContactRecord r;
        r.a = i;
        r.b = m_events[size_t(i)].partner;
        r.round = m_logRound;
        r.time = std::clamp(m_stepDt - double(d.rewind), 0.0, m_stepDt);
        r.normal = vec3Cast<double>(d.normal);
        r.impulse = double(d.impulse);
        r.speed = double(d.speed);
        return r;
    }

    int m_threads;
    DeviceModel m_model;
    ButcherTableau m_tableau{};
    std::vector<PairCoefficients<Real>> m_pairs;
    std::vector<Real> m_mass, m_invMass, m_radius;
    Vec3<Real> m_gravity{0, 0, 0};    // the global field: "up" of the contact phase
    std::vector<Vec3<Real>> m_field;  // per species: gravity plus the species' own acceleration
    Vec3<Real> m_boxLength{0, 0, 0};

    std::vector<Vec3<Real>> m_x, m_v;
    std::vector<int32_t> m_species;
    std::vector<Vec3<Real>> m_acceleration, m_scratchAcceleration;
    std::vector<Vec3<Real>> m_kx, m_kv, m_xStage, m_vStage;
    std::vector<Vec3<Real>> m_snapshotX, m_snapshotV;

    std::vector<CollisionEvent> m_events;
    bool m_logContacts = false;
    double m_logMinImpulse = 0;  // setContactLog: impacts below this impulse are not recorded
    std::vector<ContactRecord> m_log;           // this step's impacts, by (round, a)
    std::vector<ImpactDetail<Real>> m_detail;   // per particle, of this round's impact
    int32_t m_logRound = 0;                     // applyEvents calls this step
    double m_stepDt = 0;
    std::vector<char> m_active;
    std::vector<char> m_lookers;  // findEvents: the particles that may have an event this round
    int m_round = 0;              // findEvents calls this step
    bool m_moversFirst = true;    // CpuBackendOptions::moversFirst
    // Candidate lists of a dense step's rounds (buildCandidates): the partners of particle i are
    // m_candidates[m_candidateStart[i] .. m_candidateStart[i + 1]), listed at m_xCandidates, with a
    // margin of kCandidateMargin (collision_resolution.h) of the largest diameter.
    // Candidates a particle keeps from its one walk (buildCandidates): in a dense packing of equal
    // spheres 12 touch each one; larger spheres among small ones may have more and walk twice.
    static constexpr int64_t kCandidateRow = 32;
    bool m_candidatesValid = false;
    std::vector<int64_t> m_candidateStart;
    std::vector<int32_t> m_candidates;
    std::vector<int32_t> m_candidateRows;  // buildCandidates: kCandidateRow slots a particle
    std::vector<int32_t> m_candidateOrder;  // the grid's order at the listing: neighbours walk together
    std::vector<Vec3<Real>> m_xCandidates;
    Real m_candidateSlack2 = 0;
    Real m_candidateNearGap = 0;  // the near gap they were made for
    // Per particle: a partner or wall within m_nearGap at its last look (findEvents); valid until
    // the contact sweeps move particles.
    std::vector<char> m_near;
    bool m_nearValid = false;
    Real m_nearGap = 0;
    std::vector<Vec3<Real>> m_contactAcceleration;
    std::vector<char> m_hasContactAcceleration;
    std::vector<int64_t> m_needAcceleration;
    std::vector<int> m_kind;
    std::vector<double> m_loss;
    std::vector<ImpulseSums> m_impulses;  // per particle (resolved by its lower index), summed in index order
    std::vector<char> m_impactWritten;    // the particles whose m_loss and m_impulses rows this stage wrote
    CollisionTally m_tally;
    ImpactWindow<Real> m_window{0, 0};
    CellList m_grid;
    CellSplitChoice m_cellSplit;  // the contact grid's large particles (cell_list.h)

    Real radiusOf(int64_t i) const { return m_radius[size_t(m_species[size_t(i)])]; }

    void chooseContactCellSplit() { m_cellSplit = chooseCellSplit(m_model.radius, speciesCounts(m_species, int(m_radius.size()))); }

    // The contact grid at the current positions: cells at least 2 gridRadius + extra wide, the large
    // particles kept out of them.
    void buildContactGrid(double extra) {
        const int64_t n = size();
        const CellGeometry geometry = cellGeometry(vec3Cast<double>(m_boxLength), n, 2.0 * m_cellSplit.gridRadius + extra);
        const CellSplit<Real> split = cellSplitOf(m_cellSplit, m_species.data(), m_radius.data());
        m_grid.build(m_x.data(), n, geometry, split, m_cellSplit.gridRadius);
    }

    // Forces: the neighbour list and its per-slot pair values, what still matches m_x, the counters.
    bool m_useList = false;
    VerletList<Real> m_list;
    ListPassScratch<Real> m_listScratch;
    std::vector<int32_t> m_partnerScratch;
    int64_t m_buildsAtStage = 0;          // the list's builds when the collision stage began
    bool m_accelerationMatchesX = false;  // m_acceleration = a(m_x)
    bool m_listMatchesX = false;          // the list is within the skin of m_x (inside applyEvents)
    bool m_accelerationIncremental = false;  // A holds an update after collisions, not a force pass's bits (checkpoints carry it)
    bool m_refreshable = false;           // A matched X at beginCollisions: refreshAccelerations may update
    // The collision screen (screenStage): found by the last end-of-step list pass, at the gap the last
    // stage asked for; whether it still describes X; whether this stage's pairs are clear; whether
    // this stage resolves its walls at once.
    ListScreen m_screen;
    double m_screenGap = -1;
    bool m_screenPending = false;
    bool m_pairsClear = false;
    bool m_wallsAtOnce = false;
    ListScreenReach<Real> m_screenReach;
    double m_screenReachGap = -1;
    std::vector<Vec3<Real>> m_xBeforeCollisions;
    std::vector<int64_t> m_moved;
    std::vector<char> m_isMoved;
    ForceCounters m_counters;

    std::vector<int64_t> m_contactStart;  // per particle: its first contact in m_contacts before sorting
    std::vector<Contact> m_contacts;      // bottom-up
    // sortBottomUp's buffers, kept for their memory.
    std::vector<Contact> m_sortedContacts;
    std::vector<uint64_t> m_sortKey, m_sortKeyB;
    std::vector<uint32_t> m_sortOrder, m_sortOrderB, m_sortCount;
    std::vector<PairMasses<Real>> m_pairMassTable;  // by species i * species count + species j
    // listContacts' count: up to kListedPartners own partners a particle, for its fill.
    static constexpr int64_t kListedPartners = 16;
    std::vector<int32_t> m_listedPartners;
    std::vector<int32_t> m_contactCount;  // listed contacts per particle (setBounceTargets)
    std::vector<Vec3<Real>> m_xListed;
    // Warm start: the last step's impulses by particle (keepWarmStart), taken by the step's first listing.
    std::vector<int64_t> m_warmStart;
    std::vector<int64_t> m_warmPartner;
    std::vector<Real> m_warmLambda;
    bool m_firstListing = false;
    bool m_warmPending = false;  // the listed lambdas are not applied to V yet

    Clock::time_point m_phaseStart[3] = {};
    double m_forceSeconds = 0;  // force passes since the Integrate mark
};

}  // namespace

std::unique_ptr<Backend> makeCpuBackend(const CpuBackendOptions& options) {
    if (options.precision == Precision::Fp32) return std::make_unique<CpuBackendImpl<float>>(options);
    return std::make_unique<CpuBackendImpl<double>>(options);
}

}  // namespace corebox
