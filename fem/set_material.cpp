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
        if (kept_) {
            kept_->set_state(i, s);
        }
        lanes_stale_ = true;
    }
    void set_stress(std::size_t i, const Sym<double>& s) override {
        auto y = committed_state(i);
        ifsim::set_stress(y, s);
        set_state(i, std::span<const double>(y.data(), N));
    }
    std::vector<double> state(std::size_t i) const override {
        const auto y = committed_state(i);
        return {y.begin(), y.end()};
    }
    std::vector<double> trial_state(std::size_t i) const override {
        const auto y = mp_.trial_state(i);
        return {y.begin(), y.end()};
    }
    double* deps(int j) override { return mp_.deps(j); }
    const double* trial(int k) const override { return mp_.trial(k); }
    const double* committed(int k) const override {
        return kept_ ? kept_->committed(k) : mp_.committed(k);
    }

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
        const auto y = committed_state(i);
        const auto cols =
            M::template rate_stiffness<double>(params_, options.settings, y, voigt::zero<double>());
        return (cols[3][3] + cols[4][4] + cols[5][5]) / 6.0; // d sigma_12 / d eps_12 = 2G
    }

    void commit() override {
        mp_.commit();
        if (kept_) { // the new committed state is kept unturned for the next increment
            for (int k = 0; k < N; ++k) {
                std::copy_n(mp_.committed(k), mp_.padded(), kept_->committed(k));
            }
        }
        lanes_stale_ = true;
    }

    void rotate_start(const double* rotations) override {
        if (!kept_) {
            kept_.emplace(mp_.size());
            for (int k = 0; k < N; ++k) {
                std::copy_n(mp_.committed(k), mp_.padded(), kept_->committed(k));
            }
        }
        for_points(mp_.size(), [&](std::size_t i) {
            const double* r = rotations + 9 * i;
            for (int offset : tensor_offsets) {
                double s[3][3];
                const double* v[6];
                for (int j = 0; j < 6; ++j) {
                    v[j] = kept_->committed(offset + j) + i;
                }
                s[0][0] = *v[0];
                s[1][1] = *v[1];
                s[2][2] = *v[2];
                s[0][1] = s[1][0] = *v[3];
                s[0][2] = s[2][0] = *v[4];
                s[1][2] = s[2][1] = *v[5];
                double rs[3][3] = {};
                for (int a = 0; a < 3; ++a) {
                    for (int b = 0; b < 3; ++b) {
                        for (int c = 0; c < 3; ++c) {
                            rs[a][b] += r[3 * a + c] * s[c][b];
                        }
                    }
                }
                double t[3][3] = {};
                for (int a = 0; a < 3; ++a) {
                    for (int b = 0; b < 3; ++b) {
                        for (int c = 0; c < 3; ++c) {
                            t[a][b] += rs[a][c] * r[3 * b + c];
                        }
                    }
                }
                const double out[6] = {t[0][0], t[1][1], t[2][2], t[0][1], t[0][2], t[1][2]};
                for (int j = 0; j < 6; ++j) {
                    mp_.committed(offset + j)[i] = out[j];
                }
            }
            for (int k = 0; k < N; ++k) { // scalars (void ratio, ...) as committed
                if (!is_tensor_entry(k)) {
                    mp_.committed(k)[i] = kept_->committed(k)[i];
                }
            }
        });
        lanes_stale_ = true;
    }

private:
    // The model state's symmetric tensors: the stress and every history block of six
    // (kernels/model_api.hpp: stress 0..5, void ratio 6, blocks from 7, then scalars such as
    // the carried substep size).
    static constexpr auto tensor_offsets = [] {
        constexpr std::size_t n = ModelEntry<M>::history_prefixes.size();
        static_assert(7 + 6 * static_cast<int>(n) + (CarriesSubstep<M> ? 1 : 0) == N,
                      "history blocks of six after e, then the carried substep");
        std::array<int, n + 1> out{};
        for (std::size_t k = 0; k <= n; ++k) {
            out[k] = k == 0 ? 0 : 7 + 6 * static_cast<int>(k - 1);
        }
        return out;
    }();
    static constexpr bool is_tensor_entry(int k) {
        for (int offset : tensor_offsets) {
            if (k >= offset && k < offset + 6) {
                return true;
            }
        }
        return false;
    }
    StateVec<double, N> committed_state(std::size_t i) const {
        return kept_ ? kept_->state(i) : mp_.state(i);
    }

    void rate_tangent(std::size_t i, std::span<const int> comps, const UpdateOptions& options,
                      double* out) const {
        const std::size_t nc = comps.size();
        Sym<double> d;
        for (int j = 0; j < 6; ++j) {
            d[j] = mp_.deps(j)[i];
        }
        // At the (turned) start of the update, as the perturbation lanes.
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
    // Updated Lagrangian only: the committed state, unturned, while mp_'s committed columns
    // hold the turned start of the running increment.
    std::optional<MaterialPoints<M>> kept_;
    std::vector<double> delta_;            // perturbation of each point
    std::vector<unsigned char> fell_back_; // per point: rate stiffness used
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
