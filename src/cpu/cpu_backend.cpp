#include "cpu_backend.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "butcher_tableau.h"
#include "collision.h"
#include "contact_grid.h"
#include "cpu_parallel.h"
#include "errors.h"
#include "maxwell_boltzmann.h"
#include "pair_table.h"
#include "rk_stage.h"
#include "speed_statistics.h"

namespace corebox {
namespace {

// One candidate event of a particle in a collision-resolution round. Larger key = earlier in the
// step (longer rewind); positional fixes (overlaps not produced by approach) rank below every
// contact. partner: particle index, or a wall code -1 - (2 * axis + side).
struct Event {
    double key = -std::numeric_limits<double>::infinity();
    int64_t partner = kNone;
    static constexpr int64_t kNone = std::numeric_limits<int64_t>::min();
    static constexpr double kFixKey = -1.0;

    bool valid() const { return partner != kNone; }
    // Deterministic order: earlier event first, then the lower partner code.
    bool betterThan(const Event& o) const { return key > o.key || (key == o.key && partner < o.partner); }
};

int64_t wallCode(int axis, int side) { return -1 - (2 * axis + side); }

template <class Real>
class CpuBackendImpl final : public Backend {
public:
    explicit CpuBackendImpl(const CpuBackendOptions& options)
        : m_threads(options.threads > 0 ? options.threads : omp_get_max_threads()) {}

    std::string name() const override { return "cpu"; }
    Precision precision() const override { return std::is_same<Real, float>::value ? Precision::Fp32 : Precision::Fp64; }

    void setParameters(const StepParameters& parameters) override {
        const bool dtChanged = parameters.integrator.dt != m_params.integrator.dt;
        m_params = parameters;
        if (parameters.integrator.method != Method::Verlet) m_tableau = tableauFor(parameters.integrator.method);
        m_pairs = convertPairTable<Real>(buildPairTable(parameters));
        m_anyPairForce = std::any_of(m_pairs.begin(), m_pairs.end(), [](const PairCoefficients<Real>& p) { return p.eps4 != Real(0); });
        const size_t s = parameters.species.size();
        m_invMass.assign(s, 0);
        m_mass.assign(s, 0);
        m_radius.assign(s, 0);
        for (size_t k = 0; k < s; ++k) {
            m_mass[k] = Real(parameters.species[k].mass);
            m_invMass[k] = Real(1.0 / parameters.species[k].mass);
            m_radius[k] = Real(parameters.species[k].radius);
        }
        for (int a = 0; a < 3; ++a) {
            m_gravity[a] = Real(parameters.interaction.gravity[a]);
            m_boxLength[a] = Real(parameters.box.size[a]);
        }
        if (dtChanged || m_dtNext <= 0) m_dtNext = parameters.integrator.dt;
        m_accelerationValid = false;
    }

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
        m_accelerationValid = false;
    }

    ParticleState state() const override { return toHost(m_x, m_v); }

    StepReport step() override {
        StepReport report;
        if (m_params.integrator.method == Method::Verlet) {
            report.dt = m_params.integrator.dt;
            verletStep(Real(report.dt));
        } else if (m_params.integrator.adaptive && m_tableau.embeddedOrder > 0) {
            adaptiveRkStep(report);
        } else {
            report.dt = m_params.integrator.dt;
            rkStep(Real(report.dt), m_tableau.solutionStages);
            std::swap(m_x, m_xStage);
            std::swap(m_v, m_vStage);
        }
        resolveCollisions(report);
        // Collisions move particles and change velocities: the cached Verlet acceleration is only
        // reusable when nothing was touched.
        if (report.pairCollisions + report.wallCollisions + report.positionalFixes > 0) m_accelerationValid = false;
        return report;
    }

    double kineticEnergy() override {
        return deterministicSum<double>(m_threads, int64_t(m_x.size()), [&](int64_t i) {
            return 0.5 * double(m_mass[m_species[i]]) * double(norm2(m_v[i]));
        });
    }

