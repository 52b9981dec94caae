// The CPU list pass (src/cpu/list_forces.h): its AVX2 rows (list_row_simd.h) give the scalar loop's
// bits, in both precisions, with and without pair energies and the collision screen, for each cutoff
// shift, on lists split into two chunks (pairs across them taken by the partner's chunk).
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "list_forces.h"

namespace corebox {
namespace {

template <class Real>
struct PassResult {
    std::vector<Vec3<Real>> acceleration;
    std::vector<double> energy;
    ListScreen screen;
};

template <class Real, bool kEnergy>
PassResult<Real> runPass(const std::vector<Vec3<Real>>& x, const Vec3<Real>& box, const PairCoefficients<Real>& pair, bool simd) {
    const int64_t n = int64_t(x.size());
    VerletList<Real> list;
    list.update(x, box, 2.5, 0.3, 2);
    const std::vector<int32_t> species(x.size(), 0);
    const Real invMass = Real(1);
    const Vec3<Real> field{0, 0, Real(-0.5)};
    ListPassInputs<Real> in{x.data(), species.data(), &pair, 1, &invMass, &field, 2};
    in.simd = simd;
    ListScreenReach<Real> reach;
    reach.inverseReach2 = {Real(1) / Real(0.81)};
    reach.wallReach = {Real(0.45)};
    reach.box = box;
    ListPassScratch<Real> scratch;
    PassResult<Real> r;
    r.acceleration.resize(x.size());
    r.energy.resize(x.size());
    r.screen = listForcePass<Real, kEnergy, true>(list, in, scratch, n, r.acceleration.data(), kEnergy ? r.energy.data() : nullptr, &reach);
    return r;
}

template <class Real>
void expectScalarBits() {
    std::mt19937 random(7);
    const Vec3<Real> box{Real(15), Real(13), Real(17)};
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<Vec3<Real>> x(2600);  // number density ~0.78, random: some pairs close, rows of every length
    for (Vec3<Real>& p : x) p = Vec3<Real>{Real(unit(random) * box.x), Real(unit(random) * box.y), Real(unit(random) * box.z)};
    for (CutoffShift shift : {CutoffShift::None, CutoffShift::Energy, CutoffShift::Force}) {
        double energyShift = 0, forceAtCutoff = 0;
        computeCutoffShift(1.0, 4.0, 0.8, 2.5, shift, &energyShift, &forceAtCutoff);
        PairCoefficients<Real> pair;
        pair.sigma2 = Real(1);
        pair.eps4 = Real(4);
        pair.mixing = Real(0.8);
        pair.cutoff2 = Real(6.25);
        pair.cutoff = Real(2.5);
        pair.energyShift = Real(energyShift);
        pair.forceAtCutoff = Real(forceAtCutoff);
        pair.shift = int(shift);
        const auto bits = [](const auto& v) { return std::vector<unsigned char>(reinterpret_cast<const unsigned char*>(v.data()),
                                                                                reinterpret_cast<const unsigned char*>(v.data() + v.size())); };
        {
            const PassResult<Real> simd = runPass<Real, true>(x, box, pair, true), scalar = runPass<Real, true>(x, box, pair, false);
            EXPECT_EQ(bits(simd.acceleration), bits(scalar.acceleration)) << "with energies, shift " << int(shift);
            EXPECT_EQ(bits(simd.energy), bits(scalar.energy)) << "shift " << int(shift);
            EXPECT_EQ(simd.screen.nearest, scalar.screen.nearest);
            EXPECT_GT(simd.screen.nearest, 0.0);
        }
        const PassResult<Real> simd = runPass<Real, false>(x, box, pair, true), scalar = runPass<Real, false>(x, box, pair, false);
        EXPECT_EQ(bits(simd.acceleration), bits(scalar.acceleration)) << "shift " << int(shift);
        EXPECT_EQ(simd.screen.nearest, scalar.screen.nearest);
    }
}

TEST(ListPass, SimdRowsGiveTheScalarBits) {
    if (!simdListRowsAvailable()) GTEST_SKIP() << "this CPU has no AVX2: the list pass runs its scalar rows only";
    expectScalarBits<double>();
    expectScalarBits<float>();
}

}  // namespace
}  // namespace corebox
