#include "fem/contact_pair.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include "engine/coulomb_contact.hpp"
#include "fem/contact_pair_base.hpp"
#include "fem/interface_pair.hpp"
#include "fem/phase_timer.hpp"

namespace ifsim::fem {
namespace {

using detail::InterfacePair;
using detail::PairBase;
using detail::slave_point_count;

// Coulomb penalty friction at every point (engine/coulomb_contact.hpp).
class CoulombPair final : public PairBase {
public:
    CoulombPair(const Mesh& mesh, ContactPairSpec spec)
        : PairBase(mesh, std::move(spec)), points_(slave_point_count(mesh, spec_), dim_) {
        if (spec_.friction.friction_coefficient < 0.0 ||
            !(spec_.friction.tangential_stiffness > 0.0)) {
            throw std::invalid_argument(fmt::format(
                "contact pair '{}': expected a friction coefficient >= 0 and a positive "
                "tangential stiffness",
                spec_.name));
        }
    }

    bool evaluate(const std::vector<double>& du, std::vector<double>& f_int,
                  std::string&) override {
        {
            PhaseTimer timer(timers_.gather);
            gather_gaps(du, points_, coulomb_col::t_N, coulomb_col::k_N, coulomb_col::dg1,
                        coulomb_col::dg2);
        }
        CoulombContactReport rep;
        {
            PhaseTimer timer(timers_.kernels);
            rep = coulomb_contact_update(points_, spec_.friction, {});
        }
        PhaseTimer timer(timers_.scatter);
        ++counters_.evaluations;
        counters_.point_updates += static_cast<double>(rep.points);
        counters_.lanes += rep.evaluations;
        counters_.constitutive_evaluations += rep.evaluations;
        for (std::size_t i = 0; i < kin_->n_points(); ++i) {
            take_traction(points_, i);
        }
        kin_->assemble(traction_, f_int, nullptr);
        return true;
    }

    void commit() override { points_.commit(); }

protected:
    bool needs_stress() const override { return false; }
    void start(const std::vector<Voigt6>&) override {
        for (std::size_t i = 0; i < points_.size(); ++i) {
            points_.set_traction(i, 0.0, 0.0);
        }
    }
    void add_point_state(std::size_t i, ContactPointRecord& r) const override {
        r.slipping = points_.output(coulomb_col::slipping)[i];
    }
    void save_state(ContactPairSnapshot& s) const override {
        save_columns(points_, coulomb_col::n_state, s);
    }
    void load_state(const ContactPairSnapshot& s) override {
        load_columns(points_, coulomb_col::n_state, s);
    }

private:
    CoulombContactPoints points_;
};

} // namespace

std::unique_ptr<ContactPair> make_contact_pair(const Mesh& mesh, ContactPairSpec spec) {
    mesh.face_set(spec.slave_faces); // throws naming the set
    mesh.face_set(spec.master_faces);
    if (spec.coulomb()) {
        if (spec.slip_viscosity != 0.0) {
            throw std::invalid_argument(fmt::format(
                "contact pair '{}': Coulomb friction takes no slip viscosity (it regularises a "
                "continuum band past its peak)",
                spec.name));
        }
        return std::make_unique<CoulombPair>(mesh, std::move(spec));
    }
    return std::visit(
        [&](const auto& p) -> std::unique_ptr<ContactPair> {
            using P = std::decay_t<decltype(p)>;
            using M = typename model_of<P>::type;
            if constexpr (!ModelEntry<M>::interface_model) {
                std::string usable;
                for (std::string_view n : model_names(true)) {
                    usable += fmt::format("{}{}", usable.empty() ? "" : " or ", n);
                }
                throw std::invalid_argument(fmt::format(
                    "contact pair '{}': {} cannot be an interface model (no void ratio and no "
                    "state for Algorithm 1); expected {}",
                    spec.name, M::name, usable));
            } else {
                return std::make_unique<InterfacePair<M>>(mesh, spec, p);
            }
        },
        spec.interface_material);
}

} // namespace ifsim::fem