    void scaleVelocities(double alpha) override {
        const Real a = Real(alpha);
        parallelFor(m_threads, int64_t(m_v.size()), [&](int64_t i) { m_v[i] = a * m_v[i]; });
    }

    EnergySums energies() override {
        EnergySums sums;
        const size_t s = m_params.species.size();
        sums.kineticPerSpecies.assign(s, 0.0);
        std::vector<double> pairEnergy(m_x.size());
        accelerations(m_x, m_scratchAcceleration, pairEnergy.data());
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
        const Partial total = deterministicSum<Partial>(m_threads, int64_t(m_x.size()), [&](int64_t i) {
            Partial p;
            const int sp = m_species[i];
            const double m = double(m_mass[sp]);
            const Vec3<double> v = vec3Cast<double>(m_v[i]);
            const Vec3<double> x = vec3Cast<double>(m_x[i]);
            // Each pair was counted from both sides; gravity: U = -m g.x.
            p.potential = 0.5 * pairEnergy[size_t(i)] - m * dot(vec3Cast<double>(m_gravity), x);
            p.momentum = m * v;
            p.kinetic.assign(s, 0.0);
            p.kinetic[size_t(sp)] = 0.5 * m * norm2(v);
            return p;
        });
        sums.potential = total.potential;
        sums.momentum = total.momentum;
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

    SpeedStatistics speedStatistics(const SpeedRequest& request) override {
        std::vector<double> speeds;
        std::vector<int64_t> perSpecies(m_params.species.size(), 0);
        for (size_t i = 0; i < m_v.size(); ++i) {
            if (request.species >= 0 && m_species[i] != request.species) continue;
            speeds.push_back(std::sqrt(double(norm2(m_v[i]))));
            ++perSpecies[size_t(m_species[i])];
        }
        std::vector<double> masses;
        for (const SpeciesDef& sp : m_params.species) masses.push_back(sp.mass);
        return computeSpeedStatistics(std::move(speeds), perSpecies, masses, request);
    }

    void keepSnapshot() override {
        m_snapshotX = m_x;
        m_snapshotV = m_v;
    }

    ParticleState snapshot() const override { return toHost(m_snapshotX, m_snapshotV); }

    int64_t computeForcesOnly() override {
        accelerations(m_x, m_scratchAcceleration, nullptr);
        const int64_t n = int64_t(m_x.size());
        return n * (n - 1);
    }

private:
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
        if (!m_anyPairForce) {  // pure hard spheres: only gravity, no pair loop
            if (pairEnergy) *pairEnergy = 0;
            return m_gravity;
        }
        const int64_t n = int64_t(x.size());
        const Vec3<Real> xi = x[size_t(i)];
        const PairCoefficients<Real>* row = &m_pairs[size_t(m_species[size_t(i)]) * m_params.species.size()];
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
        return m_invMass[size_t(m_species[size_t(i)])] * force + m_gravity;
    }

    void accelerations(const std::vector<Vec3<Real>>& x, std::vector<Vec3<Real>>& out, double* pairEnergy) {
        out.resize(x.size());
        parallelFor(m_threads, int64_t(x.size()), [&](int64_t i) {
            out[size_t(i)] = accelerationOf(i, x, pairEnergy ? &pairEnergy[i] : nullptr);
        });
    }

    // Runs `stages` RK stages from (m_x, m_v) and leaves the solution in (m_xStage, m_vStage).
    void rkStep(Real dt, int stages) {
        const size_t n = m_x.size();
        m_kx.resize(size_t(m_tableau.stages) * n);
        m_kv.resize(size_t(m_tableau.stages) * n);
        m_xStage.resize(n);
        m_vStage.resize(n);
        for (int s = 0; s < stages; ++s) {
            parallelFor(m_threads, int64_t(n), [&](int64_t i) {
                m_xStage[size_t(i)] = rkCombine(m_tableau.a[s], s, dt, m_x[size_t(i)], m_kx.data(), n, size_t(i));
                m_vStage[size_t(i)] = rkCombine(m_tableau.a[s], s, dt, m_v[size_t(i)], m_kv.data(), n, size_t(i));
                m_kx[size_t(s) * n + size_t(i)] = m_vStage[size_t(i)];
            });
            accelerations(m_xStage, m_scratchAcceleration, nullptr);
            std::copy(m_scratchAcceleration.begin(), m_scratchAcceleration.end(), m_kv.begin() + long(size_t(s) * n));
        }
        parallelFor(m_threads, int64_t(n), [&](int64_t i) {
            m_xStage[size_t(i)] = rkCombine(m_tableau.b, stages, dt, m_x[size_t(i)], m_kx.data(), n, size_t(i));
            m_vStage[size_t(i)] = rkCombine(m_tableau.b, stages, dt, m_v[size_t(i)], m_kv.data(), n, size_t(i));
        });
    }

