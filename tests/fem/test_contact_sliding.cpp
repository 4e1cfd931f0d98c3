// A 2D elastic block pressed onto a longer fixed plate and pushed along it over several master
// edges, through CoulombContact2D (the Coulomb engine at the slave integration points) and
// the global Newton using its Jacobian. Once sliding, the
// tangential contact force is mu times the normal force; Newton converges in a few iterations.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <Eigen/Dense>

#include "fem/contact_coulomb.hpp"
#include "fem/element_kernels.hpp"

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

TEST(ContactSliding, CoulombBlockSlidesOverSeveralMasterEdges) {
    const double E = 1e4, nu = 0.3, p = 100.0, k_N = 1e6;
    ifsim::CoulombParams cp_params{0.3, 1e5};
    Mesh m;
    m.type = ElementType::quad4;
    add_row(m, {0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0}, -0.5, 0.0); // plate: nodes 0..13, 6 elements
    add_row(m, {0.2, 0.6, 1.0}, -1e-5, 0.5); // block: nodes 14..19, slightly closed at the start
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
    CoulombContact2D contact(m, {"block", "plate", k_N, cp_params});
    std::vector<double> u(static_cast<std::size_t>(ndof), 0.0);
    std::vector<int> edges_seen;
    int max_iterations = 0;
    for (int step = 0; step < 9; ++step) {
        contact.begin_increment(m, u); // projection in the converged configuration
        std::vector<double> du(static_cast<std::size_t>(ndof), 0.0);
        for (int a : top) {
            du[static_cast<std::size_t>(2 * a)] = step == 0 ? 0.0 : 0.25; // step 0: press only
        }
        std::vector<double> f_c;
        std::vector<double> history;
        bool converged = false;
        for (int it = 0; it < 25 && !converged; ++it) {
            f_c.assign(static_cast<std::size_t>(ndof), 0.0);
            std::vector<ContactTriplet> Kc;
            contact.forces(du, f_c, &Kc);
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
                max_iterations = std::max(max_iterations, it);
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
        ASSERT_TRUE(converged) << "step " << step;
        contact.commit();
        for (int i = 0; i < ndof; ++i) {
            u[static_cast<std::size_t>(i)] += du[static_cast<std::size_t>(i)];
        }
        double Fx = 0.0, Fy = 0.0; // contact forces on the block (internal, summed)
        for (int a = 14; a < 20; ++a) {
            Fx += f_c[static_cast<std::size_t>(2 * a)];
            Fy += f_c[static_cast<std::size_t>(2 * a + 1)];
        }
        std::printf("   F_N %.6f F_T %.6f\n", Fy, Fx);
        EXPECT_NEAR(Fy, -p * 0.8, 1e-8 * p); // equilibrium with the pressure
        if (step > 0) { // sliding: F_T = mu F_N, resisting the motion to the right
            EXPECT_NEAR(Fx, cp_params.friction_coefficient * p * 0.8, 1e-8 * p);
        }
        for (const auto& pt : contact.mortar().points()) {
            if (pt.master.in_contact) {
                edges_seen.push_back(pt.master.edge);
            }
        }
    }
    std::sort(edges_seen.begin(), edges_seen.end());
    edges_seen.erase(std::unique(edges_seen.begin(), edges_seen.end()), edges_seen.end());
    EXPECT_EQ(edges_seen.size(), 6U);
    EXPECT_LE(max_iterations, 6);
}

} // namespace
