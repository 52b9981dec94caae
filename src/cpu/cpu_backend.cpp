#include "cpu_backend.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "butcher_tableau.h"
#include "collision_resolution.h"
#include "cpu_parallel.h"
#include "energy_terms.h"
#include "errors.h"
#include "host_cell_list.h"
#include "host_info.h"
#include "maxwell_boltzmann.h"
#include "pair_table.h"
#include "rk_stage.h"
#include "speed_statistics.h"
#include "step_driver.h"

namespace corebox {
namespace {

template <class Real>
class CpuBackendImpl final : public Backend {
public:
    explicit CpuBackendImpl(const CpuBackendOptions& options)
        : m_threads(options.threads > 0 ? options.threads : omp_get_max_threads()) {}

    std::string name() const override { return "cpu"; }
    std::string deviceName() const override { return cpuModelName() + " (" + std::to_string(m_threads) + " threads)"; }
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
        using Clock = std::chrono::steady_clock;
        m_forceSeconds = 0;
        const Clock::time_point start = Clock::now();
        integrateStep(*this, m_params.integrator, m_tableau, m_dtNext, report);
        const Clock::time_point integrated = Clock::now();
        resolveCollisions(report);
        report.secondsForces = m_forceSeconds;
        report.secondsIntegrate = std::chrono::duration<double>(integrated - start).count() - m_forceSeconds;
        report.secondsCollide = std::chrono::duration<double>(Clock::now() - integrated).count();
        // Collisions move particles and change velocities: the cached Verlet acceleration is only
        // reusable when nothing was touched.
        if (report.pairCollisions + report.wallCollisions + report.positionalFixes > 0) m_accelerationValid = false;
        return report;
    }

    double kineticEnergy() override {
        return deterministicSum<double>(m_threads, int64_t(m_x.size()), [&](int64_t i) {
            return kineticEnergyOf(double(m_mass[m_species[i]]), vec3Cast<double>(m_v[i]));
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
            p.potential = 0.5 * pairEnergy[size_t(i)] + gravityPotentialOf(m, vec3Cast<double>(m_gravity), x);
            p.momentum = m * v;
            p.kinetic.assign(s, 0.0);
            p.kinetic[size_t(sp)] = kineticEnergyOf(m, v);
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
        const auto start = std::chrono::steady_clock::now();
        out.resize(x.size());
        parallelFor(m_threads, int64_t(x.size()), [&](int64_t i) {
            out[size_t(i)] = accelerationOf(i, x, pairEnergy ? &pairEnergy[i] : nullptr);
        });
        m_forceSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }

public:
    // ---- hooks of integrateStep (src/core/step_driver.h) ----

    // Runs `stages` RK stages from (m_x, m_v) and leaves the solution in (m_xStage, m_vStage).
    void rkStep(double dtStep, int stages) {
        const Real dt = Real(dtStep);
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

    void acceptStage() {
        std::swap(m_x, m_xStage);
        std::swap(m_v, m_vStage);
    }

    // RMS over all components of the embedded error scaled by the tolerance.
    double embeddedError(double dt, double tolerance) {
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

    void verletStep(double dtStep) {
        const Real dt = Real(dtStep);
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

private:
    // ---- a posteriori collision resolution in parallel rounds (DESIGN.md sec. 2) ----

    // Earliest event of particle i against its grid neighbours; `checkAll` false restricts the pair
    // search to active partners (a pair of inactive particles cannot have started overlapping).
    CollisionEvent earliestEvent(int64_t i, bool checkAll, const std::vector<char>& active) const {
        CollisionEvent best = noEvent();
        const Vec3<Real> xi = m_x[size_t(i)], vi = m_v[size_t(i)];
        const Real ai = m_radius[size_t(m_species[size_t(i)])];
        m_grid.forNeighbours(xi, [&](int64_t j) {
            if (j == i || !(checkAll || active[size_t(j)])) return;
            considerPair(xi, vi, ai, m_x[size_t(j)], m_v[size_t(j)], m_radius[size_t(m_species[size_t(j)])], j, best);
        });
        considerWalls(xi, vi, ai, m_boxLength, best);
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
                if (isValid(m_events[size_t(i)]) && !m_hasContactAcceleration[size_t(i)]) m_needAcceleration.push_back(i);
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
                const CollisionEvent e = m_events[size_t(i)];
                if (!isValid(e)) return;
                const int si = m_species[size_t(i)];
                if (e.partner >= 0) {
                    const int64_t j = e.partner;
                    if (j < i || m_events[size_t(j)].partner != i) return;
                    const int sj = m_species[size_t(j)];
                    kind[size_t(i)] = resolvePairEvent(m_x[size_t(i)], m_v[size_t(i)], m_contactAcceleration[size_t(i)], m_mass[size_t(si)],
                                                       m_x[size_t(j)], m_v[size_t(j)], m_contactAcceleration[size_t(j)], m_mass[size_t(sj)],
                                                       m_radius[size_t(si)] + m_radius[size_t(sj)], e.key, eParticle, elasticBelow,
                                                       &m_loss[size_t(i)]);
                } else {
                    const int code = int(-1 - e.partner), axis = code / 2;
                    kind[size_t(i)] = resolveWallEvent(m_x[size_t(i)][axis], m_v[size_t(i)][axis], m_contactAcceleration[size_t(i)][axis],
                                                       m_mass[size_t(si)], m_radius[size_t(si)], m_boxLength[axis], code % 2, e.key, eWall,
                                                       elasticBelow, &m_loss[size_t(i)]);
                }
            });
            bool anyEvent = false;
            for (int64_t i = 0; i < n; ++i) {
                const bool valid = isValid(m_events[size_t(i)]);
                active[size_t(i)] = valid;  // resolved now or still pending: look again next round
                anyEvent = anyEvent || valid;
                switch (kind[size_t(i)]) {
                    case kPairCollision: ++report.pairCollisions; break;
                    case kWallCollision: ++report.wallCollisions; break;
                    case kPositionalFix: ++report.positionalFixes; break;
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
            if (isValid(earliestEvent(i, true, active))) report.roundCapHit = true;
        }
        report.dissipated = sumLoss();
    }

    double sumLoss() const {
        double total = 0;
        for (double l : m_loss) total += l;
        return total;
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
    double m_forceSeconds = 0;  // force passes of the current step

    std::vector<Vec3<Real>> m_x, m_v;
    std::vector<int32_t> m_species;
    std::vector<Vec3<Real>> m_acceleration, m_scratchAcceleration;
    bool m_accelerationValid = false;
    std::vector<Vec3<Real>> m_kx, m_kv, m_xStage, m_vStage;
    std::vector<CollisionEvent> m_events;
    std::vector<Vec3<Real>> m_contactAcceleration;
    std::vector<char> m_hasContactAcceleration;
    std::vector<int64_t> m_needAcceleration;
    CellList m_grid;
    std::vector<double> m_loss;
    std::vector<Vec3<Real>> m_snapshotX, m_snapshotV;
};

}  // namespace

std::unique_ptr<Backend> makeCpuBackend(const CpuBackendOptions& options) {
    if (options.precision == Precision::Fp32) return std::make_unique<CpuBackendImpl<float>>(options);
    return std::make_unique<CpuBackendImpl<double>>(options);
}

}  // namespace corebox
