#pragma once
// Updates of a single material point and its tangent, for the point-level drivers (element
// test, interface test). The base update and its perturbed copies are lanes of one small
// batched update, like the contact points' perturbations. The perturbed lanes take the base's
// number of equal substeps, so the difference quotient sees no step-selection noise.

#include <algorithm>
#include <chrono>
#include <vector>

#include <Eigen/Dense>

#include "engine/batched_update.hpp"
#include "engine/perturbation_tangent.hpp"

namespace ifsim {

struct PointCounters {
    long constitutive_evaluations = 0;
    double substeps = 0.0;
    double rejected_substeps = 0.0;
    double rate_evaluations = 0.0;
    double seconds = 0.0; // time inside the batched updates
};

template <class M>
class PointEvaluator {
public:
    static constexpr int N = M::n_state;
    using State = StateVec<double, N>;

    struct Eval {
        State y;
        double status = 1.0;
        double substeps = 0.0;
    };

    PointEvaluator(const typename M::Params& params, const UpdateOptions& options,
                   PointCounters& counters)
        : params_(params), options_(options), counters_(counters), points_(7) {}

    // Update of y over deps (the base lane): adaptive, or with exactly `fixed_substeps` equal
    // substeps when it is > 0.
    Eval evaluate(const State& y, const Sym<double>& deps, double fixed_substeps = 0.0) {
        for (std::size_t i = 0; i < points_.size(); ++i) {
            points_.set_state(i, y);
            points_.set_deps(i, i == 0 ? deps : Sym<double>{});
            points_.fixed_substeps()[i] = i == 0 ? fixed_substeps : 0.0;
        }
        run(1);
        return Eval{points_.trial_state(0), points_.status()[0], points_.substeps()[0]};
    }

    // d sigma_rows / d deps_cols of the integrated update at (y, deps), by forward
    // differences with a strain perturbation of relative size `perturbation`.
    Eigen::MatrixXd jacobian(const State& y, const Sym<double>& deps, const std::vector<int>& rows,
                             const std::vector<int>& cols, double base_substeps,
                             double perturbation) {
        // The fixed scheme of engine/perturbation_tangent.hpp: base and perturbed lanes with
        // the base update's substeps; the lanes beyond them repeat the base.
        const PerturbationTangent<M> pt({perturbation, 1.0e-6, true}, cols);
        for (std::size_t i = 0; i < points_.size(); ++i) {
            points_.set_state(i, y);
            points_.set_deps(i, deps);
            points_.fixed_substeps()[i] = std::max(1.0, base_substeps);
        }
        const double delta = pt.set_increments(points_, 0, deps, base_substeps);
        run(static_cast<long>(cols.size()) + 1);
        Eigen::MatrixXd J(static_cast<Eigen::Index>(rows.size()),
                          static_cast<Eigen::Index>(cols.size()));
        for (std::size_t c = 0; c < cols.size(); ++c) {
            for (std::size_t r = 0; r < rows.size(); ++r) {
                J(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) =
                    pt.quotient(points_, 0, rows[r], c, delta, 0.0);
            }
        }
        return J;
    }

    // The model's cheap rate stiffness, same shape as jacobian().
    Eigen::MatrixXd rate_jacobian(const State& y, const Sym<double>& deps,
                                  const std::vector<int>& rows, const std::vector<int>& cols) {
        const auto c = M::template rate_stiffness<double>(params_, options_.settings, y, deps);
        Eigen::MatrixXd J(static_cast<Eigen::Index>(rows.size()),
                          static_cast<Eigen::Index>(cols.size()));
        for (std::size_t j = 0; j < cols.size(); ++j) {
            for (std::size_t r = 0; r < rows.size(); ++r) {
                J(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(j)) = c[cols[j]][rows[r]];
            }
        }
        return J;
    }

private:
    void run(long evaluations) {
        const auto t0 = std::chrono::steady_clock::now();
        batched_update(points_, params_, options_);
        counters_.seconds +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        counters_.constitutive_evaluations += evaluations;
        for (long i = 0; i < evaluations; ++i) {
            counters_.substeps += points_.substeps()[i];
            counters_.rejected_substeps += points_.rejected()[i];
            counters_.rate_evaluations += points_.rate_evaluations()[i];
        }
    }

    const typename M::Params& params_;
    const UpdateOptions& options_;
    PointCounters& counters_;
    MaterialPoints<M> points_;
};

} // namespace ifsim
