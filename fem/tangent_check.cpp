// StaticSolver::check_tangent: the diagnostic that finds an inconsistent tangent (a Newton
// iteration that converges linearly or diverges although the step is small). Along the Newton
// direction c the residual's central difference must equal -K c up to O(h^2); two step sizes
// two decades apart separate an inconsistent tangent (the same mismatch at both) from
// non-linearity or noise of the inner solves (a mismatch that changes with h). Each contact
// pair is checked on its own forces and its own tangent entries, so the source is named.
#include <algorithm>
#include <cmath>
#include <limits>

#include "fem/static_solver.hpp"
#include "fem/vector_norm.hpp"

namespace ifsim::fem {
namespace {

// Largest-entry steps of h c, metres.
constexpr double kSteps[2] = {1.0e-7, 1.0e-9};

double relative(const std::vector<double>& a, const std::vector<double>& b) {
    double diff = 0.0, ref = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        diff += (a[i] - b[i]) * (a[i] - b[i]);
        ref += b[i] * b[i];
    }
    return std::sqrt(diff) / std::max(std::sqrt(ref), 1.0e-300);
}

} // namespace

void StaticSolver::check_tangent(double t_end, const IncrementInfo& info) {
    const std::vector<double> residual_kept = residual_;
    const double reference_kept = reference_force_;
    const auto n_eq = static_cast<std::size_t>(dofs_.n_equations);
    std::vector<double> c_full(du_.size(), 0.0);
    double c_max = 0.0;
    for (std::size_t d = 0; d < du_.size(); ++d) {
        const int eq = dofs_.equation[d];
        if (eq >= 0) {
            c_full[d] = correction_[static_cast<std::size_t>(eq)];
            c_max = std::max(c_max, std::abs(c_full[d]));
        }
    }
    if (c_max == 0.0) {
        return;
    }
    // -K c on the free equations (the residual is f_ext - f_int, K = d f_int / d u).
    const Eigen::Map<const Eigen::VectorXd> c(correction_.data(), static_cast<Eigen::Index>(n_eq));
    const Eigen::VectorXd kc = system_->matrix() * c;
    std::vector<double> minus_kc(n_eq);
    for (std::size_t i = 0; i < n_eq; ++i) {
        minus_kc[i] = -kc[static_cast<Eigen::Index>(i)];
    }
    // Each pair's own tangent times c (its entries at du_, after an evaluation there).
    const auto& pairs = contacts_.pairs();
    contacts_.set_probing(true);
    std::vector<std::vector<double>> pair_kc(pairs.size());
    std::string error;
    for (std::size_t p = 0; p < pairs.size(); ++p) {
        std::vector<double> f(du_.size(), 0.0);
        std::vector<ContactTriplet> k;
        pair_kc[p].assign(du_.size(), 0.0);
        if (!pairs[p]->evaluate(du_, f, error)) {
            continue;
        }
        pairs[p]->add_tangent(k);
        for (const ContactTriplet& t : k) {
            pair_kc[p][static_cast<std::size_t>(t.row)] +=
                t.value * c_full[static_cast<std::size_t>(t.col)];
        }
    }
    for (const double step : kSteps) {
        const double h = step / c_max;
        TangentCheckRecord rec;
        rec.stage = info.stage;
        rec.t_end = t_end;
        rec.iteration = static_cast<int>(info.residuals.size());
        rec.step = step;
        rec.mismatch = std::numeric_limits<double>::quiet_NaN();
        std::vector<double> shifted(du_.size());
        const auto shift = [&](int side) { // du + h c (side 0) or du - h c (side 1)
            const double sign = side == 0 ? 1.0 : -1.0;
            for (std::size_t d = 0; d < du_.size(); ++d) {
                shifted[d] = du_[d] + sign * h * c_full[d];
            }
        };
        std::vector<double> r_side[2];
        bool ok = true;
        for (int side = 0; side < 2 && ok; ++side) {
            shift(side);
            ok = residual_pass(t_end, shifted, error);
            r_side[side] = residual_;
        }
        // Everything but the pairs (continuum, springs): the global change minus the pairs'.
        std::vector<double> rest_fd(n_eq, 0.0), rest_kc(n_eq, 0.0);
        bool rest_ok = ok;
        if (ok) {
            std::vector<double> fd(n_eq);
            double worst = -1.0;
            for (std::size_t i = 0; i < n_eq; ++i) {
                fd[i] = (r_side[0][i] - r_side[1][i]) / (2.0 * h);
                if (std::abs(fd[i] - minus_kc[i]) > worst) {
                    worst = std::abs(fd[i] - minus_kc[i]);
                    rec.worst_difference = fd[i];
                    rec.worst_tangent = minus_kc[i];
                    rec.worst_dof = static_cast<int>(i);
                }
            }
            rec.mismatch = relative(fd, minus_kc);
            for (std::size_t i = 0; i < n_eq; ++i) {
                rest_fd[i] = -fd[i];
                rest_kc[i] = -minus_kc[i];
            }
            for (std::size_t d = 0; d < du_.size(); ++d) { // equation -> global DOF
                if (dofs_.equation[d] == rec.worst_dof) {
                    rec.worst_dof = static_cast<int>(d);
                    break;
                }
            }
        }
        // The pairs alone, on their free DOFs.
        for (std::size_t p = 0; p < pairs.size(); ++p) {
            std::vector<double> f_side[2];
            bool pair_ok = true;
            for (int side = 0; side < 2 && pair_ok; ++side) {
                shift(side);
                f_side[side].assign(du_.size(), 0.0);
                pair_ok = pairs[p]->evaluate(shifted, f_side[side], error);
            }
            if (!pair_ok) {
                rec.pairs.push_back(std::numeric_limits<double>::quiet_NaN());
                rest_ok = false;
                continue;
            }
            std::vector<double> fd(n_eq, 0.0), kc_p(n_eq, 0.0);
            for (std::size_t d = 0; d < du_.size(); ++d) {
                const int eq = dofs_.equation[d];
                if (eq >= 0) {
                    const auto e = static_cast<std::size_t>(eq);
                    fd[e] = (f_side[0][d] - f_side[1][d]) / (2.0 * h);
                    kc_p[e] = pair_kc[p][d];
                    rest_fd[e] -= fd[e];
                    rest_kc[e] -= kc_p[e];
                }
            }
            rec.pairs.push_back(relative(fd, kc_p));
        }
        rec.rest = rest_ok ? relative(rest_fd, rest_kc) : std::numeric_limits<double>::quiet_NaN();
        double worst_rest = -1.0;
        for (std::size_t i = 0; i < n_eq && rest_ok; ++i) {
            if (std::abs(rest_fd[i] - rest_kc[i]) > worst_rest) {
                worst_rest = std::abs(rest_fd[i] - rest_kc[i]);
                rec.rest_worst_dof = static_cast<int>(i);
            }
        }
        for (std::size_t d = 0; d < du_.size() && rec.rest_worst_dof >= 0; ++d) {
            if (dofs_.equation[d] == rec.rest_worst_dof) {
                rec.rest_worst_dof = static_cast<int>(d);
                break;
            }
        }
        tangent_checks_.push_back(std::move(rec));
    }
    // Back to the iterate: every trial state as the Newton step found it.
    (void)residual_pass(t_end, du_, error);
    contacts_.set_probing(false);
    residual_ = residual_kept;
    reference_force_ = reference_kept;
}

} // namespace ifsim::fem
