// Butcher tables (kernels/butcher_tableau.*) against every Runge-Kutta order condition up to each method's order.
//
// Design note
// - An explicit method (A, b, c) has order p iff  sum_i b_i Phi_i(t) = 1/gamma(t)  for every rooted tree t with
//   |t| <= p (Butcher 1963; Hairer, Norsett & Wanner, Solving ODEs I, sec. II.2). The quadrature conditions
//   b.c^k = 1/(k+1) are only the bushy trees: 10 of the 1205 conditions of order 10.
// - Trees are generated, not typed in: a tree of order n is a root whose children are a multiset of smaller trees
//   with orders summing to n-1. Writing the children as a non-increasing list of indices into the trees built so far
//   gives each multiset, hence each tree, exactly once. The counts per order are asserted (OEIS A000081) and so are
//   two labelling identities that tie the density gamma and the symmetry sigma to the tree set: a generator that
//   drops, repeats or mis-weighs trees fails here instead of weakening the order checks.
// - Phi_i(t) = prod_{u child of t} sum_j a_ij Phi_j(u) and gamma(t) = |t| prod gamma(u). c therefore enters only as
//   the row sums of A (Phi of the one-node tree is 1, so A Phi of it is c); the stored c is checked against those
//   row sums separately.
// - Arithmetic in Real: __float128 (113-bit significand, eps 1.9e-34) where the compiler has it, long double
//   otherwise. Only libgcc's arithmetic is used (no libquadmath), so the test needs no extra library.
// - Two coefficient sources:
//   * the double tables the integrators run (every method). Their residuals are the rounding of the coefficients
//     to double, so the tolerance is a double-rounding one (kDoubleTableTolerance);
//   * Hairer's table as published: ~80 significant digits per entry in kernels/hairer10_tableau.tsv, parsed here
//     straight into Real. Its residuals are Real rounding only, so this is the check of the table itself, far
//     below double; the double table is also checked to be the correctly rounded TSV, entry by entry.
// - "Order p" must also be exact: every method fails some condition of order p+1 by far more than its tolerance,
//   which also shows that these checks can fail.
#include <gtest/gtest.h>

#include <cfloat>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "butcher_tableau.h"

namespace corebox {
namespace {

#if defined(__SIZEOF_FLOAT128__)
using Real = __float128;
constexpr double kRealEpsilon = 1.925929944387235853055977942584927319e-34;  // 2^-112
#else
using Real = long double;
constexpr double kRealEpsilon = LDBL_EPSILON;
#endif

// Tolerances on |b.Phi(t) - 1/gamma(t)|, absolute (1/gamma(t) itself ranges from 1 down to 1/10! = 2.8e-7).
// - Double tables: each coefficient carries a relative rounding of up to 2^-53 = 1.1e-16, and a condition is a sum
//   of products of coefficients of size up to ~12 (DP5) with cancellation, so its residual is a few 1e-16; measured
//   worst: 8.3e-16 (DP5), 6.9e-16 (DP5 embedded), 2.2e-17 (Hairer). 1e-13 is ~100 times that, and still ~1e7 below
//   the smallest order p+1 defect (Hairer's, 3.6e-6).
// - Hairer's table in Real: a condition of order k has up to 17^(k-1) terms mathematically, but the recursion
//   evaluates it as k nested dot products of at most 17 terms, so rounding grows like ~k * 17 * eps, not 17^k;
//   measured worst: 9.6e-35 in __float128 (eps 1.9e-34), 6.1e-20 in 80-bit long double (eps 1.1e-19). 1e4 * eps
//   (1.9e-30, or 1.1e-15 for long double) leaves that margin while still catching an error in the 30th digit of one
//   coefficient, where double-rounded coefficients (residuals ~1e-17) could not see anything past the 16th.
constexpr double kDoubleTableTolerance = 1e-13;
constexpr double kHairerTsvTolerance = 1e4 * kRealEpsilon;
// An order p+1 condition counts as failed when its residual exceeds this: far above both tolerances, and far below
// the worst order p+1 defect of every method here (the smallest: 3.6e-6, Hairer's at order 11).
constexpr double kOrderDefectThreshold = 1e-8;

constexpr int kMaxTreeOrder = 11;  // order 10 for Hairer's method plus one to show it is not order 11

double toDouble(Real x) { return double(x); }
Real absReal(Real x) { return x < 0 ? -x : x; }

std::string formatDouble(double x, const char* format = "%.3e") {
    char text[40];
    std::snprintf(text, sizeof text, format, x);
    return text;
}

std::string roundTrip(double x) { return formatDouble(x, "%.17g"); }

// ---- rooted trees ----------------------------------------------------------------------------------------------

struct RootedTree {
    int order = 1;
    std::uint64_t gamma = 1;    // density: |t| times the densities of the children
    std::uint64_t sigma = 1;    // symmetry: order of the automorphism group
    std::vector<int> children;  // indices into the tree list, non-increasing
};

// All rooted trees of order 1..maxOrder, sorted by order; each tree appears once.
class RootedTrees {
public:
    explicit RootedTrees(int maxOrder) {
        m_trees.push_back(RootedTree{});  // the single node
        m_firstOfOrder = {0, 0, 1};       // m_firstOfOrder[n]: index of the first tree of order n (sentinel at n+1)
        for (int n = 2; n <= maxOrder; ++n) {
            std::vector<int> children;
            addTreesWithChildren(n, n - 1, int(m_trees.size()) - 1, children);
            m_firstOfOrder.push_back(int(m_trees.size()));
        }
    }