    // Embedded-pair step with the standard controller (Hairer, Norsett & Wanner I, II.4).
    void adaptiveRkStep(StepReport& report) {
        const size_t n = m_x.size();
        const double tol = m_params.integrator.tolerance;
        const double exponent = -1.0 / double(m_tableau.embeddedOrder + 1);
        double dt = m_dtNext;
        for (int attempt = 0;; ++attempt) {
            rkStep(Real(dt), m_tableau.stages);
            const double errorSum = deterministicSum<double>(m_threads, int64_t(n), [&](int64_t i) {
                const Vec3<Real> ex = rkCombine(m_tableau.bError, m_tableau.stages, Real(dt), Vec3<Real>{0, 0, 0},
                                                m_kx.data(), n, size_t(i));
                const Vec3<Real> ev = rkCombine(m_tableau.bError, m_tableau.stages, Real(dt), Vec3<Real>{0, 0, 0},
                                                m_kv.data(), n, size_t(i));
                double e = 0;
                for (int a = 0; a < 3; ++a) {
                    e += scaledErrorSquared(ex[a], m_x[size_t(i)][a], m_xStage[size_t(i)][a], tol);
                    e += scaledErrorSquared(ev[a], m_v[size_t(i)][a], m_vStage[size_t(i)][a], tol);
                }
                return e;
            });
            const double error = std::sqrt(errorSum / double(6 * std::max<size_t>(n, 1)));
            const double factor = std::isfinite(error) ? std::clamp(0.9 * std::pow(std::max(error, 1e-10), exponent), 0.2, 5.0) : 0.2;
            if (error <= 1.0) {
                report.dt = dt;
                report.rejectedSteps = attempt;
                m_dtNext = dt * factor;
                std::swap(m_x, m_xStage);
                std::swap(m_v, m_vStage);
                return;
            }
            dt *= factor;
            if (attempt >= 60 || dt < 1e-12 * m_params.integrator.dt) {
                throw InstabilityError("adaptive dp5 could not meet tolerance " + std::to_string(tol) +
                                       ": step size fell to " + std::to_string(dt) + " after " +
                                       std::to_string(attempt + 1) + " rejected attempts");
            }
        }
    }

    void verletStep(Real dt) {
        const int64_t n = int64_t(m_x.size());
        if (!m_accelerationValid) accelerations(m_x, m_acceleration, nullptr);
        const Real half = Real(0.5) * dt;
        parallelFor(m_threads, n, [&](int64_t i) {
            verletKick(m_v[size_t(i)], m_acceleration[size_t(i)], half);
            verletDrift(m_x[size_t(i)], m_v[size_t(i)], dt);
        });
        accelerations(m_x, m_acceleration, nullptr);
        parallelFor(m_threads, n, [&](int64_t i) { verletKick(m_v[size_t(i)], m_acceleration[size_t(i)], half); });
        m_accelerationValid = true;
    }

    // ---- a posteriori collision resolution in parallel rounds (DESIGN.md sec. 2) ----

