// The batched update: bitwise independence of the thread count, scalar against SIMD path,
// Sanisand's lane refill against its masked batches, padding never leaks, and commit swaps the
// state.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include <tbb/global_control.h>

#include "engine/batched_update.hpp"
#include "engine/sample_states.hpp"
#include "kernels/parameter_sets.hpp"

using namespace ifsim;

namespace {

template <class M>
std::vector<double> trial_states(const MaterialPoints<M>& mp) {
    std::vector<double> out;
    for (int k = 0; k < M::n_state; ++k) {
        out.insert(out.end(), mp.trial(k), mp.trial(k) + mp.size());
    }
    return out;
}

template <class M>
std::vector<double> run_once(const typename M::Params& p, std::size_t n, bool simd, int threads,
                             std::size_t chunk = 16, const SampleSpec& spec = {}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    MaterialPoints<M> mp(n);
    fill_samples(mp, p, spec);
    UpdateOptions opt;
    opt.simd = simd;
    opt.chunk_points = chunk;
    const auto rep = batched_update(mp, p, opt);
    EXPECT_EQ(rep.failed, 0u);
    return trial_states(mp);
}

double worst_relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
    double worst = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        worst = std::max(worst, std::abs(a[i] - b[i]) / (1e-3 + std::abs(b[i])));
    }
    return worst;
}

SanisandParams karlsruhe_sanisand() {
    auto p = parameter_sets::sanisand_karlsruhe();
    p.prepare();
    return p;
}

// Increments of 1e-3: many substeps per point, loading, unloading and crossings in one batch.
const SampleSpec large_increments{12345, 1.0e-3};

HypoplasticityParams hypo() {
    auto p = parameter_sets::hypoplasticity_karlsruhe();
    p.prepare();
    return p;
}

} // namespace

TEST(BatchedUpdate, OneThreadAndTwoThreadsAreBitwiseEqual) {
    for (bool simd : {true, false}) {
        const auto a = run_once<Hypoplasticity>(hypo(), 403, simd, 1);
        const auto b = run_once<Hypoplasticity>(hypo(), 403, simd, 2);
        ASSERT_EQ(a.size(), b.size());
        EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0);
    }
}

TEST(BatchedUpdate, ChunkSizeDoesNotChangeResults) {
    const auto a = run_once<Hypoplasticity>(hypo(), 200, true, 2, 8);
    const auto b = run_once<Hypoplasticity>(hypo(), 200, true, 2, 1024);
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0);
}

TEST(BatchedUpdate, ScalarAndSimdPathsAgree) {
    const std::size_t n = 300;
    const auto a = run_once<Hypoplasticity>(hypo(), n, true, 1);
    const auto b = run_once<Hypoplasticity>(hypo(), n, false, 1);
    EXPECT_LT(worst_relative_difference(a, b), 1e-8);
}

// Sanisand's own substep loop run with lane refill (a finished lane takes the next point; the
// engine's choice for it is the masked path, see Sanisand::lane_refill): bitwise the same as the
// batch-by-batch masked path, in every stat, also for the starts the refill treats specially: a
// back-stress off the cone (consistent_start acts), a stress below the pressure floor, a NaN
// increment (restored, failed), fixed substeps, and lanes that run out of max_substeps.
TEST(BatchedUpdate, SanisandLaneRefillEqualsTheMaskedBatchPath) {
    const auto P = karlsruhe_sanisand();
    const std::size_t n = 203;
    auto prepare = [&](MaterialPoints<Sanisand>& mp) {
        fill_samples(mp, P, large_increments);
        for (std::size_t i : {3u, 50u, 101u}) { // alpha far off the sample's stress ratio
            auto y = mp.state(i);
            set_sym_at(y, Sanisand::alpha_index, Sym<double>{0.3, -0.1, -0.2, 0.15, 0.0, 0.05});
            mp.set_state(i, y);
        }
        for (std::size_t i : {10u, 77u}) { // below the pressure floor
            auto y = mp.state(i);
            set_stress(y, Sym<double>{-1e-4, -2e-4, -1e-4, 0.0, 0.0, 0.0});
            mp.set_state(i, y);
        }
        mp.set_deps(20, Sym<double>{std::nan(""), 0.0, 0.0, 0.0, 0.0, 0.0});
        for (std::size_t i = 30; i < 46; ++i) {
            mp.fixed_substeps()[i] = 4.0;
        }
    };
    double substeps = 0.0;
    for (int max_substeps : {200000, 3}) {
        MaterialPoints<Sanisand> refill(n), masked(n);
        prepare(refill);
        prepare(masked);
        UpdateOptions opt;
        opt.settings.max_substeps = max_substeps;
        detail::update_range_refill<Sanisand>(refill, P, opt, 0, refill.padded());
        detail::update_range<Sanisand, simd::batch>(masked, P, opt, 0, masked.padded());
        const auto a = trial_states(refill);
        const auto b = trial_states(masked);
        EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0)
            << "max_substeps " << max_substeps;
        int failed = 0;
        for (std::size_t i = 0; i < n; ++i) {
            EXPECT_EQ(refill.status()[i], masked.status()[i]) << "point " << i;
            EXPECT_EQ(refill.substeps()[i], masked.substeps()[i]) << "point " << i;
            EXPECT_EQ(refill.rejected()[i], masked.rejected()[i]) << "point " << i;
            EXPECT_EQ(refill.rate_evaluations()[i], masked.rate_evaluations()[i]) << "point " << i;
            failed += refill.status()[i] < -0.5 ? 1 : 0;
            substeps += max_substeps > 3 ? refill.substeps()[i] : 0.0;
        }
        EXPECT_EQ(refill.status()[20], lane_status::failed); // the NaN increment
        EXPECT_LT(refill.status()[10], 0.5);                 // below the floor: reported, not ok
        if (max_substeps == 3) {
            EXPECT_GT(failed, 10); // lanes did run out
        }
    }
    EXPECT_GT(substeps, 3.0 * n); // the points did substep, at different counts
}

