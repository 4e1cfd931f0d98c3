// `ifsim kernel-bench` with interface formulations, and the batched Coulomb contact points it
// times: the JSON carries the contract's fields and the interface costs (lanes and
// sub-increments per point); the Coulomb Jacobian columns are the derivatives of the traction
// with respect to the slave and master displacements, in ContactPoints' layout and convention.

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "engine/coulomb_contact.hpp"
#include "io/cli/cli.hpp"
#include "io/cli/exit_codes.hpp"
#include "io/cli/kernel_bench.hpp"

namespace ifsim::io {
namespace {

nlohmann::ordered_json bench(const std::string& model, const std::string& formulation,
                             const std::string& jacobian = "perturbation",
                             const std::string& subincrement = "fixed", bool scalar = false) {
    KernelBenchOptions o;
    o.model = model;
    o.formulation = formulation;
    o.points = 9; // more than one SIMD batch, not a multiple of the lanes
    o.threads = 1;
    o.seconds = 0.02;
    o.jacobian = jacobian;
    o.subincrement = subincrement;
    o.scalar = scalar;
    return run_kernel_bench(o);
}

void expect_contract_fields(const nlohmann::ordered_json& j, const std::string& formulation) {
    for (const char* key :
         {"model", "formulation", "points", "threads", "path", "evaluations_per_second",
          "points_per_second", "lanes_per_point", "subincrements_per_point"}) {
        EXPECT_TRUE(j.contains(key)) << key;
    }
    EXPECT_EQ(j["formulation"], formulation);
    EXPECT_EQ(j["points"], 9);
    EXPECT_EQ(j["threads"], 1);
    EXPECT_GT(j["points_per_second"].get<double>(), 0.0);
    EXPECT_GE(j["evaluations_per_second"].get<double>(), j["points_per_second"].get<double>());
    EXPECT_EQ(j["failed_points"], 0);
    EXPECT_EQ(j["committed"], false);
}

TEST(InterfaceBench, ContinuumFormulationsTimeTheContactEngine) {
    for (const char* model : {"hypoplasticity", "sanisand"}) {
        for (const char* form : {"novel", "stutz"}) {
            const auto j = bench(model, form);
            expect_contract_fields(j, form);
            EXPECT_EQ(j["model"], model);
            EXPECT_EQ(j["path"], "simd");
            // Eq. 37 in 3D: the base lane and 2 ndim = 6 perturbed lanes per point.
            EXPECT_DOUBLE_EQ(j["lanes_per_point"].get<double>(), 7.0) << model << form;
            // A few micrometres over d_s = 3 mm is ~1e-3 of shear strain: about 200 fixed
            // sub-increments of 5e-6.
            EXPECT_GT(j["subincrements_per_point"].get<double>(), 50.0) << model << form;
            EXPECT_GT(j["evaluations_per_point"].get<double>(),
                      7.0 * j["subincrements_per_point"].get<double>());
        }
    }
}

TEST(InterfaceBench, JacobianAndSubincrementOptionsChangeTheWork) {
    const auto perturbed = bench("hypoplasticity", "novel");
    const auto analytical = bench("hypoplasticity", "novel", "analytical");
    EXPECT_DOUBLE_EQ(analytical["lanes_per_point"].get<double>(), 1.0);
    EXPECT_EQ(analytical["jacobian"], "analytical");
    EXPECT_LT(analytical["evaluations_per_point"].get<double>(),
              perturbed["evaluations_per_point"].get<double>() / 3.0);
    const auto adaptive = bench("hypoplasticity", "novel", "perturbation", "adaptive");
    EXPECT_EQ(adaptive["subincrement"], "adaptive");
    EXPECT_LT(adaptive["subincrements_per_point"].get<double>(),
              perturbed["subincrements_per_point"].get<double>());
    const auto scalar = bench("hypoplasticity", "stutz", "perturbation", "fixed", true);
    EXPECT_EQ(scalar["path"], "scalar");
    EXPECT_EQ(scalar["failed_points"], 0);
}

TEST(InterfaceBench, CoulombIsOneAnalyticalLanePerPoint) {
    for (const char* model : {"coulomb", "hypoplasticity"}) {
        const auto j = bench(model, "coulomb");
        expect_contract_fields(j, "coulomb");
        EXPECT_EQ(j["model"], model);
        EXPECT_EQ(j["interface_model"], "coulomb");
        EXPECT_DOUBLE_EQ(j["lanes_per_point"].get<double>(), 1.0);
        EXPECT_DOUBLE_EQ(j["subincrements_per_point"].get<double>(), 0.0);
        EXPECT_DOUBLE_EQ(j["evaluations_per_second"].get<double>(),
                         j["points_per_second"].get<double>());
    }
}

TEST(InterfaceBench, BadOptionsAreErrors) {
    EXPECT_THROW(bench("hypoplasticity", "mohr"), std::invalid_argument);
    EXPECT_THROW(bench("linear-elastic", "novel"), std::invalid_argument);
    EXPECT_THROW(bench("coulomb", "novel"), std::invalid_argument);
    EXPECT_THROW(bench("coulomb", "none"), std::invalid_argument);
    EXPECT_THROW(bench("hypoplasticity", "novel", "exact"), std::invalid_argument);
    EXPECT_THROW(bench("hypoplasticity", "novel", "perturbation", "variable"),
                 std::invalid_argument);
    EXPECT_THROW(bench("coulomb", "coulomb", "analytical"), std::invalid_argument);
}

TEST(InterfaceBench, CommandLinePrintsTheJson) {
    std::vector<std::string> args = {"ifsim",          "kernel-bench",
                                     "--model",        "sanisand",
                                     "--formulation",  "stutz",
                                     "--points",       "4",
                                     "--threads",      "1",
                                     "--seconds",      "0.02",
                                     "--subincrement", "adaptive"};
    std::vector<const char*> argv;
    for (const auto& a : args) {
        argv.push_back(a.c_str());
    }
    testing::internal::CaptureStdout();
    testing::internal::CaptureStderr();
    const int code = run_cli(static_cast<int>(argv.size()), argv.data());
    const std::string out = testing::internal::GetCapturedStdout();
    const std::string err = testing::internal::GetCapturedStderr();
    ASSERT_EQ(code, exit_code::ok) << err;
    const auto j = nlohmann::json::parse(out);
    EXPECT_EQ(j["model"], "sanisand");
    EXPECT_EQ(j["formulation"], "stutz");
    EXPECT_EQ(j["points"], 4);
    EXPECT_EQ(j["subincrement"], "adaptive");

    args.insert(args.end(), {"--jacobian", "exact"});
    argv.clear();
    for (const auto& a : args) {
        argv.push_back(a.c_str());
    }
    testing::internal::CaptureStdout();
    testing::internal::CaptureStderr();
    const int bad = run_cli(static_cast<int>(argv.size()), argv.data());
    testing::internal::GetCapturedStdout();
    const std::string bad_err = testing::internal::GetCapturedStderr();
    EXPECT_EQ(bad, exit_code::bad_input);
    EXPECT_NE(bad_err.find("--jacobian exact"), std::string::npos) << bad_err;
}

// Coulomb points with varied frames, pressures and tractions, in stick, slip and open contact.
CoulombContactPoints coulomb_points(std::size_t n, int ndim) {
    CoulombContactPoints cp(n, ndim);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (std::size_t i = 0; i < n; ++i) {
        const double a = 3.0 * u(rng), b = 3.0 * u(rng);
        // A rotated frame: n = (cos a cos b, sin a cos b, sin b) and two tangents.
        const double nv[3] = {std::cos(a) * std::cos(b), std::sin(a) * std::cos(b), std::sin(b)};
        const double t1[3] = {-std::sin(a), std::cos(a), 0.0};
        const double t2[3] = {nv[1] * t1[2] - nv[2] * t1[1], nv[2] * t1[0] - nv[0] * t1[2],
                              nv[0] * t1[1] - nv[1] * t1[0]};
        cp.set_frame(i, nv, t1, t2);
        const double t_N = i % 7 == 6 ? 5.0 : -100.0 - 100.0 * u(rng); // every 7th open
        cp.input(coulomb_col::t_N)[i] = t_N;
        cp.input(coulomb_col::k_N)[i] = 1.0e6;
        cp.input(coulomb_col::dg1)[i] = 2.0e-5 * u(rng);
        cp.input(coulomb_col::dg2)[i] = 2.0e-5 * u(rng);
        cp.set_traction(i, 10.0 * u(rng), 10.0 * u(rng));
    }
    return cp;
}

TEST(CoulombContact, JacobianColumnsAreTheDerivativesOfTheTraction) {
    const CoulombParams p{0.25, 1.0e6}; // stiff: points both stick and slip
    for (int ndim : {2, 3}) {
        CoulombContactPoints cp = coulomb_points(23, ndim);
        CoulombContactOptions opt;
        const CoulombContactReport rep = coulomb_contact_update(cp, p, opt);
        EXPECT_GT(rep.slipping, 0u);
        EXPECT_GT(rep.open, 0u);
        EXPECT_LT(rep.slipping + rep.open, cp.size()); // some stick
        for (std::size_t i = 0; i < cp.size(); ++i) {
            const double t_N = cp.input(coulomb_col::t_N)[i];
            const double k_N = cp.input(coulomb_col::k_N)[i];
            const double h = 1.0e-9;
            for (int c = 0; c < 2 * ndim; ++c) {
                // The gap change of a displacement (slave +, master -), as in the contact
                // engine's perturbed lanes: t_N + k_N dg.n, dg_T,b - dg.t_b.
                const double sgn = c < ndim ? 1.0 : -1.0;
                const int d = c % ndim;
                auto traction = [&](double s) {
                    const double n_d = cp.input(coulomb_col::n + d)[i];
                    const double t1 = cp.input(coulomb_col::t1 + d)[i];
                    const double t2 = cp.input(coulomb_col::t2 + d)[i];
                    const double tn = t_N + k_N * s * sgn * n_d;
                    const auto r =
                        coulomb_update<double>(p, tn, cp.committed(coulomb_col::tau1)[i],
                                               cp.committed(coulomb_col::tau2)[i],
                                               cp.input(coulomb_col::dg1)[i] - s * sgn * t1,
                                               cp.input(coulomb_col::dg2)[i] - s * sgn * t2);
                    return std::vector<double>{r.open ? 0.0 : tn, r.tau1, r.tau2};
                };
                const auto plus = traction(h), minus = traction(-h);
                for (int comp = 0; comp < 3; ++comp) {
                    const double fd = (plus[comp] - minus[comp]) / (2.0 * h);
                    EXPECT_NEAR(cp.jacobian(i, comp, c), fd, 1e-5 * std::max(1.0, std::abs(fd)))
                        << "point " << i << " comp " << comp << " column " << c;
                }
            }
            EXPECT_EQ(cp.output(contact_col::traction + 1)[i], cp.trial(coulomb_col::tau1)[i]);
        }
    }
}

TEST(CoulombContact, ScalarSimdAndThreadsGiveTheSameResults) {
    const CoulombParams p{0.3, 2.0e5};
    CoulombContactPoints a = coulomb_points(37, 3);
    CoulombContactPoints b = coulomb_points(37, 3);
    CoulombContactOptions simd_opt;
    simd_opt.chunk_points = 8;
    CoulombContactOptions scalar_opt;
    scalar_opt.simd = false;
    coulomb_contact_update(a, p, simd_opt);
    coulomb_contact_update(b, p, scalar_opt);
    for (std::size_t i = 0; i < a.size(); ++i) {
        for (int k = 0; k < coulomb_col::n_outputs; ++k) {
            EXPECT_NEAR(a.output(k)[i], b.output(k)[i],
                        1e-12 * std::max(1.0, std::abs(b.output(k)[i])))
                << "point " << i << " output " << k;
        }
    }
    // Commit swaps the trial traction in.
    const double trial = a.trial(coulomb_col::tau1)[3];
    a.commit();
    EXPECT_EQ(a.committed(coulomb_col::tau1)[3], trial);
}

} // namespace
} // namespace ifsim::io