    const std::vector<RootedTree>& trees() const { return m_trees; }
    int countOfOrder(int n) const { return m_firstOfOrder[n + 1] - m_firstOfOrder[n]; }

    // Bracket notation for messages: "t" is a single node, [u v] a root with children u and v.
    std::string describe(int index) const {
        const RootedTree& tree = m_trees[index];
        if (tree.children.empty()) return "t";
        std::string text = "[";
        for (int child : tree.children) text += describe(child);
        return text + "]";
    }

private:
    // Extends `children` by trees of index <= maxChild (so the list stays non-increasing) whose orders sum to
    // `remaining`, and appends one tree of order `order` for each complete list.
    void addTreesWithChildren(int order, int remaining, int maxChild, std::vector<int>& children) {
        if (remaining == 0) {
            m_trees.push_back(makeTree(order, children));
            return;
        }
        for (int child = maxChild; child >= 0; --child) {
            if (m_trees[child].order > remaining) continue;
            children.push_back(child);
            addTreesWithChildren(order, remaining - m_trees[child].order, child, children);
            children.pop_back();
        }
    }

    RootedTree makeTree(int order, const std::vector<int>& children) const {
        RootedTree tree;
        tree.order = order;
        tree.children = children;
        tree.gamma = std::uint64_t(order);
        // sigma(t) = prod over distinct children u of sigma(u)^m * m!, m the multiplicity of u. Equal children are
        // adjacent (the list is sorted), and the m-th copy of u multiplies in sigma(u) and the factor m of m!.
        std::uint64_t copies = 0;
        for (std::size_t k = 0; k < children.size(); ++k) {
            const RootedTree& child = m_trees[children[k]];
            copies = (k > 0 && children[k] == children[k - 1]) ? copies + 1 : 1;
            tree.gamma *= child.gamma;
            tree.sigma *= child.sigma * copies;
        }
        return tree;
    }

