// An elastic block pressed onto a longer fixed plate and pushed along it over several master
// faces, through the static solver with a Coulomb contact pair (2D quad4 and 3D hex8). Once
// sliding, the mean tangential traction is mu times the normal one and opposes the motion;
// the pairing follows the block across faces (pattern rebuilds) without losing a point, and
// Newton converges in a few iterations with the exact Coulomb Jacobian.
#include <gtest/gtest.h>

#include <cstdio>

#include "fem/static_solver.hpp"
#include "fem/structured_mesh.hpp"

namespace {

using namespace ifsim;
using namespace ifsim::fem;

struct SlideResult {
    bool ok = false;
    std::string reason;
    std::vector<ContactResultant> rows;
    std::vector<int> iterations;
    SolverCounters counters;
};

SlideResult slide(int dim) {
    const bool d3 = dim == 3;
    const int vert = dim - 1;
    Mesh mesh;
    if (d3) {
        append_body(mesh, box_mesh({3.0, 1.0, 0.5, 6, 2, 1, {0.0, 0.0, -0.5}}), "plate");
        append_body(mesh, box_mesh({0.8, 0.6, 0.5, 2, 2, 1, {0.2, 0.2, 0.0}}), "block");
    } else {
        append_body(mesh, rectangle_mesh({3.0, 0.5, 6, 1, {0.0, -0.5}}), "plate");
        append_body(mesh, rectangle_mesh({0.8, 0.5, 2, 1, {0.2, 0.0}}), "block");
    }
    LinearElasticParams elastic;
    elastic.E = 1.0e4;
    elastic.nu = 0.3;
    ElementSetMaterial plate;
    plate.element_set = "plate";
    plate.material = elastic;
    plate.initial_state = {0, 0, 0, 0, 0, 0, 0.5};
    std::vector<double> y{0, 0, 0, 0, 0, 0, 0.5};
    y[static_cast<std::size_t>(vert)] = -100.0; // the block starts under the 100 kPa it carries
    ElementSetMaterial block = plate;
    block.element_set = "block";
    block.initial_state = y;
    StaticSolver solver(mesh, {plate, block}, SolverSettings{});
    ContactPairSpec c;
    c.slave_faces = "block.bottom";
    c.master_faces = "plate.top";
    c.normal_penalty = 1.0e6;
    c.options.interface.formulation = InterfaceFormulation::coulomb;
    c.friction = CoulombParams{0.3, 1.0e5};
    solver.add_contact(c);

    Stage st;
    st.name = "slide";
    st.steps = 30;
    for (int d = 0; d < dim; ++d) {
        st.displacements.push_back({"plate.all", d, 0.0});
        if (d != vert) {
            st.displacements.push_back({"block.top", d, d == 0 ? 1.5 : 0.0});
        }
    }
    st.equal_displacements.push_back({"block.top", vert});
    st.pressures.push_back({"block.top", 100.0, 100.0});
    SlideResult out;
    const auto res = solver.run_stage(st, [&](const IncrementInfo& info) {
        out.rows.push_back(solver.contacts()[0]->resultant());
        out.iterations.push_back(static_cast<int>(info.corrections.size()));
    });
    out.ok = res.ok;
    out.reason = res.reason;
    out.counters = solver.counters();
    return out;
}

void expect_sliding_friction(int dim) {
    const SlideResult r = slide(dim);
    ASSERT_TRUE(r.ok) << r.reason;
    const int points = dim == 2 ? 4 : 16; // Gauss points of the block's bottom faces
    for (std::size_t k = 0; k < r.rows.size(); ++k) {
        const ContactResultant& row = r.rows[k];
        EXPECT_EQ(row.active, points) << "increment " << k;
        // The mortar weights are taken in the current configuration, the pressure on the
        // reference faces (small strain): the mean differs from 100 kPa by the block's strain.
        EXPECT_NEAR(row.t_N, -100.0, 2.0e-3 * 100.0) << "increment " << k;
        if (k >= 2) { // sliding: 0.05 m per increment, far beyond the stick range mu t_N / k_T
            EXPECT_NEAR(row.shear[0] / row.t_N, 0.3, 1.0e-9) << "increment " << k;
        }
        // The first increment switches from stick to slip; then the slip state is known.
        EXPECT_LE(r.iterations[k], k == 0 ? 6 : 3) << "increment " << k;
    }
    // 1.5 m over master faces of 0.5 m: the block's points cross three face borders.
    EXPECT_GE(r.counters.contact_pattern_rebuilds, 3);
    std::printf("%dD: %ld pattern rebuilds, %ld Newton iterations in %zu increments\n", dim,
                r.counters.contact_pattern_rebuilds, r.counters.newton_iterations, r.rows.size());
}

TEST(ContactSliding, CoulombBlockSlidesOverSeveralMasterFaces2D) {
    expect_sliding_friction(2);
}

TEST(ContactSliding, CoulombBlockSlidesOverSeveralMasterFaces3D) {
    expect_sliding_friction(3);
}

} // namespace
