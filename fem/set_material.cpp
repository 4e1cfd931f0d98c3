#include "fem/set_material.hpp"
#include "engine/parallel_chunks.hpp"
#include "engine/perturbation_tangent.hpp"

#include <algorithm>
#include <array>
#include <optional>

namespace ifsim::fem {
namespace {

constexpr std::array<int, 3> active_2d = {0, 1, 3};
constexpr std::array<int, 6> active_3d = {0, 1, 2, 3, 4, 5};

std::span<const int> active_components(int dim) {
    if (dim == 2) {
        return active_2d;
    }
    return active_3d;
}

// Point loops outside the batched update: fixed chunks, so the work split never depends on
// the thread count (each point writes only its own data anyway).
template <class F>
void for_points(std::size_t n, F&& body) {
    for_each_index(n, 512, std::forward<F>(body));
}

template <class M>
class SetMaterialOf final : public SetMaterial {
public:
    static constexpr int N = M::n_state;

    SetMaterialOf(const typename M::Params& params, std::size_t n) : params_(params), mp_(n) {
        params_.prepare();
    }

    std::string model_name() const override { return M::name; }
    int n_state() const override { return N; }
    std::size_t size() const override { return mp_.size(); }

    void set_state(std::size_t i, std::span<const double> y) override {
        StateVec<double, N> s{};
        std::copy_n(y.begin(), N, s.begin());
        mp_.set_state(i, s);
        lanes_stale_ = true;
    }
    void set_stress(std::size_t i, const Sym<double>& s) override {
        auto y = mp_.state(i);
        ifsim::set_stress(y, s);
        mp_.set_state(i, y);
        lanes_stale_ = true;
    }
    std::vector<double> state(std::size_t i) const override {
        const auto y = mp_.state(i);
        return {y.begin(), y.end()};
    }
    std::vector<double> trial_state(std::size_t i) const override {
        const auto y = mp_.trial_state(i);
        return {y.begin(), y.end()};
    }
    double* deps(int j) override { return mp_.deps(j); }
    const double* trial(int k) const override { return mp_.trial(k); }
    const double* committed(int k) const override { return mp_.committed(k); }

    UpdateReport update(const UpdateOptions& options) override {
        return batched_update(mp_, params_, options);
    }

    TangentReport tangent(const TangentSettings& ts, const UpdateOptions& options, int dim,
                          double* out) override {
        const auto comps = active_components(dim);
        const std::size_t nc = comps.size();
        const std::size_t n = mp_.size();
        TangentReport rep;
        if (ts.kind == TangentKind::rate) {
            for_points(n, [&](std::size_t i) { rate_tangent(i, comps, options, out); });
            return rep;
        }
        const PerturbationTangent<M> pt({ts.perturbation, ts.perturbation_floor, ts.fixed_substeps},
                                        comps);
        const std::size_t L = pt.lanes_per_point();
        if (!lanes_ || lanes_->size() != n * L) {
            lanes_.emplace(n * L);
            lanes_stale_ = true;
        }
        MaterialPoints<M>& lp = *lanes_;
        if (lanes_stale_) { // committed state changes only between increments
            for_points(n, [&](std::size_t i) {
                for (int k = 0; k < N; ++k) {
                    const double v = mp_.committed(k)[i];
                    for (std::size_t c = 0; c < L; ++c) {
                        lp.committed(k)[i * L + c] = v;
                    }
                }
            });
            lanes_stale_ = false;
        }
        delta_.resize(n);
        for_points(n, [&](std::size_t i) {
            Sym<double> d;
            for (int j = 0; j < 6; ++j) {
                d[j] = mp_.deps(j)[i];
            }
            delta_[i] = pt.set_increments(lp, i * L, d, mp_.substeps()[i]);
        });
        batched_update(lp, params_, options);
        rep.evaluations = static_cast<long>(n * L);
        fell_back_.assign(n, 0);
        for_points(n, [&](std::size_t i) {
            if (!pt.usable(lp, i * L, mp_.substeps()[i], mp_.rejected()[i])) {
                fell_back_[i] = 1;
                rate_tangent(i, comps, options, out);
                return;
            }
            double* Di = out + i * nc * nc;
            for (std::size_t r = 0; r < nc; ++r) {
                const double base = mp_.trial(comps[r])[i];
                for (std::size_t c = 0; c < nc; ++c) {
                    Di[r * nc + c] = pt.quotient(lp, i * L, comps[r], c, delta_[i], base);
                }
            }
        });
        for (unsigned char f : fell_back_) {
            rep.fallbacks += f;
        }
        return rep;
    }

    double shear_modulus(std::size_t i, const UpdateOptions& options) const override {
        const auto y = mp_.state(i);
        const auto cols =
            M::template rate_stiffness<double>(params_, options.settings, y, voigt::zero<double>());
        return (cols[3][3] + cols[4][4] + cols[5][5]) / 6.0; // d sigma_12 / d eps_12 = 2G
    }

    void commit() override {
        mp_.commit();
        lanes_stale_ = true;
    }

private:
    void rate_tangent(std::size_t i, std::span<const int> comps, const UpdateOptions& options,
                      double* out) const {
        const std::size_t nc = comps.size();
        Sym<double> d;
        for (int j = 0; j < 6; ++j) {
            d[j] = mp_.deps(j)[i];
        }
        const auto cols =
            M::template rate_stiffness<double>(params_, options.settings, mp_.state(i), d);
        double* Di = out + i * nc * nc;
        for (std::size_t r = 0; r < nc; ++r) {
            for (std::size_t c = 0; c < nc; ++c) {
                Di[r * nc + c] = cols[comps[c]][comps[r]];
            }
        }
    }

    typename M::Params params_;
    MaterialPoints<M> mp_;
    std::optional<MaterialPoints<M>> lanes_; // base + perturbed lanes of every point
    std::vector<double> delta_;              // perturbation of each point
    std::vector<unsigned char> fell_back_;   // per point: rate stiffness used
    bool lanes_stale_ = true;
};

} // namespace

std::unique_ptr<SetMaterial> make_set_material(const MaterialChoice& material, std::size_t points) {
    return std::visit(
        [&](const auto& params) -> std::unique_ptr<SetMaterial> {
            using M = typename model_of<std::decay_t<decltype(params)>>::type;
            return std::make_unique<SetMaterialOf<M>>(params, points);
        },
        material);
}

} // namespace ifsim::fem
