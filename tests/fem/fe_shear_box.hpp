#pragma once
// The §5 simple interface shear box as a finite-element model (2D quad4 or 3D hex8): one soil
// element (L4C, e0 = 0.81, K0 = 0.5 under 100 kPa, intergranular strain mobilised in the
// shearing direction) on a longer rigid plate (all plate nodes prescribed), a hypoplastic
// interface (novel formulation unless told otherwise) between the soil's bottom and the
// plate's top. Stage 1 applies the pressure (the prestressed contact starts in equilibrium),
// stage 2 moves the plate along +x while the soil's top is held horizontally and tied
// vertically, and the soil's bottom nodes are tied horizontally (simple shear).

#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "fem/static_solver.hpp"
#include "fem/structured_mesh.hpp"
#include "tests/engine/interface_fixtures.hpp"

namespace ifsim::fem::testing {

struct ShearBoxOptions {
    int dim = 2;
    ContactJacobian jacobian = ContactJacobian::perturbation;
    InterfaceFormulation formulation = InterfaceFormulation::novel;
    double displacement = 1.0e-3; // plate travel in stage 2, m
    int steps = 20;
    double max_subincrement = 5.0e-5;
    int threads = 0; // 0: TBB's default
    double normal_penalty = 1.0e8;
    int soil_elements = 1; // per horizontal axis (the §5 box: 1)
    int plate_elements = 7;
    int max_iterations = 20; // global Newton
    int max_cuts = SolverSettings{}.max_cuts;
    int max_gathers = SolverSettings{}.max_gathers; // 0: explicit gather (the paper's)
    bool check_tangent = false;                     // SolverSettings::check_tangent
    bool reuse_factorisation = false;               // SolverSettings::reuse_factorisation
    bool hold_slip_viscosity = false;               // SolverSettings::hold_slip_viscosity
    int carry_cuts = 0;                             // SolverSettings::carry_cuts
    bool elastic_soil = false; // linear-elastic soil (E 1e5 kPa): only the interface can fail
    std::function<void(ContactPairSpec&)> adjust; // last changes to the contact pair
};

struct ShearBoxRun {
    bool ok = true;
    std::string reason;
    std::vector<double> u_t1, t_t1, t_n;        // per increment of stage 2
    std::vector<int> iterations;                // Newton iterations per increment of stage 2
    std::vector<std::vector<double>> residuals; // relative residuals of each increment
    std::vector<double> u;                      // final displacements
    std::vector<double> interface_state;        // mean void ratio and eps_N at the end
    SolverCounters counters;
    SolverTimers timers;
};

// The box's solver (mesh, materials, contact pair) and its two stages.
struct ShearBox {
    std::unique_ptr<StaticSolver> solver;
    Stage consolidation, shear;
    int plate_node = 0;
};

inline ShearBox build_shear_box(const ShearBoxOptions& o) {
    const bool d3 = o.dim == 3;
    const int vert = d3 ? 2 : 1;
    Mesh mesh;
    if (d3) {
        append_body(
            mesh,
            box_mesh(
                {0.14, 0.14, 0.01, o.plate_elements, o.plate_elements, 1, {-0.02, -0.02, -0.01}}),
            "plate");
        append_body(
            mesh, box_mesh({0.1, 0.1, 0.02, o.soil_elements, o.soil_elements, 1, {0.0, 0.0, 0.0}}),
            "soil");
    } else {
        append_body(mesh, rectangle_mesh({0.14, 0.01, o.plate_elements, 1, {-0.02, -0.01}}),
                    "plate");
        append_body(mesh, rectangle_mesh({0.1, 0.02, o.soil_elements, 1, {0.0, 0.0}}), "soil");
    }
    const double R = parameter_sets::hypoplasticity_l4c().R;
    const double e0 = 0.81;
    ElementSetMaterial plate;
    plate.element_set = "plate";
    LinearElasticParams steel;
    steel.E = 2.0e8;
    steel.nu = 0.3;
    plate.material = steel;
    plate.initial_state = {0, 0, 0, 0, 0, 0, 0.5};
    ElementSetMaterial soil;
    soil.element_set = "soil";
    soil.material = test::l4c(1.0);
    // Global axes: vertical stress -100, horizontal -50; the plate moving +x under the soil
    // shears it with d u_x / d vertical < 0, so h_(x, vertical) = -R / sqrt 2 is "mobilised in
    // the shearing direction".
    std::vector<double> y(Hypoplasticity::n_state, 0.0);
    y[0] = y[1] = y[2] = -50.0;
    y[static_cast<std::size_t>(vert)] = -100.0;
    y[6] = e0;
    y[static_cast<std::size_t>(Hypoplasticity::h_index + (d3 ? 4 : 3))] = -R / std::sqrt(2.0);
    soil.initial_state = y;
    if (o.elastic_soil) {
        LinearElasticParams sand;
        sand.E = 1.0e5;
        sand.nu = 0.25;
        soil.material = sand;
        soil.initial_state.resize(LinearElastic::n_state);
    }

    SolverSettings settings;
    settings.max_iterations = o.max_iterations;
    settings.max_cuts = o.max_cuts;
    settings.max_gathers = o.max_gathers;
    settings.check_tangent = o.check_tangent;
    settings.reuse_factorisation = o.reuse_factorisation;
    settings.hold_slip_viscosity = o.hold_slip_viscosity;
    settings.carry_cuts = o.carry_cuts;
    ShearBox box;
    box.solver = std::make_unique<StaticSolver>(mesh, std::vector<ElementSetMaterial>{plate, soil},
                                                settings);
    StaticSolver& solver = *box.solver;
    ContactPairSpec c;
    c.slave_faces = "soil.bottom";
    c.master_faces = "plate.top";
    c.normal_penalty = o.normal_penalty;
    c.interface_material = test::l4c(0.9);
    c.options.interface.formulation = o.formulation;
    c.options.interface.max_subincrement = o.max_subincrement;
    c.options.jacobian = o.jacobian;
    c.initial_state = [e0, R](const Voigt6& s) { // by value: the pair outlives this function
        std::vector<double> z(Hypoplasticity::n_state, 0.0);
        for (std::size_t k = 0; k < 5; ++k) {
            z[k] = s[k];
        }
        z[6] = e0;
        z[static_cast<std::size_t>(Hypoplasticity::h_index + 3)] = R / std::sqrt(2.0);
        return z;
    };
    if (o.adjust) {
        o.adjust(c);
    }
    solver.add_contact(c);

    Stage st;
    st.name = "consolidation";
    st.steps = 1;
    for (int d = 0; d < o.dim; ++d) {
        st.displacements.push_back({"plate.all", d, 0.0});
        if (d != vert) {
            st.displacements.push_back({"soil.top", d, 0.0});
            st.equal_displacements.push_back({"soil.bottom", d});
        }
    }
    // Laminar rings: the bottom also moves as a whole vertically, so the box carries the
    // couple of the shear tractions and the sample stays homogeneous (the point-level
    // idealisation).
    st.equal_displacements.push_back({"soil.top", vert});
    st.equal_displacements.push_back({"soil.bottom", vert});
    st.pressures.push_back({"soil.top", 100.0, 100.0});
    box.consolidation = st;
    st.name = "shear";
    st.steps = o.steps;
    st.displacements[0].change = o.displacement; // plate.all along x
    box.shear = st;
    box.plate_node = mesh.node_set("plate.all")[0];
    return box;
}

inline ShearBoxRun run_shear_box(const ShearBoxOptions& o) {
    std::unique_ptr<tbb::global_control> limit;
    if (o.threads > 0) {
        limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                      static_cast<std::size_t>(o.threads));
    }
    ShearBox box = build_shear_box(o);
    StaticSolver& solver = *box.solver;
    ShearBoxRun run;
    auto res = solver.run_stage(box.consolidation);
    if (!res.ok) {
        run.ok = false;
        run.reason = res.reason;
        run.u = solver.displacement();
        run.counters = solver.counters();
        return run;
    }
    const int plate_node = box.plate_node;
    res = solver.run_stage(box.shear, [&](const IncrementInfo& info) {
        const ContactResultant r = solver.contacts()[0]->resultant();
        run.u_t1.push_back(solver.displacement()[static_cast<std::size_t>(plate_node * o.dim)]);
        run.t_t1.push_back(r.shear[0]);
        run.t_n.push_back(r.t_N);
        run.iterations.push_back(static_cast<int>(info.corrections.size()));
        run.residuals.push_back(info.residuals);
    });
    run.ok = res.ok;
    run.reason = res.reason;
    run.u = solver.displacement();
    const ContactResultant r = solver.contacts()[0]->resultant();
    run.interface_state = {r.void_ratio, r.eps_N};
    run.counters = solver.counters();
    run.timers = solver.timers();
    return run;
}

} // namespace ifsim::fem::testing
