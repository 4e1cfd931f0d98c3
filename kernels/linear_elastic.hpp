#pragma once
// Isotropic linear elasticity (Hooke), the reference model of the engine's tests.
// State: [0..5] stress, [6] void ratio (follows the volumetric strain).

#include "kernels/explicit_integration.hpp"
#include "kernels/model_api.hpp"

namespace ifsim {

struct LinearElasticParams {
    double E = 1.0e5; // Young's modulus, kPa
    double nu = 0.25; // Poisson's ratio
    void prepare() {}
};

struct LinearElastic {
    static constexpr const char* name = "linear-elastic";
    static constexpr int n_state = 7;
    // One closed-form step: no substeps, nothing to refill.
    static constexpr bool lane_refill = false;
    static constexpr bool pressure_floor = false;
    using Params = LinearElasticParams;
    template <class T>
    using State = StateVec<T, n_state>;

    template <class T>
    static Sym<T> stress_increment(const Params& p, const Sym<T>& de) {
        const double G = p.E / (2.0 * (1.0 + p.nu));
        const double lambda = p.E * p.nu / ((1.0 + p.nu) * (1.0 - 2.0 * p.nu));
        const T tr = voigt::trace(de);
        Sym<T> ds;
        for (int i = 0; i < 6; ++i) {
            ds[i] = 2.0 * G * de[i];
        }
        for (int i = 0; i < 3; ++i) {
            ds[i] += lambda * tr;
        }
        return ds;
    }

    // Exact in one step: linear elasticity needs no substeps. Linear elasticity has no
    // pressure floor either: tension is a valid state of this model.
    template <class T>
    static void integrate(const Params& p, const IntegrationSettings&, const SubstepControl<T>&,
                          State<T>& y, const Sym<T>& deps, UpdateStats<T>& stats) {
        set_stress(y, voigt::add(stress_of(y), stress_increment(p, deps)));
        y[6] = y[6] + (1.0 + y[6]) * voigt::trace(deps);
        stats.substeps += T(1.0);
        stats.rate_evaluations += T(1.0);
    }

    template <class T>
    static std::array<Sym<T>, 6> rate_stiffness(const Params& p, const IntegrationSettings&,
                                                const State<T>&, const Sym<T>&) {
        std::array<Sym<T>, 6> cols;
        for (int j = 0; j < 6; ++j) {
            Sym<T> unit = voigt::zero<T>();
            unit[j] = T(1.0);
            cols[j] = stress_increment(p, unit);
        }
        return cols;
    }
};

} // namespace ifsim
