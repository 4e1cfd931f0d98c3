// The global Newton with a hypoplastic interface (ContactEngine<Hypoplasticity>, paper §3.3):
// an elastic block pressed onto a fixed plate and sheared along it; the slave points' s_p1, s_p2
// are the block's stresses extrapolated to them (Eq. 14) and rotated into the contact frame
// (Eqs. 15, 16) at the start of each increment. Iteration counts with the Eq. 37 perturbation
// Jacobian against the analytical Eq. B3 option.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <Eigen/Dense>

#include "engine/contact_update.hpp"
#include "fem/contact_assembly.hpp"
#include "fem/element_kernels.hpp"
#include "fem/stress_extrapolation.hpp"
#include "tests/engine/interface_fixtures.hpp"

namespace {

using namespace ifsim::fem;

void add_row(Mesh& m, const std::vector<double>& xs, double y0, double y1) {
    const int base = m.n_nodes();
    const int n = static_cast<int>(xs.size());
    for (double x : xs) {
        m.coordinates.insert(m.coordinates.end(), {x, y0});
    }
    for (double x : xs) {
        m.coordinates.insert(m.coordinates.end(), {x, y1});
    }
    for (int i = 0; i + 1 < n; ++i) {
        m.connectivity.insert(m.connectivity.end(),
                              {base + i, base + i + 1, base + n + i + 1, base + n + i});
    }
}

struct ShearRun {
    std::vector<int> iterations; // per increment
    std::vector<double> tau;     // mean tau of the active points per increment
    bool ok = true;
};

ShearRun shear(ifsim::ContactJacobian jacobian) {
    const double E = 1e4, nu = 0.3, p = 100.0, k_N = 1e6;
    const auto mp = ifsim::test::l4c(0.9);
    ifsim::ContactOptions opt;
    opt.interface.ndim = 2;
    opt.interface.max_subincrement = 2.0e-5;
    opt.jacobian = jacobian;
    ifsim::ContactEngine<ifsim::Hypoplasticity> engine;
    ShearRun run;
    Mesh m;
    m.type = ElementType::quad4;
    add_row(m, {0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0}, -0.5, 0.0); // plate: nodes 0..13, 6 elements
    add_row(m, {0.2, 0.6, 1.0}, -1e-4, 0.5); // block: nodes 14..19, t_N = -100 at the start
    for (int e = 0; e < 6; ++e) {
        m.face_sets["plate"].push_back({e, 2});
    }
    for (int e = 6; e < 8; ++e) {
        m.face_sets["block"].push_back({e, 0});
    }
    m.validate();
    const int ndof = 2 * m.n_nodes();
    const std::vector<int> top{17, 18, 19};
    std::vector<bool> fixed(static_cast<std::size_t>(ndof), false);
    for (int i = 0; i < 28; ++i) {
        fixed[static_cast<std::size_t>(i)] = true; // the plate is fixed
    }
    for (int a : top) {
        fixed[static_cast<std::size_t>(2 * a)] = true; // pushed along x
    }
    Eigen::VectorXd f_ext = Eigen::VectorXd::Zero(ndof);
    for (int i = 0; i < 2; ++i) { // pressure on the block's top
        f_ext[2 * top[static_cast<std::size_t>(i)] + 1] -= 0.5 * p * 0.4;
        f_ext[2 * top[static_cast<std::size_t>(i) + 1] + 1] -= 0.5 * p * 0.4;
    }
    const double lam = E * nu / ((1 + nu) * (1 - 2 * nu)), G = E / (2 * (1 + nu));
    const double Dm[9] = {lam + 2 * G, lam, 0, lam, lam + 2 * G, 0, 0, 0, 2 * G};
    Eigen::MatrixXd K_el = Eigen::MatrixXd::Zero(ndof, ndof);
    const auto rule = gauss_rule<2>(false);
    for (int e = 0; e < m.n_elements(); ++e) {
        double X[8], dNdx[8];
        for (int a = 0; a < 4; ++a) {
            X[2 * a] = m.coordinate(m.node(e, a), 0);
            X[2 * a + 1] = m.coordinate(m.node(e, a), 1);
        }
        Eigen::Matrix<double, 8, 8> Ke = Eigen::Matrix<double, 8, 8>::Zero();
        for (int q = 0; q < rule.n; ++q) {
            const double det =
                physical_gradients<2>(X, rule.xi[static_cast<std::size_t>(q)].data(), dNdx);
            add_tangent<2>(dNdx, Dm, det * rule.weight[static_cast<std::size_t>(q)], Ke);
        }
        for (int a = 0; a < 8; ++a) {
            for (int b = 0; b < 8; ++b) {
                K_el(2 * m.node(e, a / 2) + a % 2, 2 * m.node(e, b / 2) + b % 2) += Ke(a, b);
            }
        }
    }
    MortarContact2D contact(m, "block", "plate");
    std::vector<double> u(static_cast<std::size_t>(ndof), 0.0);
    contact.pair(m, u);
    ifsim::ContactPoints<ifsim::Hypoplasticity> cpts(contact.points().size(), 2);
    for (std::size_t i = 0; i < cpts.size(); ++i) {
        cpts.set_state(i, ifsim::test::hypo_state(-100.0));
    }
    for (int step = 0; step < 6; ++step) {
        contact.pair(m, u); // projection in the converged configuration
        // Eqs. 14-16: the block's Gauss-point stresses extrapolated to each slave point.
        std::vector<std::array<double, 2>> s_p(contact.points().size());
        for (std::size_t i = 0; i < s_p.size(); ++i) {
            const auto& pt = contact.points()[i];
            const auto face = contact.slave_face(pt.slave.edge);
            double X[8], dNdx[8], ue[8];
            for (int a = 0; a < 4; ++a) {
                for (int d = 0; d < 2; ++d) {
                    X[2 * a + d] = m.coordinate(m.node(face.element, a), d);
                    ue[2 * a + d] = u[static_cast<std::size_t>(2 * m.node(face.element, a) + d)];
                }
            }
            std::vector<Voigt6> gp;
            for (int q = 0; q < rule.n; ++q) {
                physical_gradients<2>(X, rule.xi[static_cast<std::size_t>(q)].data(), dNdx);
                const auto eps = strain_at<2>(dNdx, ue);
                const double sxx = (lam + 2 * G) * eps[0] + lam * eps[1];
                const double syy = lam * eps[0] + (lam + 2 * G) * eps[1];
                // An initial K0 = 0.5 state under the 100 kPa pressure plus the elastic change
                // (the initial part stands for a confined block; it only feeds s_p).
                gp.push_back(
                    {-50.0 + sxx, -100.0 + syy, -50.0 + nu * (sxx + syy), 2 * G * eps[3], 0, 0});
            }
            const auto xi = quad4_face_point(face.local_face, pt.slave.xi);
            const auto s = extrapolate_stress(2, gp, xi.data());
            const auto l =
                rotate_to_frame(s, {pt.master.normal[0], pt.master.normal[1], 0},
                                {pt.master.tangent[0], pt.master.tangent[1], 0}, {0, 0, 1});
            s_p[i] = {l[1], l[2]};
        }
        std::vector<double> du(static_cast<std::size_t>(ndof), 0.0);
        for (int a : top) {
            du[static_cast<std::size_t>(2 * a)] = step == 0 ? 0.0 : 2e-4; // step 0: press only
        }
        std::vector<double> f_c;
        std::vector<double> history;
        bool converged = false;
        for (int it = 0; it < 40 && !converged; ++it) {
            contact.update_gaps(du);
            std::vector<PointTraction> tr(contact.points().size());
            for (std::size_t i = 0; i < tr.size(); ++i) {
                const auto& pt = contact.points()[i];
                const double n3[3] = {pt.master.normal[0], pt.master.normal[1], 0.0};
                const double t3[3] = {pt.master.tangent[0], pt.master.tangent[1], 0.0};
                const double z3[3] = {0.0, 0.0, 1.0};
                cpts.set_frame(i, n3, t3, z3);
                const bool closed = pt.master.in_contact && pt.g_N <= 0.0;
                cpts.input(ifsim::contact_col::t_N)[i] = closed ? k_N * pt.g_N : 0.0;
                cpts.input(ifsim::contact_col::k_N)[i] = closed ? k_N : 0.0;
                cpts.input(ifsim::contact_col::dg1)[i] = pt.dg_T;
                cpts.input(ifsim::contact_col::dg2)[i] = 0.0;
                cpts.input(ifsim::contact_col::s_p1)[i] = s_p[i][0];
                cpts.input(ifsim::contact_col::s_p2)[i] = s_p[i][1];
            }
            if (!engine.update(cpts, mp, opt).ok()) {
                std::printf("engine failed (step %d, iteration %d)\n", step, it);
                run.ok = false;
                return run;
            }
            for (std::size_t i = 0; i < tr.size(); ++i) {
                tr[i].t_N = cpts.output(ifsim::contact_col::traction)[i];
                tr[i].tau = cpts.output(ifsim::contact_col::traction + 1)[i];
                for (int c = 0; c < 4; ++c) {
                    tr[i].jac[0][static_cast<std::size_t>(c)] =
                        cpts.output(ifsim::contact_col::jacobian + 0 + 3 * c)[i];
                    tr[i].jac[1][static_cast<std::size_t>(c)] =
                        cpts.output(ifsim::contact_col::jacobian + 1 + 3 * c)[i];
                }
            }
            f_c.assign(static_cast<std::size_t>(ndof), 0.0);
            std::vector<ContactTriplet> Kc;
            contact.assemble(tr, f_c, &Kc);
            Eigen::VectorXd ut(ndof);
            for (int i = 0; i < ndof; ++i) {
                ut[i] = u[static_cast<std::size_t>(i)] + du[static_cast<std::size_t>(i)];
            }
            Eigen::VectorXd R =
                f_ext - K_el * ut - Eigen::Map<const Eigen::VectorXd>(f_c.data(), ndof);
            Eigen::MatrixXd K = K_el;
            for (const auto& t : Kc) {
                K(t.row, t.col) += t.value;
            }
            for (int i = 0; i < ndof; ++i) {
                if (fixed[static_cast<std::size_t>(i)]) {
                    R[i] = 0.0;
                    K.row(i).setZero();
                    K.col(i).setZero();
                    K(i, i) = 1.0;
                }
            }
            history.push_back(R.norm() / f_ext.norm());
            if (R.norm() <= 1e-10 * f_ext.norm()) {
                converged = true;
                run.iterations.push_back(it);
                break;
            }
            const Eigen::VectorXd d = K.partialPivLu().solve(R);
            for (int i = 0; i < ndof; ++i) {
                du[static_cast<std::size_t>(i)] += d[i];
            }
        }
        std::printf("step %d residuals:", step);
        for (double v : history) {
            std::printf(" %.1e", v);
        }
        std::printf("\n");
        if (!converged) {
            run.iterations.push_back(static_cast<int>(history.size())); // the limit
            run.ok = false;
            return run;
        }
        cpts.commit();
        for (int i = 0; i < ndof; ++i) {
            u[static_cast<std::size_t>(i)] += du[static_cast<std::size_t>(i)];
        }
        double tau = 0.0;
        for (std::size_t i = 0; i < cpts.size(); ++i) {
            tau +=
                cpts.output(ifsim::contact_col::traction + 1)[i] / static_cast<double>(cpts.size());
        }
        run.tau.push_back(tau);
    }
    return run;
}

TEST(ContactNewtonHypo, Eq37JacobianNeedsFewerIterationsThanB3) {
    std::printf("Eq. 37 perturbation:\n");
    const ShearRun a = shear(ifsim::ContactJacobian::perturbation);
    std::printf("Eq. B3 analytical:\n");
    const ShearRun b = shear(ifsim::ContactJacobian::analytical);
    ASSERT_TRUE(a.ok);
    for (int k : a.iterations) {
        EXPECT_LE(k, 10);
    }
    EXPECT_GT(std::abs(a.tau.back()), 1.0); // the interface carries shear
    // B3 converges linearly (measured about x0.95 per iteration in the pressing increment) and
    // here does not reach the tolerance within 40 iterations; it must at least need more
    // iterations in every increment it completes, and in the first one it does not complete.
    ASSERT_FALSE(b.iterations.empty());
    for (std::size_t k = 0; k < b.iterations.size(); ++k) {
        EXPECT_LT(a.iterations[k], b.iterations[k]) << "increment " << k;
    }
    if (b.ok) { // same converged solution
        for (std::size_t k = 0; k < a.tau.size(); ++k) {
            EXPECT_NEAR(a.tau[k], b.tau[k], 1e-6 * std::abs(a.tau[k]) + 1e-9);
        }
    }
}

} // namespace