    // Earliest event of particle i against its grid neighbours; `checkAll` false restricts the pair
    // search to active partners (a pair of inactive particles cannot have started overlapping).
    Event earliestEvent(int64_t i, bool checkAll, const std::vector<char>& active) const {
        Event best;
        const Vec3<Real> xi = m_x[size_t(i)], vi = m_v[size_t(i)];
        const Real ai = m_radius[size_t(m_species[size_t(i)])];
        const Real slack = contactSlack<Real>();
        m_grid.forNeighbours(xi, [&](int64_t j) {
            if (j == i || !(checkAll || active[size_t(j)])) return;
            const Real d = ai + m_radius[size_t(m_species[size_t(j)])];
            const Vec3<Real> r = xi - m_x[size_t(j)];
            if (norm2(r) >= d * d * (Real(1) - slack)) return;
            const Real s = contactRewindTime(r, vi - m_v[size_t(j)], d);
            const Event e{s >= Real(0) ? double(s) : Event::kFixKey, j};
            if (e.betterThan(best)) best = e;
        });
        for (int axis = 0; axis < 3; ++axis) {
            for (int side = 0; side < 2; ++side) {
                const Real pos = side == 0 ? xi[axis] + slack * std::max(ai, Real(1)) : xi[axis] - slack * std::max(ai, Real(1));
                const Real s = wallRewindTime(pos, vi[axis], ai, m_boxLength[axis], side);
                if (s == Real(-2)) continue;
                const Event e{s >= Real(0) ? double(s) : Event::kFixKey, wallCode(axis, side)};
                if (e.betterThan(best)) best = e;
            }
        }
        return best;
    }

    void resolveCollisions(StepReport& report) {
        const int64_t n = int64_t(m_x.size());
        const Real eParticle = Real(m_params.interaction.restitution);
        const Real eWall = Real(m_params.box.wallRestitution);
        const Real elasticBelow = Real(m_params.interaction.elasticBelowSpeed);
        m_events.resize(size_t(n));
        m_loss.assign(size_t(n), 0.0);
        m_contactAcceleration.resize(size_t(n));
        m_hasContactAcceleration.assign(size_t(n), 0);
        std::vector<char> active(size_t(n), 1);
        std::vector<int64_t> kind(size_t(n), 0);  // 0 none, 1 pair impulse, 2 wall, 3 fix
        const double reach = 2.0 * double(*std::max_element(m_radius.begin(), m_radius.end()));
        for (int round = 0; round < m_params.interaction.maxCollisionRounds; ++round) {
            m_grid.build(m_x, m_boxLength, reach);
            // Every particle's earliest event: active particles look at all neighbours, inactive
            // ones only at active neighbours.
            parallelForDynamic(m_threads, n, [&](int64_t i) {
                m_events[size_t(i)] = earliestEvent(i, active[size_t(i)] != 0, active);
            });
            report.rounds = round + 1;
            // End-of-step accelerations of the particles about to be resolved (second-order rewind).
            m_needAcceleration.clear();
            for (int64_t i = 0; i < n; ++i) {
                if (m_events[size_t(i)].valid() && !m_hasContactAcceleration[size_t(i)]) m_needAcceleration.push_back(i);
            }
            parallelFor(m_threads, int64_t(m_needAcceleration.size()), [&](int64_t k) {
                const int64_t i = m_needAcceleration[size_t(k)];
                m_contactAcceleration[size_t(i)] = accelerationOf(i, m_x, nullptr);
                m_hasContactAcceleration[size_t(i)] = 1;
            });
            // Resolve every event that is the earliest of each particle it touches: a matching, so
            // the updates below never write the same particle twice.
            std::fill(kind.begin(), kind.end(), 0);
            parallelFor(m_threads, n, [&](int64_t i) {
                const Event e = m_events[size_t(i)];
                if (!e.valid()) return;
                if (e.partner >= 0) {
                    const int64_t j = e.partner;
                    if (j < i || m_events[size_t(j)].partner != i) return;
                    kind[size_t(i)] = resolvePair(i, j, e.key, eParticle, elasticBelow, &m_loss[size_t(i)]);
                } else {
                    const int code = int(-1 - e.partner);
                    kind[size_t(i)] = resolveWall(i, code / 2, code % 2, e.key, eWall, elasticBelow, &m_loss[size_t(i)]);
                }
            });
            bool anyEvent = false;
            for (int64_t i = 0; i < n; ++i) {
                const Event e = m_events[size_t(i)];
                active[size_t(i)] = e.valid();  // resolved now or still pending: look again next round
                anyEvent = anyEvent || e.valid();
                switch (kind[size_t(i)]) {
                    case 1: ++report.pairCollisions; break;
                    case 2: ++report.wallCollisions; break;
                    case 3: ++report.positionalFixes; break;
                    default: break;
                }
            }
            if (!anyEvent) {
                report.dissipated = sumLoss();
                return;
            }
        }
        // The cap was reached; see whether anything is still left.
        m_grid.build(m_x, m_boxLength, reach);
        std::fill(active.begin(), active.end(), 1);
        for (int64_t i = 0; i < n && !report.roundCapHit; ++i) {
            if (earliestEvent(i, true, active).valid()) report.roundCapHit = true;
        }
        report.dissipated = sumLoss();
    }

