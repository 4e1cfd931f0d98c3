#include "fem/static_solver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/parallel_chunks.hpp"
#include "fem/element_kernels.hpp"
#include "fem/loads.hpp"
#include "fem/phase_timer.hpp"

namespace ifsim::fem {
namespace {

double norm2(std::span<const double> v) {
    double s = 0.0;
    for (double x : v) {
        s += x * x;
    }
    return std::sqrt(s);
}

// The last relative residuals of a Newton iteration, for a failure message.
std::string residual_trace(const std::vector<double>& residuals) {
    const std::size_t n = residuals.size();
    const std::size_t from = n > 8 ? n - 8 : 0;
    std::string out = from > 0 ? "... " : "";
    for (std::size_t i = from; i < n; ++i) {
        out += fmt::format("{}{:.1e}", i > from ? " " : "", residuals[i]);
    }
    return out;
}

} // namespace

struct StaticSolver::SetData {
    ElementSetMaterial spec;
    std::unique_ptr<SetMaterial> material;
    std::vector<int> elements;
    std::vector<double> tangent;        // point * nc * nc
    std::array<double*, 6> deps_cols{}; // stable: the increment columns are never swapped
};

StaticSolver::StaticSolver(Mesh mesh, std::vector<ElementSetMaterial> materials,
                           SolverSettings settings)
    : mesh_(std::move(mesh)), settings_(std::move(settings)), linear_(settings_.linear_solver) {
    mesh_.validate();
    geom_ = build_geometry(mesh_, settings_.integration);
    const int ne = mesh_.n_elements();
    const int D = mesh_.dim();
    const int nc = D == 2 ? 3 : 6;
    set_of_element_.assign(static_cast<std::size_t>(ne), -1);
    local_of_element_.assign(static_cast<std::size_t>(ne), -1);
    for (auto& spec : materials) {
        auto s = std::make_unique<SetData>();
        s->elements = mesh_.element_set(spec.element_set);
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
    const auto n_dofs = static_cast<std::size_t>(mesh_.n_nodes() * D);
    u_.assign(n_dofs, 0.0);
    du_.assign(n_dofs, 0.0);
    f_int_.assign(n_dofs, 0.0);
    f_int_committed_.assign(n_dofs, 0.0);
    f_ext_.assign(n_dofs, 0.0);
    f_ext_committed_.assign(n_dofs, 0.0);
    apply_k0();
    if (settings_.integration == Integration::reduced) {
        hourglass_stiffness();
    }
}

StaticSolver::~StaticSolver() = default;

const SolverCounters& StaticSolver::counters() const {
    counters_.linear = linear_.counters();
    counters_.contact_pairings = 0;
    counters_.contact_evaluations = 0;
    counters_.contact_point_updates = 0.0;
    counters_.contact_lanes = 0.0;
    counters_.contact_subincrements = 0.0;
    counters_.contact_constitutive_evaluations = 0.0;
    counters_.contact_failures = 0;
    counters_.contact_relaxed_reruns = 0;
    counters_.contact_relaxed_point_updates = 0.0;
    for (const auto& c : contacts_) {
        const ContactPairCounters& k = c->counters();
        counters_.contact_pairings += c->kinematics().projection_counters().pairings;
        counters_.contact_evaluations += k.evaluations;
        counters_.contact_point_updates += k.point_updates;
        counters_.contact_lanes += k.lanes;
        counters_.contact_subincrements += k.subincrements;
        counters_.contact_constitutive_evaluations += k.constitutive_evaluations;
        counters_.contact_failures += k.failed_evaluations;
        counters_.contact_relaxed_reruns += k.relaxed_reruns;
        counters_.contact_relaxed_point_updates += k.relaxed_point_updates;
    }
    return counters_;
}

SolverTimers StaticSolver::timers() const {
    SolverTimers t = timers_;
    t.contact_scatter += contact_matrix_s_;
    for (const auto& c : contacts_) {
        t.contact_search += c->timers().search;
        t.contact_gather += c->timers().gather;
        t.contact_kernels += c->timers().kernels;
        t.contact_scatter += c->timers().scatter;
    }
    return t;
}

void StaticSolver::add_contact(ContactPairSpec spec) {
    if (stage_count_ > 0) {
        throw std::logic_error("contact pairs are added before the first stage");
    }
    contacts_.push_back(make_contact_pair(mesh_, std::move(spec)));
}

void StaticSolver::element_stresses(int element, std::vector<Voigt6>& out, bool trial) const {
    const auto e = static_cast<std::size_t>(element);
    const SetData& s = *sets_[static_cast<std::size_t>(set_of_element_.at(e))];
    out.resize(static_cast<std::size_t>(geom_.nip));
    for (int q = 0; q < geom_.nip; ++q) {
        const auto p = static_cast<std::size_t>(local_of_element_[e] * geom_.nip + q);
        const std::vector<double> y = trial ? s.material->trial_state(p) : s.material->state(p);
        for (std::size_t j = 0; j < 6; ++j) {
            out[static_cast<std::size_t>(q)][j] = y[j];
        }
    }
}

void StaticSolver::begin_contacts(bool dofs_changed) {
    bool changed = dofs_changed;
    const ElementStresses stresses = [this](int e, std::vector<Voigt6>& out) {
        element_stresses(e, out);
    };
    for (auto& c : contacts_) {
        changed = c->begin_increment(mesh_, u_, stresses) || changed;
    }
    if (!changed && system_) {
        return;
    }
    std::vector<std::array<int, 2>> couplings;
    for (const auto& c : contacts_) {
        const auto more = c->couplings();
        couplings.insert(couplings.end(), more.begin(), more.end());
    }
    system_ = std::make_unique<SparseSystem>(mesh_, dofs_, couplings);
    ++counters_.patterns_built;
    counters_.contact_pattern_rebuilds += dofs_changed ? 0 : 1;
}

std::vector<double> StaticSolver::state(int element, int point) const {
    const auto e = static_cast<std::size_t>(element);
    const SetData& s = *sets_[static_cast<std::size_t>(set_of_element_.at(e))];
    return s.material->state(static_cast<std::size_t>(local_of_element_[e] * geom_.nip + point));
}

std::vector<double> StaticSolver::trial_state(int element, int point) const {
    const auto e = static_cast<std::size_t>(element);
    const SetData& s = *sets_[static_cast<std::size_t>(set_of_element_.at(e))];
    return s.material->trial_state(
        static_cast<std::size_t>(local_of_element_[e] * geom_.nip + point));
}

void StaticSolver::apply_k0() {
    const int D = mesh_.dim();
    for (auto& s : sets_) {
        if (!s->spec.k0) {
            continue;
        }
        PhaseTimer timer(timers_.k0);
        const K0Stress& k = *s->spec.k0;
        for (std::size_t l = 0; l < s->elements.size(); ++l) {
            const int e = s->elements[l];
            for (int q = 0; q < geom_.nip; ++q) {
                const double z =
                    geom_.ip_coordinates[static_cast<std::size_t>((e * geom_.nip + q) * D + D - 1)];
                const double sv = -(k.surcharge + k.unit_weight * (k.surface - z));
                const double sh = k.k0 * sv;
                const Sym<double> stress = D == 2 ? Sym<double>{sh, sv, sh, 0.0, 0.0, 0.0}
                                                  : Sym<double>{sh, sh, sv, 0.0, 0.0, 0.0};
                s->material->set_stress(
                    l * static_cast<std::size_t>(geom_.nip) + static_cast<std::size_t>(q), stress);
                ++counters_.k0_points;
            }
        }
    }
}

void StaticSolver::hourglass_stiffness() {
    hourglass_k_.assign(static_cast<std::size_t>(mesh_.n_elements()), 0.0);
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

void StaticSolver::begin_stage(const Stage& stage) {
    DofMap next = build_dof_map(mesh_, stage); // throws before anything changes
    for (const GroundSpring& g : stage.springs) {
        if (g.direction < 0 || g.direction >= mesh_.dim()) {
            throw std::invalid_argument(
                fmt::format("spring direction {} on node set '{}' does not exist in {}D",
                            g.direction, g.node_set, mesh_.dim()));
        }
        mesh_.node_set(g.node_set);
    }
    for (const FacePressure& p : stage.pressures) {
        mesh_.face_set(p.face_set);
    }
    stage_ = stage;
    ++stage_count_;
    const bool dofs_changed = !system_ || next.equation != dofs_.equation;
    dofs_ = std::move(next);
    if (!contacts_.empty()) {
        begin_contacts(dofs_changed);
    } else if (dofs_changed) {
        system_ = std::make_unique<SparseSystem>(mesh_, dofs_);
        ++counters_.patterns_built;
    }
    u_stage_start_ = u_;
    dt_last_ = 0.0;
    const int D = mesh_.dim();

    std::vector<Spring> springs;
    for (const GroundSpring& g : stage.springs) {
        const auto& nodes = mesh_.node_set(g.node_set);
        Spring sp;
        sp.key = fmt::format("{}#{}", g.node_set, g.direction);
        sp.stiffness = nodes.empty() ? 0.0 : g.total_stiffness / double(nodes.size());
        for (int n : nodes) {
            sp.dofs.push_back(n * D + g.direction);
        }
        const auto prev = std::find_if(springs_.begin(), springs_.end(),
                                       [&](const Spring& o) { return o.key == sp.key; });
        if (prev != springs_.end()) {
            sp.reference = prev->reference; // the spring continues from the previous stage
        } else {
            for (int d : sp.dofs) {
                sp.reference.push_back(u_[static_cast<std::size_t>(d)]);
            }
        }
        springs.push_back(std::move(sp));
    }
    springs_ = std::move(springs);

    if (stage.gravity && gravity_unit_.empty()) {
        PhaseTimer timer(timers_.gravity);
        std::vector<double> density(static_cast<std::size_t>(mesh_.n_elements()), 0.0);
        for (const auto& s : sets_) {
            for (int e : s->elements) {
                density[static_cast<std::size_t>(e)] = s->spec.density;
            }
        }
        gravity_unit_ = unit_gravity_forces(mesh_, density);
        ++counters_.gravity_load_builds;
    }
    for (const FacePressure& p : stage.pressures) {
        if (!pressure_unit_.contains(p.face_set)) {
            PhaseTimer timer(timers_.pressure);
            pressure_unit_[p.face_set] = unit_pressure_forces(mesh_, p.face_set);
            ++counters_.pressure_load_builds;
        }
    }
    residual_.assign(static_cast<std::size_t>(dofs_.n_equations), 0.0);
    correction_.assign(static_cast<std::size_t>(dofs_.n_equations), 0.0);
}

void StaticSolver::external_force(double t, std::vector<double>& f) {
    std::fill(f.begin(), f.end(), 0.0);
    if (stage_->gravity) {
        PhaseTimer timer(timers_.gravity);
        const double g = stage_->gravity->from + (stage_->gravity->to - stage_->gravity->from) * t;
        for (std::size_t d = 0; d < f.size(); ++d) {
            f[d] += g * gravity_unit_[d];
        }
        ++counters_.gravity_load_applications;
    }
    if (!stage_->pressures.empty()) {
        PhaseTimer timer(timers_.pressure);
        for (const FacePressure& p : stage_->pressures) {
            const double v = p.from + (p.to - p.from) * t;
            const auto& unit = pressure_unit_.at(p.face_set);
            for (std::size_t d = 0; d < f.size(); ++d) {
                f[d] += v * unit[d];
            }
        }
    }
}

template <int D>
void StaticSolver::strains_d(std::span<const double> du) {
    using Tr = ElementTraits<D>;
    for_each_index(
        static_cast<std::size_t>(mesh_.n_elements()), settings_.element_grain, [&](std::size_t e) {
            SetData& s = *sets_[static_cast<std::size_t>(set_of_element_[e])];
            const int ei = static_cast<int>(e);
            double ue[Tr::ndof];
            for (int a = 0; a < Tr::nen; ++a) {
                const int n = mesh_.node(ei, a);
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

void StaticSolver::compute_strains(std::span<const double> du) {
    if (mesh_.dim() == 2) {
        strains_d<2>(du);
    } else {
        strains_d<3>(du);
    }
}

bool StaticSolver::update_materials(bool with_tangent, std::string& error) {
    if (!with_tangent) {
        for (auto& s : sets_) {
            const UpdateReport rep = s->material->update(settings_.update);
            counters_.constitutive_evaluations += static_cast<long>(rep.points);
            if (rep.failed > 0) {
                counters_.failed_point_updates += static_cast<long>(rep.failed);
                const auto local = static_cast<int>(rep.first_failed) / geom_.nip;
                error =
                    fmt::format("{} material point(s) of set '{}' ({}) failed, first at element {} "
                                "integration point {}",
                                rep.failed, s->spec.element_set, s->material->model_name(),
                                s->elements[static_cast<std::size_t>(local)],
                                static_cast<int>(rep.first_failed) % geom_.nip);
                return false;
            }
        }
        return true;
    }
    for (auto& s : sets_) {
        const TangentReport rep = s->material->tangent(settings_.tangent, settings_.update,
                                                       mesh_.dim(), s->tangent.data());
        counters_.constitutive_evaluations += rep.evaluations;
        counters_.tangent_evaluations += rep.evaluations;
        counters_.tangent_fallbacks += rep.fallbacks;
    }
    return true;
}

template <int D>
void StaticSolver::assemble_d(std::span<const double> du, bool with_tangent) {
    using Tr = ElementTraits<D>;
    constexpr int nc = Tr::ncomp;
    const bool reduced = settings_.integration == Integration::reduced;
    // Trial columns move on every commit (swap): look them up once per pass.
    auto& stress = stress_cols_;
    stress.resize(sets_.size());
    for (std::size_t k = 0; k < sets_.size(); ++k) {
        for (int j = 0; j < 6; ++j) {
            stress[k][static_cast<std::size_t>(j)] = sets_[k]->material->trial(j);
        }
    }
    if (with_tangent) {
        system_->zero_values();
    } else {
        std::fill(f_int_.begin(), f_int_.end(), 0.0);
    }
    for (int c = 0; c < system_->n_colours(); ++c) {
        const auto elements = system_->colour(c);
        for_each_index(elements.size(), settings_.element_grain, [&](std::size_t k) {
            const int e = elements[k];
            const auto eu = static_cast<std::size_t>(e);
            const auto set = static_cast<std::size_t>(set_of_element_[eu]);
            const int local = local_of_element_[eu];
            int dof[Tr::ndof];
            for (int a = 0; a < Tr::nen; ++a) {
                for (int i = 0; i < D; ++i) {
                    dof[a * D + i] = mesh_.node(e, a) * D + i;
                }
            }
            if (with_tangent) {
                Eigen::Matrix<double, Tr::ndof, Tr::ndof> K =
                    Eigen::Matrix<double, Tr::ndof, Tr::ndof>::Zero();
                const double* tangent = sets_[set]->tangent.data();
                for (int q = 0; q < geom_.nip; ++q) {
                    const auto p = static_cast<std::size_t>(local * geom_.nip + q);
                    add_tangent<D>(geom_.gradients(e, q), tangent + p * nc * nc, geom_.weight(e, q),
                                   K);
                }
                if (reduced) {
                    add_hourglass_tangent<D>(geom_.hourglass_gamma.data() +
                                                 eu * Tr::n_hourglass * Tr::nen,
                                             hourglass_k_[eu], K);
                }
                system_->add_element_matrix(e, K.data());
                return;
            }
            double f[Tr::ndof] = {};
            for (int q = 0; q < geom_.nip; ++q) {
                const auto p = static_cast<std::size_t>(local * geom_.nip + q);
                Sym<double> s;
                for (int j = 0; j < 6; ++j) {
                    s[static_cast<std::size_t>(j)] = stress[set][static_cast<std::size_t>(j)][p];
                }
                add_internal_force<D>(geom_.gradients(e, q), s, geom_.weight(e, q), f);
            }
            if (reduced) { // hourglass force of the total displacement
                double ut[Tr::ndof];
                for (int k2 = 0; k2 < Tr::ndof; ++k2) {
                    const auto d = static_cast<std::size_t>(dof[k2]);
                    ut[k2] = u_[d] + du[d];
                }
                add_hourglass_force<D>(geom_.hourglass_gamma.data() +
                                           eu * Tr::n_hourglass * Tr::nen,
                                       hourglass_k_[eu], ut, f);
            }
            for (int k2 = 0; k2 < Tr::ndof; ++k2) {
                f_int_[static_cast<std::size_t>(dof[k2])] += f[k2];
            }
        });
    }
}

void StaticSolver::assemble(std::span<const double> du, bool with_tangent) {
    if (mesh_.dim() == 2) {
        assemble_d<2>(du, with_tangent);
    } else {
        assemble_d<3>(du, with_tangent);
    }
}

bool StaticSolver::residual_pass(double t, std::span<const double> du, std::string& error) {
    {
        PhaseTimer timer(timers_.element);
        compute_strains(du);
        if (!update_materials(false, error)) {
            return false;
        }
    }
    {
        PhaseTimer timer(timers_.assembly);
        assemble(du, false);
        for (const Spring& sp : springs_) {
            for (std::size_t k = 0; k < sp.dofs.size(); ++k) {
                const auto d = static_cast<std::size_t>(sp.dofs[k]);
                f_int_[d] += sp.stiffness * (u_[d] + du[d] - sp.reference[k]);
            }
        }
    }
    if (!contacts_.empty()) {
        contact_du_.assign(du.begin(), du.end());
        for (auto& c : contacts_) {
            if (!c->evaluate(contact_du_, f_int_, error)) {
                return false;
            }
        }
    }
    external_force(t, f_ext_);
    PhaseTimer timer(timers_.assembly);
    std::fill(residual_.begin(), residual_.end(), 0.0);
    for (std::size_t d = 0; d < u_.size(); ++d) {
        const int eq = dofs_.equation[d];
        if (eq >= 0) {
            residual_[static_cast<std::size_t>(eq)] += f_ext_[d] - f_int_[d];
        }
    }
    // The force level of the run: this state's, or the mean over the converged increments
    // (time-averaged, as Abaqus does), so that a body unloaded towards zero stress is not
    // held to a residual relative to its vanishing forces.
    const double averaged = committed_references_ > 0
                                ? reference_sum_ / static_cast<double>(committed_references_)
                                : 0.0;
    reference_force_ =
        std::max({norm2(f_ext_), norm2(f_int_), averaged, settings_.reference_force_floor});
    return true;
}

// Needs the residual pass at the same increment just before (the perturbation lanes start from
// its strain increments and compare with its substep counts).
void StaticSolver::tangent_pass(std::span<const double> du) {
    {
        PhaseTimer timer(timers_.element);
        std::string unused;
        update_materials(true, unused);
    }
    {
        PhaseTimer timer(timers_.assembly);
        assemble(du, true);
        for (const Spring& sp : springs_) {
            for (int d : sp.dofs) {
                const int eq = dofs_.equation[static_cast<std::size_t>(d)];
                if (eq >= 0) {
                    system_->add_diagonal(eq, sp.stiffness);
                }
            }
        }
    }
    if (contacts_.empty()) {
        return;
    }
    for (const auto& c : contacts_) {
        contact_K_.clear();
        c->add_tangent(contact_K_); // timed by the pair (kernels when its lanes were deferred)
        PhaseTimer contact_timer(contact_matrix_s_);
        for (const ContactTriplet& k : contact_K_) {
            const int r = dofs_.equation[static_cast<std::size_t>(k.row)];
            const int q = dofs_.equation[static_cast<std::size_t>(k.col)];
            if (r >= 0 && q >= 0) {
                system_->add_value(r, q, k.value);
            }
        }
    }
}

bool StaticSolver::evaluate(double t, std::span<const double> increment, bool with_tangent,
                            std::string& error) {
    if (!stage_) {
        error = "evaluate() before begin_stage()";
        return false;
    }
    if (increment.size() != u_.size()) {
        error = fmt::format("increment of length {} for {} DOFs", increment.size(), u_.size());
        return false;
    }
    if (!residual_pass(t, increment, error)) {
        return false;
    }
    if (with_tangent) {
        tangent_pass(increment);
    }
    return true;
}

bool StaticSolver::solve_increment(double t_begin, double t_end, IncrementInfo& info,
                                   std::string& error, const IncrementCallback& on_iteration) {
    if (!contacts_.empty()) {
        begin_contacts(false);
    }
    std::fill(du_.begin(), du_.end(), 0.0);
    if (settings_.extrapolate && dt_last_ > 0.0) {
        const double scale = (t_end - t_begin) / dt_last_;
        for (std::size_t d = 0; d < du_.size(); ++d) {
            if (dofs_.equation[d] >= 0) {
                du_[d] = scale * du_last_[d];
            }
        }
    }
    for (std::size_t k = 0; k < dofs_.prescribed.size(); ++k) {
        const auto d = static_cast<std::size_t>(dofs_.prescribed[k]);
        du_[d] = u_stage_start_[d] + dofs_.prescribed_change[k] * t_end - u_[d];
    }
    const double tol_r = settings_.residual_tolerance;
    const double tol_u = settings_.displacement_tolerance;
    double last_correction = std::numeric_limits<double>::infinity();
    if (!residual_pass(t_end, du_, error)) {
        return false;
    }
    double rel = norm2(residual_) / reference_force_;
    for (int it = 0;; ++it) {
        info.residuals.push_back(rel);
        if (on_iteration) {
            on_iteration(info);
        }
        if (!std::isfinite(rel)) {
            error = "the residual is not finite";
            return false;
        }
        // Converged, or at the noise floor of the inner solves (small and no longer falling).
        const auto& r = info.residuals;
        const bool converged =
            rel <= 1.0e-2 * tol_r || (it > 0 && rel <= tol_r && last_correction <= tol_u);
        const bool stagnated = !converged && settings_.stagnation_tolerance > 0.0 &&
                               r.size() >= 4 && rel <= settings_.stagnation_tolerance &&
                               rel > 0.5 * r[r.size() - 4];
        if (converged || stagnated) {
            if (!targets_settled(info, error)) {
                if (!error.empty()) {
                    return false;
                }
                // New targets: the residual of the same displacements with them.
                if (!residual_pass(t_end, du_, error)) {
                    return false;
                }
                rel = norm2(residual_) / reference_force_;
                last_correction = std::numeric_limits<double>::infinity();
                continue;
            }
            if (stagnated) {
                info.stagnated = true;
                ++counters_.stagnation_accepts;
            }
            return true;
        }
        if (it == settings_.max_iterations) {
            error = fmt::format("Newton did not converge in {} iterations (relative residual "
                                "{:.3e}, last relative correction {:.3e}; residuals {})",
                                settings_.max_iterations, rel, last_correction,
                                residual_trace(info.residuals));
            return false;
        }
        tangent_pass(du_);
        {
            PhaseTimer timer(timers_.solve);
            if (!linear_.factorise(system_->matrix(), system_->pattern_id(), error) ||
                !linear_.solve(residual_.data(), correction_.data(), error)) {
                return false;
            }
        }
        ++counters_.newton_iterations;
        // Backtracking line search on the residual norm: halve the step while the residual
        // grows (a kink of the response sends full Newton steps into 2-cycles). A failed
        // evaluation (a material or interface point) is also retried with half the step.
        du_start_.assign(du_.begin(), du_.end());
        double alpha = 1.0;
        double rel_new = 0.0;
        for (int ls = 0;; ++ls) {
            for (std::size_t d = 0; d < du_.size(); ++d) {
                const int eq = dofs_.equation[d];
                du_[d] = eq >= 0 ? du_start_[d] + alpha * correction_[static_cast<std::size_t>(eq)]
                                 : du_start_[d];
            }
            const bool evaluated = residual_pass(t_end, du_, error);
            rel_new = evaluated ? norm2(residual_) / reference_force_
                                : std::numeric_limits<double>::infinity();
            const bool worse = !(rel_new <= rel) && rel_new > tol_r;
            // A failed evaluation may halve further: near a stress-free state the soil's
            // tangent is almost singular and the full step lands far outside what the
            // interface (or a material point) can follow.
            const int limit =
                evaluated ? settings_.max_line_search : std::max(settings_.max_line_search, 12);
            if (!worse || ls >= limit) {
                if (!evaluated) {
                    return false;
                }
                break;
            }
            alpha *= 0.5;
            ++info.line_search_steps;
            ++counters_.line_search_steps;
        }
        last_correction = alpha * norm2(correction_) / std::max(norm2(du_), 1.0e-300);
        info.corrections.push_back(last_correction);
        rel = rel_new;
    }
}

bool StaticSolver::targets_settled(IncrementInfo& info, std::string& error) {
    if (contacts_.empty() || settings_.max_gathers <= 0) {
        return true;
    }
    const ElementStresses trial = [this](int e, std::vector<Voigt6>& out) {
        element_stresses(e, out, true);
    };
    double change = 0.0;
    for (auto& c : contacts_) {
        change = std::max(change, c->regather(trial));
    }
    info.gather_change = change;
    if (change <= settings_.gather_tolerance) {
        counters_.worst_gather_change = std::max(counters_.worst_gather_change, change);
        return true;
    }
    if (info.gathers >= settings_.max_gathers) {
        error = fmt::format("the in-plane stresses gathered from the continuum (Eqs. 14-16) did "
                            "not settle in {} gathers (last change {:.2e} of their size)",
                            settings_.max_gathers, change);
        return false;
    }
    ++info.gathers;
    ++counters_.gathers;
    return false;
}

void StaticSolver::measure_initial_imbalance() {
    if (!contacts_.empty()) {
        begin_contacts(false);
    }
    std::fill(du_.begin(), du_.end(), 0.0);
    for (std::size_t k = 0; k < dofs_.prescribed.size(); ++k) {
        const auto d = static_cast<std::size_t>(dofs_.prescribed[k]);
        du_[d] = u_stage_start_[d] - u_[d];
    }
    std::string error;
    if (!residual_pass(0.0, du_, error)) {
        return; // the first increment reports the failure
    }
    imbalance_.evaluated = true;
    imbalance_.relative = norm2(residual_) / reference_force_;
    // The largest entry per equation (a tied set's forces sum into its master's equation),
    // named by the first node that carries it.
    double worst = -1.0;
    for (std::size_t d = 0; d < du_.size(); ++d) {
        const int eq = dofs_.equation[d];
        const double r = eq >= 0 ? residual_[static_cast<std::size_t>(eq)] : 0.0;
        if (std::abs(r) > worst) {
            worst = std::abs(r);
            imbalance_.node = static_cast<int>(d) / mesh_.dim();
            imbalance_.direction = static_cast<int>(d) % mesh_.dim();
            imbalance_.force = r;
        }
    }
}

StageResult StaticSolver::run_stage(const Stage& stage, const IncrementCallback& on_increment,
                                    const IncrementCallback& on_iteration) {
    begin_stage(stage);
    if (stage_count_ == 1) {
        measure_initial_imbalance();
    }
    StageResult result;
    const int steps = std::max(1, stage.steps);
    const int max_cuts = std::max(0, settings_.max_cuts);
    for (int k = 1; k <= steps; ++k) {
        // Automatic increment control inside the nominal step [t_a, t_step]: the increment is
        // halved on failure (up to max_cuts times) and doubled again after growth_after
        // converged increments in a row, never past the step's end, so a hard stretch costs
        // small increments only while it lasts.
        double t_a = double(k - 1) / steps;
        const double t_step = double(k) / steps;
        int depth = 0;
        int streak = 0;
        while (true) {
            const double h = 1.0 / (double(steps) * std::ldexp(1.0, depth));
            const bool last = t_a + h >= t_step - 1.0e-12 * h;
            const double t_b = last ? t_step : t_a + h;
            IncrementInfo info;
            info.stage = stage_count_;
            info.step = k;
            info.t_begin = t_a;
            info.t_end = t_b;
            info.cut_depth = depth;
            std::string error;
            if (solve_increment(t_a, t_b, info, error, on_iteration)) {
                for (auto& s : sets_) {
                    s->material->commit();
                }
                for (auto& c : contacts_) {
                    c->commit();
                }
                for (std::size_t d = 0; d < u_.size(); ++d) {
                    u_[d] += du_[d];
                }
                f_int_committed_ = f_int_;
                reference_sum_ += std::max(norm2(f_ext_), norm2(f_int_));
                ++committed_references_;
                du_last_ = du_;
                dt_last_ = t_b - t_a;
                f_ext_committed_ = f_ext_;
                ++counters_.increments;
                ++result.increments;
                counters_.worst_accepted_residual =
                    std::max(counters_.worst_accepted_residual, info.residuals.back());
                t_a = t_b;
                if (on_increment) {
                    on_increment(info);
                }
                if (last) {
                    break;
                }
                // Grow back only to a size that divides the rest of the step evenly.
                if (depth > 0 && ++streak >= settings_.growth_after) {
                    const double rest = (t_step - t_a) * double(steps) * std::ldexp(1.0, depth);
                    if (std::fmod(std::round(rest), 2.0) == 0.0) {
                        --depth;
                        streak = 0;
                        ++counters_.increment_growths;
                    }
                }
                continue;
            }
            if (depth >= max_cuts) {
                result.ok = false;
                result.reason = fmt::format(
                    "stage {} ('{}'), step {} of {}, pseudo-time {:.6g} to {:.6g}: {} (after "
                    "halving the step {} times)",
                    stage_count_, stage.name, k, steps, t_a, t_b, error, depth);
                return result;
            }
            ++counters_.cuts;
            dt_last_ = 0.0; // the retry starts from zero: the extrapolation may have misled
            ++depth;
            streak = 0;
        }
    }
    return result;
}

} // namespace ifsim::fem
