#pragma once
// The consistent tangent of the integrated update by forward differences, the perturbed
// copies of every point being lanes of one batched update (as the contact points' Eq. 37
// lanes are for Algorithm 1). One scheme for the FE element sets (many points,
// fem/set_material.cpp) and the point-level drivers (one point, engine/point_evaluator.hpp).
//
// Lanes of a point: [its base, fixed scheme only] then one lane per perturbed strain
// component, each with the point's increment plus delta on that component,
// delta = relative * max(|deps|, floor).
//  - adaptive: the lanes integrate adaptively like the base update; a lane whose accepted or
//    rejected substep count differs from the base took another step sequence and the point's
//    quotient is not usable (the caller falls back to the rate stiffness);
//  - fixed: base and perturbed lanes all take max(1, base substeps) equal substeps: free of
//    step-selection noise, off by O(substep size) where adaptive steps resolve more.

#include <algorithm>
#include <cstddef>
#include <span>

#include "engine/material_points.hpp"
#include "kernels/voigt.hpp"

namespace ifsim {

struct PerturbationScheme {
    double relative = 1.0e-7; // perturbation relative to the norm of the strain increment
    double floor = 1.0e-6;    // strain norm used when the increment is smaller
    bool fixed_substeps = false;
};

template <class M>
class PerturbationTangent {
public:
    PerturbationTangent(const PerturbationScheme& scheme, std::span<const int> cols)
        : scheme_(scheme), cols_(cols) {}

    std::size_t first_perturbed() const { return scheme_.fixed_substeps ? 1 : 0; }
    std::size_t lanes_per_point() const { return first_perturbed() + cols_.size(); }

    // The increments (and fixed substep counts) of point i's lanes, starting at lane `at`,
    // for the point's increment d and its base update's accepted substeps; returns delta.
    double set_increments(MaterialPoints<M>& lanes, std::size_t at, const Sym<double>& d,
                          double base_substeps) const {
        const double delta = scheme_.relative * std::max(voigt::norm(d), scheme_.floor);
        const double fixed = scheme_.fixed_substeps ? std::max(1.0, base_substeps) : 0.0;
        for (std::size_t c = 0; c < lanes_per_point(); ++c) {
            const std::size_t lane = at + c;
            for (int j = 0; j < 6; ++j) {
                lanes.deps(j)[lane] = d[j];
            }
            if (c >= first_perturbed()) {
                lanes.deps(cols_[c - first_perturbed()])[lane] += delta;
            }
            lanes.fixed_substeps()[lane] = fixed;
        }
        return delta;
    }

    // After the batched update: whether point i's lanes give a quotient (no lane failed and,
    // adaptive, every lane took the base's step sequence).
    bool usable(const MaterialPoints<M>& lanes, std::size_t at, double base_substeps,
                double base_rejected) const {
        for (std::size_t c = 0; c < lanes_per_point(); ++c) {
            const std::size_t lane = at + c;
            if (lanes.status()[lane] < -0.5) {
                return false;
            }
            if (!scheme_.fixed_substeps && (lanes.substeps()[lane] != base_substeps ||
                                            lanes.rejected()[lane] != base_rejected)) {
                return false;
            }
        }
        return true;
    }

    // d y_row / d eps_col = (lane trial - base trial) / delta for a state entry `row`; the base
    // is the point's base lane (fixed) or `adaptive_base` (the base update's trial value).
    double quotient(const MaterialPoints<M>& lanes, std::size_t at, int row, std::size_t col,
                    double delta, double adaptive_base) const {
        const double* y = lanes.trial(row);
        const double base = scheme_.fixed_substeps ? y[at] : adaptive_base;
        return (y[at + first_perturbed() + col] - base) / delta;
    }

private:
    PerturbationScheme scheme_;
    std::span<const int> cols_;
};

} // namespace ifsim