    double sumLoss() const {
        double total = 0;
        for (double l : m_loss) total += l;
        return total;
    }

    // Rewind i and j to contact, apply the impulse, move forward again. Returns the event kind.
    int resolvePair(int64_t i, int64_t j, double key, Real e, Real elasticBelow, double* loss) {
        Vec3<Real>& xi = m_x[size_t(i)];
        Vec3<Real>& xj = m_x[size_t(j)];
        Vec3<Real>& vi = m_v[size_t(i)];
        Vec3<Real>& vj = m_v[size_t(j)];
        const Real mi = m_mass[size_t(m_species[size_t(i)])], mj = m_mass[size_t(m_species[size_t(j)])];
        const Real d = m_radius[size_t(m_species[size_t(i)])] + m_radius[size_t(m_species[size_t(j)])];
        if (key == Event::kFixKey) {
            // Overlapping but separating: push apart along the line of centres, heavier moves less.
            const Vec3<Real> r = xi - xj;
            const Real dist = std::sqrt(norm2(r));
            const Vec3<Real> nrm = dist > Real(0) ? (Real(1) / dist) * r : Vec3<Real>{1, 0, 0};
            const Real gap = d - dist;
            xi += (gap * mj / (mi + mj)) * nrm;
            xj -= (gap * mi / (mi + mj)) * nrm;
            return 3;
        }
        const Vec3<Real> ai = m_contactAcceleration[size_t(i)], aj = m_contactAcceleration[size_t(j)];
        const Real s = parabolicContactRewindTime(xi - xj, vi - vj, ai - aj, d, Real(key));
        const Real halfS2 = Real(0.5) * s * s;
        xi += halfS2 * ai - s * vi;  // back to contact along each parabola
        xj += halfS2 * aj - s * vj;
        vi -= s * ai;
        vj -= s * aj;
        const Vec3<Real> r = xi - xj;
        const Vec3<Real> nrm = (Real(1) / std::sqrt(norm2(r))) * r;
        const Real mu = mi * mj / (mi + mj);
        const Real vn = dot(vi - vj, nrm);
        if (vn < Real(0)) {
            const Real eEff = effectiveRestitution(e, vn, elasticBelow);
            const Real impulse = collisionImpulse(mu, vn, eEff);
            vi += (impulse / mi) * nrm;
            vj -= (impulse / mj) * nrm;
            *loss += double(collisionEnergyLoss(mu, vn, eEff));
        }
        xi += s * vi + halfS2 * ai;  // and forward to the end of the step
        xj += s * vj + halfS2 * aj;
        vi += s * ai;
        vj += s * aj;
        // Resting contact: when the relative acceleration presses the pair together faster than
        // the rebound separates it, they end the step still overlapping. Put them at contact and
        // remove the closing normal velocity instead of colliding again. The energy this takes out
        // (kinetic, minus the work done lifting the pair apart against the pressing force, to
        // first order in the small gap) is counted as dissipated, so the balance stays exact.
        const Vec3<Real> rEnd = xi - xj;
        const Real distEnd = std::sqrt(norm2(rEnd));
        if (distEnd < d * (Real(1) - contactSlack<Real>())) {
            const Vec3<Real> nEnd = distEnd > Real(0) ? (Real(1) / distEnd) * rEnd : nrm;
            const Real gap = d - distEnd;
            xi += (gap * mj / (mi + mj)) * nEnd;
            xj -= (gap * mi / (mi + mj)) * nEnd;
            *loss += double(mu * dot(ai - aj, nEnd) * gap);
            const Real closing = dot(vi - vj, nEnd);
            if (closing < Real(0)) {
                const Real impulse = collisionImpulse(mu, closing, Real(0));
                vi += (impulse / mi) * nEnd;
                vj -= (impulse / mj) * nEnd;
                *loss += double(collisionEnergyLoss(mu, closing, Real(0)));
            }
        }
        return 1;
    }