    std::vector<RootedTree> m_trees;
    std::vector<int> m_firstOfOrder;
};

const RootedTrees& allTrees() {
    static const RootedTrees trees(kMaxTreeOrder);
    return trees;
}

// ---- tables in Real --------------------------------------------------------------------------------------------

struct RealTableau {
    std::string name;
    int stages = 0;
    std::vector<std::vector<Real>> a;
    std::vector<Real> b;
    std::vector<Real> c;  // as stored; the conditions use the row sums of a instead
};

RealTableau fromDoubleTable(const std::string& name, const ButcherTableau& t, const double* weights) {
    RealTableau r;
    r.name = name;
    r.stages = t.stages;
    r.a.assign(t.stages, std::vector<Real>(t.stages, 0));
    r.b.assign(t.stages, 0);
    r.c.assign(t.stages, 0);
    for (int i = 0; i < t.stages; ++i) {
        for (int j = 0; j < t.stages; ++j) r.a[i][j] = t.a[i][j];
        r.b[i] = weights[i];
        r.c[i] = t.c[i];
    }
    return r;
}

// Decimal text ("-.123e-1", "1.") to Real without strtold's 64-bit or strtod's 53-bit rounding: the integer part by
// Horner (exact below 10^33), the fraction from its last digit back as f = (f + d) / 10, where each step's rounding
// is divided by 10 by every later step, so the result is within a few ulp of Real (exponents here are e-1 to e-3).
bool parseDecimal(const std::string& text, Real* value) {
    std::size_t k = 0;
    const bool negative = k < text.size() && text[k] == '-';
    if (k < text.size() && (text[k] == '-' || text[k] == '+')) ++k;
    Real integer = 0;
    int digits = 0;
    for (; k < text.size() && text[k] >= '0' && text[k] <= '9'; ++k, ++digits) integer = integer * 10 + (text[k] - '0');
    std::size_t fractionBegin = k, fractionEnd = k;
    if (k < text.size() && text[k] == '.') {
        fractionBegin = ++k;
        while (k < text.size() && text[k] >= '0' && text[k] <= '9') ++k;
        fractionEnd = k;
        digits += int(fractionEnd - fractionBegin);
    }
    Real fraction = 0;
    for (std::size_t m = fractionEnd; m > fractionBegin; --m) fraction = (fraction + (text[m - 1] - '0')) / 10;
    int exponent = 0;
    if (k < text.size() && (text[k] == 'e' || text[k] == 'E')) {
        char* end = nullptr;
        exponent = int(std::strtol(text.c_str() + k + 1, &end, 10));
        k = std::size_t(end - text.c_str());
    }
    if (digits == 0 || k != text.size()) return false;
    Real x = integer + fraction;
    for (; exponent > 0; --exponent) x *= 10;
    for (; exponent < 0; ++exponent) x /= 10;
    *value = negative ? -x : x;
    return true;
}

struct TsvEntry {
    char kind = 0;  // 'a', 'b' or 'c'
    int i = 0;      // 0-based
    int j = 0;      // 0-based; a only
    std::string text;
};

// The rows of kernels/hairer10_tableau.tsv (kind, i, j, value; 1-based; '#' comments), the file the build turns into
// the double table (cmake/GenerateTableau.cmake).
std::vector<TsvEntry> readHairerTsv() {
    const std::string path = std::string(COREBOX_SOURCE_DIR) + "/kernels/hairer10_tableau.tsv";
    std::ifstream in(path);
    EXPECT_TRUE(in.good()) << "cannot read " << path;
    std::vector<TsvEntry> entries;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream fields(line);
        std::string kind, i, j, value;
        std::getline(fields, kind, '\t');
        std::getline(fields, i, '\t');
        std::getline(fields, j, '\t');
        std::getline(fields, value, '\t');
        TsvEntry e;
        e.kind = kind.empty() ? 0 : kind[0];
        e.i = std::atoi(i.c_str()) - 1;
        e.j = kind == "a" ? std::atoi(j.c_str()) - 1 : 0;
        e.text = value;
        const bool inRange = e.i >= 0 && e.i < 17 && e.j >= 0 && e.j < 17;
        EXPECT_TRUE(kind.size() == 1 && (e.kind == 'a' || e.kind == 'b' || e.kind == 'c') && inRange) << line;
        if (inRange) entries.push_back(e);
    }
    return entries;
}

RealTableau hairerFromTsv(const std::vector<TsvEntry>& entries) {
    RealTableau r;
    r.name = "hairer10_tsv";
    r.stages = 17;
    r.a.assign(17, std::vector<Real>(17, 0));
    r.b.assign(17, 0);
    r.c.assign(17, 0);
    for (const TsvEntry& e : entries) {
        Real value = 0;
        EXPECT_TRUE(parseDecimal(e.text, &value)) << "not a number: " << e.text;
        if (e.kind == 'a') r.a[e.i][e.j] = value;
        if (e.kind == 'b') r.b[e.i] = value;
        if (e.kind == 'c') r.c[e.i] = value;
    }
    return r;
}

// ---- order conditions ------------------------------------------------------------------------------------------

// residual[k] = b.Phi(t_k) - 1/gamma(t_k) for every generated tree, up to order kMaxTreeOrder.
std::vector<Real> conditionResiduals(const RealTableau& t) {
    const std::vector<RootedTree>& trees = allTrees().trees();
    const int s = t.stages;
    // aPhi[k] = A Phi(t_k): the factor a tree contributes as a child of a larger one.
    std::vector<std::vector<Real>> aPhi(trees.size(), std::vector<Real>(s, 0));
    std::vector<Real> residuals(trees.size(), 0);
    std::vector<Real> phi(s);
    for (std::size_t k = 0; k < trees.size(); ++k) {
        for (int i = 0; i < s; ++i) {
            phi[i] = 1;
            for (int child : trees[k].children) phi[i] *= aPhi[child][i];
        }
        Real weighted = 0;
        for (int i = 0; i < s; ++i) {
            weighted += t.b[i] * phi[i];
            for (int j = 0; j < i; ++j) aPhi[k][i] += t.a[i][j] * phi[j];  // explicit: a_ij = 0 for j >= i
        }
        residuals[k] = weighted - Real(1) / Real(trees[k].gamma);
    }
    return residuals;
}

// Strictly lower-triangular A and stored c equal to the row sums of A.
void expectExplicitWithConsistentNodes(const RealTableau& t, double tolerance) {
    for (int i = 0; i < t.stages; ++i) {
        Real rowSum = 0;
        for (int j = 0; j < i; ++j) rowSum += t.a[i][j];
        for (int j = i; j < t.stages; ++j) {
            EXPECT_TRUE(t.a[i][j] == 0) << t.name << ": not explicit, a[" << i << "][" << j << "] != 0";
        }
        EXPECT_LE(toDouble(absReal(rowSum - t.c[i])), tolerance) << t.name << ": c[" << i << "] is not the row sum";
    }
}

// Every condition of order <= order holds to `tolerance`, some condition of order+1 fails by more than
// kOrderDefectThreshold; the worst residual up to `order` is recorded as a test property.
void expectExactOrder(const RealTableau& t, int order, double tolerance) {
    ASSERT_LT(order, kMaxTreeOrder);
    const RootedTrees& trees = allTrees();
    const std::vector<Real> residuals = conditionResiduals(t);
    double worst = 0, worstDefect = 0;
    int worstTree = 0, conditions = 0, failures = 0, defects = 0;
    std::string firstFailures;
    for (std::size_t k = 0; k < residuals.size(); ++k) {
        const int treeOrder = trees.trees()[k].order;
        const double r = toDouble(absReal(residuals[k]));
        if (treeOrder == order + 1) {
            if (r > worstDefect) worstDefect = r;
            if (r > kOrderDefectThreshold) ++defects;
        }
        if (treeOrder > order) continue;
        ++conditions;
        if (r > worst) {
            worst = r;
            worstTree = int(k);
        }
        if (r > tolerance && ++failures <= 5) {
            firstFailures += "\n  order " + std::to_string(treeOrder) + " tree " + trees.describe(int(k)) +
                             ": residual " + formatDouble(toDouble(residuals[k]));
        }
    }
    ::testing::Test::RecordProperty("worst_residual_" + t.name, formatDouble(worst));
    ::testing::Test::RecordProperty("worst_order_" + std::to_string(order + 1) + "_defect_" + t.name,
                                    formatDouble(worstDefect));
    EXPECT_EQ(failures, 0) << t.name << ": " << failures << " of " << conditions << " conditions up to order " << order
                           << " miss 1/gamma by more than " << tolerance << ", first:" << firstFailures;
    EXPECT_GT(worstDefect, kOrderDefectThreshold)
        << t.name << ": every order " << order + 1 << " condition holds, so the order is not exactly " << order;
    std::printf(
        "  %-14s order %2d: %4d conditions, worst residual %.3e (tree %s); order %d: %d of %d fail, by <= %.3e\n",
        t.name.c_str(), order, conditions, worst, trees.describe(worstTree).c_str(), order + 1, defects,
        trees.countOfOrder(order + 1), worstDefect);
}

// ---- tests -----------------------------------------------------------------------------------------------------

TEST(RootedTrees, CountsPerOrderAreOeisA000081) {
    const std::uint64_t expected[kMaxTreeOrder + 1] = {0, 1, 1, 2, 4, 9, 20, 48, 115, 286, 719, 1842};
    int upToTen = 0;
    for (int n = 1; n <= kMaxTreeOrder; ++n) {
        EXPECT_EQ(std::uint64_t(allTrees().countOfOrder(n)), expected[n]) << "trees of order " << n;
        if (n <= 10) upToTen += allTrees().countOfOrder(n);
    }
    EXPECT_EQ(upToTen, 1205);  // the conditions for order 10
}

// Counts alone would not catch a wrong gamma or a tree listed twice in place of another. Two classical identities
// over the trees of order n do: labellings sum_t n!/sigma(t) = n^(n-1) (Cayley, rooted labelled trees), and
// monotone labellings sum_t n!/(sigma(t) gamma(t)) = (n-1)! (increasing trees).
TEST(RootedTrees, SymmetryAndDensityGiveTheLabellingCounts) {
    std::uint64_t factorial = 1;
    for (int n = 1; n <= kMaxTreeOrder; ++n) {
        const std::uint64_t previousFactorial = factorial;  // (n-1)!
        factorial *= std::uint64_t(n);
        std::uint64_t cayley = 1;
        for (int k = 1; k < n; ++k) cayley *= std::uint64_t(n);
        std::uint64_t labelled = 0, monotone = 0;
        for (const RootedTree& tree : allTrees().trees()) {
            if (tree.order != n) continue;
            EXPECT_EQ(factorial % (tree.sigma * tree.gamma), 0u) << "order " << n;
            labelled += factorial / tree.sigma;
            monotone += factorial / (tree.sigma * tree.gamma);
        }
        EXPECT_EQ(labelled, cayley) << "order " << n;
        EXPECT_EQ(monotone, previousFactorial) << "order " << n;
    }
}

TEST(RootedTrees, BracketNotation) {
    const RootedTrees& trees = allTrees();
    EXPECT_EQ(trees.describe(0), "t");
    EXPECT_EQ(trees.describe(1), "[t]");
    EXPECT_EQ(trees.trees()[1].gamma, 2u);
}

TEST(ButcherTableau, ClassicalMethodsHaveExactlyTheirOrder) {
    const struct {
        Method method;
        const char* name;
        int order;
    } methods[] = {{Method::Euler, "euler", 1}, {Method::Rk2, "rk2_midpoint", 2}, {Method::Rk4, "rk4", 4}};
    for (const auto& m : methods) {
        const ButcherTableau t = tableauFor(m.method);
        EXPECT_EQ(t.order, m.order) << m.name;
        const RealTableau r = fromDoubleTable(m.name, t, t.b);
        expectExplicitWithConsistentNodes(r, kDoubleTableTolerance);
        expectExactOrder(r, m.order, kDoubleTableTolerance);
    }
}

TEST(ButcherTableau, DormandPrinceHasOrderFiveAndItsEmbeddedWeightsOrderFour) {
    const ButcherTableau t = tableauFor(Method::Dp5);
    EXPECT_EQ(t.stages, 7);
    EXPECT_EQ(t.order, 5);
    EXPECT_EQ(t.embeddedOrder, 4);
    const RealTableau fifth = fromDoubleTable("dp5", t, t.b);
    expectExplicitWithConsistentNodes(fifth, kDoubleTableTolerance);
    expectExactOrder(fifth, 5, kDoubleTableTolerance);
    // The table stores bError = b - b_hat; the embedded weights are recovered in Real (one more double rounding).
    double embedded[kMaxStages] = {};
    RealTableau fourth = fromDoubleTable("dp5_embedded4", t, embedded);
    for (int i = 0; i < t.stages; ++i) fourth.b[i] = Real(t.b[i]) - Real(t.bError[i]);
    expectExactOrder(fourth, 4, kDoubleTableTolerance);
}

TEST(ButcherTableau, DormandPrinceEmbeddedWeightsDifferAndSkipTheLastStageWhenFixed) {
    const ButcherTableau t = dormandPrince5Tableau();
    double errorSum = 0;
    for (int i = 0; i < t.stages; ++i) errorSum += t.bError[i];
    EXPECT_NEAR(errorSum, 0.0, 1e-15);  // both weight sets sum to one
    EXPECT_EQ(t.solutionStages, 6);     // b_7 = 0: the 7th stage only serves the error estimate (FSAL)
}

// The published table, in Real: the check of the coefficients themselves.
TEST(ButcherTableau, Hairer10TableFileHasExactlyOrderTen) {
    const RealTableau t = hairerFromTsv(readHairerTsv());
    expectExplicitWithConsistentNodes(t, kHairerTsvTolerance);
    EXPECT_TRUE(t.c[16] == 1);
    expectExactOrder(t, 10, kHairerTsvTolerance);
}

// The double table the integrators run: the correctly rounded TSV (what the generated source promises), keeping
// order 10 up to that rounding.
TEST(ButcherTableau, Hairer10AsRunIsTheRoundedFileAndKeepsOrderTen) {
    const ButcherTableau t = tableauFor(Method::Hairer10);
    EXPECT_EQ(t.stages, 17);
    EXPECT_EQ(t.order, 10);
    EXPECT_EQ(t.solutionStages, 17);
    EXPECT_DOUBLE_EQ(t.c[16], 1.0);
    ButcherTableau fromFile;
    int entries = 0;
    for (const TsvEntry& e : readHairerTsv()) {
        const double rounded = std::strtod(e.text.c_str(), nullptr);  // correctly rounded, as the compiler rounds
        if (e.kind == 'a') fromFile.a[e.i][e.j] = rounded;
        if (e.kind == 'b') fromFile.b[e.i] = rounded;
        if (e.kind == 'c') fromFile.c[e.i] = rounded;
        ++entries;
    }
    EXPECT_GT(entries, 100);
    // Compared as 17-digit text (%.17g): equal strings iff equal doubles, and readable when they differ.
    for (int i = 0; i < 17; ++i) {
        EXPECT_EQ(roundTrip(t.b[i]), roundTrip(fromFile.b[i])) << "b[" << i << "]";
        EXPECT_EQ(roundTrip(t.c[i]), roundTrip(fromFile.c[i])) << "c[" << i << "]";
        for (int j = 0; j < 17; ++j) {
            EXPECT_EQ(roundTrip(t.a[i][j]), roundTrip(fromFile.a[i][j])) << "a[" << i << "][" << j << "]";
        }
    }
    const RealTableau r = fromDoubleTable("hairer10", t, t.b);
    expectExplicitWithConsistentNodes(r, kDoubleTableTolerance);
    expectExactOrder(r, 10, kDoubleTableTolerance);
}

TEST(ButcherTableau, VerletHasNoTableau) { EXPECT_THROW(tableauFor(Method::Verlet), std::invalid_argument); }

}  // namespace
}  // namespace corebox
