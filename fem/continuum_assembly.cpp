#include "fem/continuum_assembly.hpp"

#include <algorithm>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "engine/parallel_chunks.hpp"
#include "fem/continuum_force_loop.hpp"
#include "fem/continuum_set_data.hpp"
#include "fem/element_kernels.hpp"
#include "fem/phase_timer.hpp"

namespace ifsim::fem {

ContinuumAssembly::ContinuumAssembly(const Mesh& mesh, std::vector<ElementSetMaterial> materials,
                                     const SolverSettings& settings, double& k0_seconds)
    : settings_(settings) {
    geom_ = build_geometry(mesh, settings_.integration);
    const int ne = mesh.n_elements();
    const int nc = mesh.dim() == 2 ? 3 : 6;
    set_of_element_.assign(static_cast<std::size_t>(ne), -1);
    local_of_element_.assign(static_cast<std::size_t>(ne), -1);
    for (auto& spec : materials) {
        auto s = std::make_unique<SetData>();
        s->elements = mesh.element_set(spec.element_set);
        const int id = static_cast<int>(sets_.size());
        for (std::size_t l = 0; l < s->elements.size(); ++l) {
            const auto e = static_cast<std::size_t>(s->elements[l]);
            if (set_of_element_[e] >= 0) {
                throw std::invalid_argument(fmt::format(
                    "element {} is in two material sets ('{}' and '{}')", e,
                    sets_[static_cast<std::size_t>(set_of_element_[e])]->spec.element_set,
                    spec.element_set));
            }
            set_of_element_[e] = id;
            local_of_element_[e] = static_cast<int>(l);
        }
        const std::size_t points = s->elements.size() * static_cast<std::size_t>(geom_.nip);
        s->material = make_set_material(spec.material, points);
        if (static_cast<int>(spec.initial_state.size()) != s->material->n_state()) {
            throw std::invalid_argument(fmt::format(
                "element set '{}': the initial state of model {} needs {} values, got {}",
                spec.element_set, s->material->model_name(), s->material->n_state(),
                spec.initial_state.size()));
        }
        for (std::size_t i = 0; i < points; ++i) {
            s->material->set_state(i, spec.initial_state);
        }
        s->tangent.assign(points * static_cast<std::size_t>(nc * nc), 0.0);
        for (int j = 0; j < 6; ++j) {
            s->deps_cols[static_cast<std::size_t>(j)] = s->material->deps(j);
        }
        s->spec = std::move(spec);
        sets_.push_back(std::move(s));
    }
    for (int e = 0; e < ne; ++e) {
        if (set_of_element_[static_cast<std::size_t>(e)] < 0) {
            throw std::invalid_argument(
                fmt::format("element {} has no material (it is in none of the material sets)", e));
        }
    }
    apply_k0(mesh.dim(), k0_seconds);
    if (settings_.integration == Integration::reduced) {
        hourglass_stiffness(ne);
    }
    if (settings_.kinematics == Kinematics::updated_lagrangian) {
        reference_ = geom_;
        configured_u_.assign(static_cast<std::size_t>(mesh.n_nodes() * mesh.dim()), 0.0);
        increment_gradients_.assign(static_cast<std::size_t>(ne * geom_.nip) * 9, 0.0);
        for (auto& s : sets_) {
            s->rotations.assign(s->elements.size() * static_cast<std::size_t>(geom_.nip) * 9, 0.0);
        }
    }
}

ContinuumAssembly::~ContinuumAssembly() = default;

const ContinuumAssembly::SetData& ContinuumAssembly::set_of(int element) const {
    return *sets_[static_cast<std::size_t>(set_of_element_.at(static_cast<std::size_t>(element)))];
}

std::size_t ContinuumAssembly::point_of(int element, int q) const {
    return static_cast<std::size_t>(
        local_of_element_[static_cast<std::size_t>(element)] * geom_.nip + q);
}

std::vector<double> ContinuumAssembly::state(int element, int point) const {
    return set_of(element).material->state(point_of(element, point));
}

std::vector<double> ContinuumAssembly::committed_states() const {
    std::vector<double> out;
    for (const auto& set : sets_) {
        for (std::size_t i = 0; i < set->material->size(); ++i) {
            const std::vector<double> y = set->material->state(i);
            out.insert(out.end(), y.begin(), y.end());
        }
    }
    return out;
}

void ContinuumAssembly::restore_committed_states(const std::vector<double>& states) {
    std::size_t at = 0;
    for (const auto& set : sets_) {
        const auto n = static_cast<std::size_t>(set->material->n_state());
        for (std::size_t i = 0; i < set->material->size(); ++i) {
            if (at + n > states.size()) {
                throw std::invalid_argument("snapshot of another model: too few material states");
            }
            set->material->set_state(i, std::span<const double>(states.data() + at, n));
            at += n;
        }
    }
    if (at != states.size()) {
        throw std::invalid_argument("snapshot of another model: too many material states");
    }
}

std::vector<double> ContinuumAssembly::trial_state(int element, int point) const {
    return set_of(element).material->trial_state(point_of(element, point));
}

void ContinuumAssembly::element_stresses(int element, std::vector<Voigt6>& out, bool trial) const {
    const SetData& s = set_of(element);
    out.resize(static_cast<std::size_t>(geom_.nip));
    for (int q = 0; q < geom_.nip; ++q) {
        const auto p = point_of(element, q);
        const std::vector<double> y = trial ? s.material->trial_state(p) : s.material->state(p);
        for (std::size_t j = 0; j < 6; ++j) {
            out[static_cast<std::size_t>(q)][j] = y[j];
        }
    }
}

std::vector<double> ContinuumAssembly::densities(int n_elements) const {
    std::vector<double> density(static_cast<std::size_t>(n_elements), 0.0);
    for (const auto& s : sets_) {
        for (int e : s->elements) {
            density[static_cast<std::size_t>(e)] = s->spec.density;
        }
    }
    return density;
}

void ContinuumAssembly::apply_k0(int dim, double& k0_seconds) {
    for (auto& s : sets_) {
        if (!s->spec.k0) {
            continue;
        }
        PhaseTimer timer(k0_seconds);
        const K0Stress& k = *s->spec.k0;
        for (std::size_t l = 0; l < s->elements.size(); ++l) {
            const int e = s->elements[l];
            for (int q = 0; q < geom_.nip; ++q) {
                const double z = geom_.ip_coordinates[static_cast<std::size_t>(
                    (e * geom_.nip + q) * dim + dim - 1)];
                const double sv = -(k.surcharge + k.unit_weight * (k.surface - z));
                const double sh = k.k0 * sv;
                const Sym<double> stress = dim == 2 ? Sym<double>{sh, sv, sh, 0.0, 0.0, 0.0}
                                                    : Sym<double>{sh, sh, sv, 0.0, 0.0, 0.0};
                s->material->set_stress(
                    l * static_cast<std::size_t>(geom_.nip) + static_cast<std::size_t>(q), stress);
                ++counters_.k0_points;
            }
        }
    }
}

void ContinuumAssembly::hourglass_stiffness(int n_elements) {
    hourglass_k_.assign(static_cast<std::size_t>(n_elements), 0.0);
    for (auto& s : sets_) {
        for (std::size_t l = 0; l < s->elements.size(); ++l) {
            const auto e = static_cast<std::size_t>(s->elements[l]);
            const double G = s->spec.hourglass_shear_modulus > 0.0
                                 ? s->spec.hourglass_shear_modulus
                                 : s->material->shear_modulus(l, settings_.update);
            hourglass_k_[e] = settings_.hourglass_coefficient * G * geom_.hourglass_scale[e];
        }
    }
}

template <int D>
void ContinuumAssembly::strains_d(const Mesh& mesh, std::span<const double> du) {
    using Tr = ElementTraits<D>;
    for_each_index(
        static_cast<std::size_t>(mesh.n_elements()), settings_.element_grain, [&](std::size_t e) {
            SetData& s = *sets_[static_cast<std::size_t>(set_of_element_[e])];
            const int ei = static_cast<int>(e);
            double ue[Tr::ndof];
            for (int a = 0; a < Tr::nen; ++a) {
                const int n = mesh.node(ei, a);
                for (int i = 0; i < D; ++i) {
                    ue[a * D + i] = du[static_cast<std::size_t>(n * D + i)];
                }
            }
            for (int q = 0; q < geom_.nip; ++q) {
                const Sym<double> de = strain_at<D>(geom_.gradients(ei, q), ue);
                const auto p = static_cast<std::size_t>(local_of_element_[e] * geom_.nip + q);
                for (int j = 0; j < 6; ++j) {
                    s.deps_cols[static_cast<std::size_t>(j)][p] = de[static_cast<std::size_t>(j)];
                }
            }
        });
}

void ContinuumAssembly::strains(const Mesh& mesh, std::span<const double> du) {
    switch (settings_.kinematics) {
    case Kinematics::small_strain:
        if (mesh.dim() == 2) {
            strains_d<2>(mesh, du);
        } else {
            strains_d<3>(mesh, du);
        }
        return;
    case Kinematics::updated_lagrangian:
        if (mesh.dim() == 2) {
            strains_ul<2>(mesh, du);
        } else {
            strains_ul<3>(mesh, du);
        }
        return;
    }
}

bool ContinuumAssembly::update(std::string& error) {
    last_unreliable_ = 0;
    if (!inverted_.empty()) {
        error =
            fmt::format("the increment inverts {} element(s), first element {} (det F <= 0 "
                        "at an integration point)",
                        inverted_.size(), *std::min_element(inverted_.begin(), inverted_.end()));
        return false;
    }
    for (auto& s : sets_) {
        const UpdateReport rep = s->material->update(settings_.update);
        counters_.constitutive_evaluations += static_cast<long>(rep.points);
        last_unreliable_ += static_cast<long>(rep.unreliable);
        if (rep.failed > 0) {
            counters_.failed_point_updates += static_cast<long>(rep.failed);
            const auto local = static_cast<int>(rep.first_failed) / geom_.nip;
            error = fmt::format("{} material point(s) of set '{}' ({}) failed, first at element {} "
                                "integration point {}",
                                rep.failed, s->spec.element_set, s->material->model_name(),
                                s->elements[static_cast<std::size_t>(local)],
                                static_cast<int>(rep.first_failed) % geom_.nip);
            return false;
        }
    }
    return true;
}

void ContinuumAssembly::material_tangents(int dim) {
    for (auto& s : sets_) {
        const TangentReport rep =
            s->material->tangent(settings_.tangent, settings_.update, dim, s->tangent.data());
        counters_.constitutive_evaluations += rep.evaluations;
        counters_.tangent_evaluations += rep.evaluations;
        counters_.tangent_fallbacks += rep.fallbacks;
    }
}

void ContinuumAssembly::commit() {
    for (auto& s : sets_) {
        s->material->commit();
    }
    counters_.unreliable_committed += last_unreliable_;
}

template <int D>
void ContinuumAssembly::internal_force_d(const Mesh& mesh, const SparseSystem& system,
                                         std::span<const double> u, std::span<const double> du,
                                         std::vector<double>& f_int) {
    // Trial columns move on every commit (swap): look them up once per pass.
    auto& stress = stress_cols_;
    stress.resize(sets_.size());
    for (std::size_t k = 0; k < sets_.size(); ++k) {
        for (int j = 0; j < 6; ++j) {
            stress[k][static_cast<std::size_t>(j)] = sets_[k]->material->trial(j);
        }
    }
    force_loop<D>(
        mesh, system, u, du, f_int, geom_, [&](int e, std::size_t set, int local, double* f) {
            for (int q = 0; q < geom_.nip; ++q) {
                const auto p = static_cast<std::size_t>(local * geom_.nip + q);
                Sym<double> s;
                for (int j = 0; j < 6; ++j) {
                    s[static_cast<std::size_t>(j)] = stress[set][static_cast<std::size_t>(j)][p];
                }
                add_internal_force<D>(geom_.gradients(e, q), s, geom_.weight(e, q), f);
            }
        });
}

void ContinuumAssembly::internal_force(const Mesh& mesh, const SparseSystem& system,
                                       std::span<const double> u, std::span<const double> du,
                                       std::vector<double>& f) {
    switch (settings_.kinematics) {
    case Kinematics::small_strain:
        if (mesh.dim() == 2) {
            internal_force_d<2>(mesh, system, u, du, f);
        } else {
            internal_force_d<3>(mesh, system, u, du, f);
        }
        return;
    case Kinematics::updated_lagrangian:
        if (mesh.dim() == 2) {
            internal_force_ul<2>(mesh, system, u, du, f);
        } else {
            internal_force_ul<3>(mesh, system, u, du, f);
        }
        return;
    }
}

template <int D>
void ContinuumAssembly::tangent_d(const Mesh& mesh, SparseSystem& system,
                                  PrescribedCoupling* coupling) {
    using Tr = ElementTraits<D>;
    constexpr int nc = Tr::ncomp;
    const bool reduced = settings_.integration == Integration::reduced;
    for (int c = 0; c < system.n_colours(); ++c) {
        const auto elements = system.colour(c);
        for_each_index(elements.size(), colour_grain(elements.size()), [&](std::size_t k) {
            const int e = elements[k];
            const auto eu = static_cast<std::size_t>(e);
            const auto set = static_cast<std::size_t>(set_of_element_[eu]);
            const int local = local_of_element_[eu];
            Eigen::Matrix<double, Tr::ndof, Tr::ndof> K =
                Eigen::Matrix<double, Tr::ndof, Tr::ndof>::Zero();
            const double* tangent = sets_[set]->tangent.data();
            for (int q = 0; q < geom_.nip; ++q) {
                const auto p = static_cast<std::size_t>(local * geom_.nip + q);
                add_tangent<D>(geom_.gradients(e, q), tangent + p * nc * nc, geom_.weight(e, q), K);
            }
            if (reduced) {
                add_hourglass_tangent<D>(geom_.hourglass_gamma.data() +
                                             eu * Tr::n_hourglass * Tr::nen,
                                         hourglass_k_[eu], K);
            }
            scatter_tangent<D>(mesh, system, coupling, e, K.data());
        });
    }
}

// The element matrix (column-major ndof x ndof) into the system; with a coupling the prescribed
// columns times their increments into its right-hand side.
template <int D>
void ContinuumAssembly::scatter_tangent(const Mesh& mesh, SparseSystem& system,
                                        PrescribedCoupling* coupling, int e, const double* K) {
    constexpr int ndof = ElementTraits<D>::ndof;
    system.add_element_matrix(e, K);
    if (coupling == nullptr) {
        return;
    }
    // No two elements of a colour share an equation: the right-hand side needs no lock.
    const auto eq = system.element_equations(e);
    for (int b = 0; b < ndof; ++b) {
        const auto node_dof = static_cast<std::size_t>(mesh.node(e, b / D) * D + b % D);
        const double dp = coupling->prescribed_du[node_dof];
        if (eq[static_cast<std::size_t>(b)] >= 0 || dp == 0.0) {
            continue;
        }
        for (int a = 0; a < ndof; ++a) {
            const int r = eq[static_cast<std::size_t>(a)];
            if (r >= 0) {
                coupling->rhs[static_cast<std::size_t>(r)] -= K[b * ndof + a] * dp;
            }
        }
    }
}

template void ContinuumAssembly::scatter_tangent<2>(const Mesh&, SparseSystem&, PrescribedCoupling*,
                                                    int, const double*);
template void ContinuumAssembly::scatter_tangent<3>(const Mesh&, SparseSystem&, PrescribedCoupling*,
                                                    int, const double*);

void ContinuumAssembly::tangent(const Mesh& mesh, SparseSystem& system,
                                PrescribedCoupling* coupling) {
    switch (settings_.kinematics) {
    case Kinematics::small_strain:
        if (mesh.dim() == 2) {
            tangent_d<2>(mesh, system, coupling);
        } else {
            tangent_d<3>(mesh, system, coupling);
        }
        return;
    case Kinematics::updated_lagrangian:
        if (mesh.dim() == 2) {
            tangent_ul<2>(mesh, system, coupling);
        } else {
            tangent_ul<3>(mesh, system, coupling);
        }
        return;
    }
}

} // namespace ifsim::fem
