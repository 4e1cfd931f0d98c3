#pragma once
// Where a committed material state leaves the region the model describes sand in, counted per
// run so that a completed run says so (summary.json warnings, quality "degraded") instead of
// passing it off as a result: a tensile principal stress (cohesionless sand carries none; the
// models' own equations can still produce one, e.g. Sanisand in extension from 1 kPa ends at
// s11 = +0.13 kPa, converged to 1e-6), and, for hypoplasticity, a void ratio outside
// [e_d(p), e_i(p)] of the Bauer law (the bounds of the model's admissible states). The checks
// look at states after they are computed; they change nothing.

#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>

#include <Eigen/Eigenvalues>

#include "engine/model_registry.hpp"

namespace ifsim {

// Largest tensile principal stress (kPa) taken as round-off, not tension.
inline constexpr double tension_tolerance = 1.0e-6;
// Relative excess over a hypoplastic void-ratio bound taken as round-off.
inline constexpr double void_ratio_tolerance = 1.0e-9;

struct AdmissibilityCount {
    long rows = 0;       // rows (committed states) outside
    int first_step = -1; // step of the first one
    double worst = 0.0;  // largest excess (kPa, or void ratio)
    int worst_step = -1;
    void add(int step, double excess) {
        if (rows++ == 0) {
            first_step = step;
        }
        if (excess > worst) {
            worst = excess;
            worst_step = step;
        }
    }
};

struct StateAdmissibility {
    AdmissibilityCount tension;    // largest principal stress above tension_tolerance
    AdmissibilityCount void_ratio; // outside [e_d(p), e_i(p)] (hypoplasticity), e <= 0 (any)
};

inline double largest_principal_stress(const double* y) {
    Eigen::Matrix3d s;
    s << y[0], y[3], y[4], y[3], y[1], y[5], y[4], y[5], y[2];
    return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(s, Eigen::EigenvaluesOnly)
        .eigenvalues()
        .maxCoeff();
}

// Excess of e over the model's bounds at the state's mean pressure (0 inside).
template <class Params>
double void_ratio_excess(const Params& p, const double* y) {
    const double e = y[state_index::void_ratio];
    if (!(e > 0.0)) {
        return std::isfinite(e) ? -e + 1.0e-300 : 1.0e300;
    }
    if constexpr (std::is_same_v<Params, HypoplasticityParams>) {
        const double tr = y[0] + y[1] + y[2];
        if (!(tr < 0.0)) {
            return 0.0; // no pressure, no Bauer bounds (the tension check speaks)
        }
        const double bauer = std::exp(-std::pow(-tr / p.h_s, p.n));
        const double e_i = p.e_i0 * bauer, e_d = p.e_d0 * bauer;
        const double above = e - e_i * (1.0 + void_ratio_tolerance);
        const double below = e_d * (1.0 - void_ratio_tolerance) - e;
        return std::max({above, below, 0.0});
    }
    return 0.0;
}

// Counts the state of one committed row (model state layout of kernels/model_api.hpp).
// Linear elasticity is no sand model: it is not checked.
inline void check_state(const MaterialChoice& material, const double* y, int step,
                        StateAdmissibility& a) {
    std::visit(
        [&](const auto& p) {
            using P = std::decay_t<decltype(p)>;
            if constexpr (!std::is_same_v<P, LinearElasticParams>) {
                const double s_max = largest_principal_stress(y);
                if (s_max > tension_tolerance) {
                    a.tension.add(step, s_max);
                }
                const double excess = void_ratio_excess(p, y);
                if (excess > 0.0) {
                    a.void_ratio.add(step, excess);
                }
            }
        },
        material);
}

} // namespace ifsim
