// Aitken's dynamic relaxation of a fixed-point iteration (fem/aitken_relaxation.hpp), the
// accelerator of the implicit gather: on linear maps against the plain iteration and the exact
// fixed point.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "fem/aitken_relaxation.hpp"

using ifsim::fem::AitkenRelaxation;

namespace {

// x <- A x + b with A diagonal: the fixed point is b / (1 - a).
struct DiagonalMap {
    std::vector<double> a, b;
    std::vector<double> operator()(const std::vector<double>& x) const {
        std::vector<double> y(x.size());
        for (std::size_t i = 0; i < x.size(); ++i) {
            y[i] = a[i] * x[i] + b[i];
        }
        return y;
    }
    double error(const std::vector<double>& x) const {
        double e = 0.0;
        for (std::size_t i = 0; i < x.size(); ++i) {
            e = std::max(e, std::abs(x[i] - b[i] / (1.0 - a[i])));
        }
        return e;
    }
};

// Rounds until the change G(x) - x is below tol (the gather's settle test).
int rounds_to_settle(const DiagonalMap& G, bool aitken, double tol, std::vector<double>& x) {
    AitkenRelaxation relax;
    for (int k = 0; k < 1000; ++k) {
        const std::vector<double> g = G(x);
        std::vector<double> r(x.size());
        double change = 0.0;
        for (std::size_t i = 0; i < x.size(); ++i) {
            r[i] = g[i] - x[i];
            change = std::max(change, std::abs(r[i]));
        }
        if (change <= tol) {
            x = g;
            return k;
        }
        const double omega = aitken ? relax.factor(r) : 1.0;
        for (std::size_t i = 0; i < x.size(); ++i) {
            x[i] += omega * r[i];
        }
    }
    return 1000;
}

// A scalar linear map is solved exactly by the second relaxed step: omega = 1 / (1 - a).
TEST(AitkenRelaxation, ScalarLinearMapIsSolvedInTwoSteps) {
    for (double a : {0.8, 0.85, -0.6}) {
        const DiagonalMap G{{a}, {2.0}};
        std::vector<double> x{0.0};
        AitkenRelaxation relax;
        for (int k = 0; k < 2; ++k) {
            const double r = G(x)[0] - x[0];
            x[0] += relax.factor({r}) * r;
        }
        EXPECT_NEAR(G.error(x), 0.0, 1e-12) << "a = " << a;
        EXPECT_NEAR(relax.last_factor(), 1.0 / (1.0 - a), 1e-9) << "a = " << a;
    }
}

// A slowly contracting map (the slowest mode 0.8, as the §6 Sanisand gathers): far fewer
// rounds than the plain iteration, to the same fixed point.
TEST(AitkenRelaxation, SlowContractionSettlesInFewerRoundsAtTheSameFixedPoint) {
    const DiagonalMap G{{0.8, 0.5, 0.3, -0.2}, {1.0, -2.0, 0.5, 3.0}};
    std::vector<double> plain(4, 0.0), relaxed(4, 0.0);
    const int n_plain = rounds_to_settle(G, false, 1e-8, plain);
    const int n_relaxed = rounds_to_settle(G, true, 1e-8, relaxed);
    EXPECT_GT(n_plain, 70);
    EXPECT_LT(n_relaxed, n_plain / 2);
    EXPECT_LT(G.error(plain), 1e-7);
    EXPECT_LT(G.error(relaxed), 1e-7);
}

// The factor stays within its bounds, and reset() (a new increment) restarts with the plain step.
TEST(AitkenRelaxation, FactorIsBoundedAndResetRestartsPlain) {
    AitkenRelaxation relax;
    EXPECT_EQ(relax.factor({1.0, 0.0}), 1.0);
    // residuals nearly equal: omega would be huge
    EXPECT_EQ(relax.factor({1.0 - 1e-9, 0.0}), AitkenRelaxation::max_factor);
    // a flipped residual: omega would be tiny or negative
    relax.reset();
    EXPECT_EQ(relax.factor({1.0}), 1.0);
    EXPECT_GE(relax.factor({-1.0}), AitkenRelaxation::min_factor);
    relax.reset();
    EXPECT_EQ(relax.factor({5.0, 5.0, 5.0}), 1.0);
    // a residual of another length (the closed points changed) drops the history
    EXPECT_EQ(relax.factor({1.0, 2.0}), 1.0);
}

} // namespace