    int resolveWall(int64_t i, int axis, int side, double key, Real e, Real elasticBelow, double* loss) {
        Vec3<Real>& x = m_x[size_t(i)];
        Vec3<Real>& v = m_v[size_t(i)];
        const Real a = m_radius[size_t(m_species[size_t(i)])];
        const Real wall = side == 0 ? a : m_boxLength[axis] - a;
        if (key == Event::kFixKey) {
            x[axis] = wall;
            return 3;
        }
        // Normal coordinate pointing into the box: p = distance from the wall plane, vn, an.
        const Real sign = side == 0 ? Real(1) : Real(-1);
        const Real p = sign * (x[axis] - wall);
        const Real vIn = sign * v[axis];
        const Real aIn = sign * m_contactAcceleration[size_t(i)][axis];
        const Real s = parabolicWallRewindTime(p, vIn, aIn, Real(key));
        const Real vContact = vIn - aIn * s;
        const Real m = m_mass[size_t(m_species[size_t(i)])];
        const Real eEff = effectiveRestitution(e, vContact, elasticBelow);
        const Real vOut = vContact < Real(0) ? -eEff * vContact : vContact;
        if (vContact < Real(0)) *loss += double(collisionEnergyLoss(m, vContact, eEff));
        Real pEnd = vOut * s + Real(0.5) * aIn * s * s;
        Real vEnd = vOut + aIn * s;
        if (pEnd < Real(0)) {
            // Resting contact: pressed onto the wall harder than it rebounds. It stays on the wall
            // and an inward normal velocity is absorbed. Dissipated: that kinetic energy minus the
            // work of lifting it by -pEnd against the pressing acceleration.
            *loss -= double(m * aIn * pEnd);
            pEnd = 0;
            if (vEnd < Real(0)) {
                *loss += double(Real(0.5) * m * vEnd * vEnd);
                vEnd = 0;
            }
        }
        x[axis] = wall + sign * pEnd;
        v[axis] = sign * vEnd;
        return 2;
    }

    int m_threads;
    StepParameters m_params;
    ButcherTableau m_tableau;
    std::vector<PairCoefficients<Real>> m_pairs;
    bool m_anyPairForce = true;
    std::vector<Real> m_mass, m_invMass, m_radius;
    Vec3<Real> m_gravity{0, 0, 0};
    Vec3<Real> m_boxLength{0, 0, 0};
    double m_dtNext = 0;

    std::vector<Vec3<Real>> m_x, m_v;
    std::vector<int32_t> m_species;
    std::vector<Vec3<Real>> m_acceleration, m_scratchAcceleration;
    bool m_accelerationValid = false;
    std::vector<Vec3<Real>> m_kx, m_kv, m_xStage, m_vStage;
    std::vector<Event> m_events;
    std::vector<Vec3<Real>> m_contactAcceleration;
    std::vector<char> m_hasContactAcceleration;
    std::vector<int64_t> m_needAcceleration;
    ContactGrid<Real> m_grid;
    std::vector<double> m_loss;
    std::vector<Vec3<Real>> m_snapshotX, m_snapshotV;
};

}  // namespace

std::unique_ptr<Backend> makeCpuBackend(const CpuBackendOptions& options) {
    if (options.precision == Precision::Fp32) return std::make_unique<CpuBackendImpl<float>>(options);
    return std::make_unique<CpuBackendImpl<double>>(options);
}

}  // namespace corebox