// Sanisand through batched_update: bitwise the same for any thread count and chunk size, and
// the scalar path to round-off of the SIMD math functions.
TEST(BatchedUpdate, SanisandThreadsChunksAndScalarPath) {
    const auto P = karlsruhe_sanisand();
    const auto one = run_once<Sanisand>(P, 403, true, 1, 16, large_increments);
    const auto two = run_once<Sanisand>(P, 403, true, 2, 16, large_increments);
    const auto big_chunks = run_once<Sanisand>(P, 403, true, 2, 1024, large_increments);
    EXPECT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(double)), 0);
    EXPECT_EQ(std::memcmp(one.data(), big_chunks.data(), one.size() * sizeof(double)), 0);
    const auto scalar = run_once<Sanisand>(P, 403, false, 1, 16, large_increments);
    EXPECT_LT(worst_relative_difference(one, scalar), 1e-8);
}

TEST(BatchedUpdate, LinearElasticityIsExactOnBothPaths) {
    LinearElasticParams p{1.0e4, 0.2};
    MaterialPoints<LinearElastic> mp(5);
    fill_samples(mp, p, SampleSpec{});
    for (bool simd : {true, false}) {
        UpdateOptions opt;
        opt.simd = simd;
        batched_update(mp, p, opt);
        for (std::size_t i = 0; i < 5; ++i) {
            const auto y0 = mp.state(i);
            const auto y1 = mp.trial_state(i);
            Sym<double> d;
            for (int j = 0; j < 6; ++j) {
                d[j] = mp.deps(j)[i];
            }
            const auto ds = LinearElastic::stress_increment(p, d);
            for (int k = 0; k < 6; ++k) {
                EXPECT_NEAR(y1[k], y0[k] + ds[k], 1e-10);
            }
        }
    }
}

TEST(BatchedUpdate, FailedPointIsReportedAndRestored) {
    auto p = hypo();
    MaterialPoints<Hypoplasticity> mp(20);
    fill_samples(mp, p, SampleSpec{});
    auto y = mp.state(13);
    y[0] = std::nan("");
    mp.set_state(13, y);
    const auto rep = batched_update(mp, p, UpdateOptions{});
    EXPECT_EQ(rep.failed, 1u);
    EXPECT_EQ(rep.first_failed, 13u);
    EXPECT_TRUE(std::isnan(mp.trial(0)[13])); // left exactly as it came in
    for (std::size_t i = 0; i < 20; ++i) {
        if (i != 13) {
            EXPECT_TRUE(std::isfinite(mp.trial(0)[i]));
        }
    }
}

TEST(BatchedUpdate, CommitSwapsTrialIntoCommitted) {
    auto p = hypo();
    MaterialPoints<Hypoplasticity> mp(9);
    fill_samples(mp, p, SampleSpec{});
    batched_update(mp, p, UpdateOptions{});
    const auto trial = mp.trial_state(4);
    mp.commit();
    EXPECT_EQ(mp.state(4), trial);
}
