// A recorded Algorithm 1 call, run again alone (evaluate_contact_point, the replay of scene kind
// "interface-point"), gives what the call gave among its neighbours: bit for bit, on the SIMD
// path with other points in the same batches and on the scalar path.

#include <gtest/gtest.h>

#include "engine/failed_contact_point.hpp"
#include "tests/engine/interface_fixtures.hpp"

namespace ifsim {
namespace {

template <class M>
void expect_replays_bitwise(const typename M::Params& params,
                            const StateVec<double, M::n_state>& y0, bool adaptive, bool simd) {
    const std::size_t n = 11; // more than one batch of lanes, with a ragged end
    ContactPoints<M> cp(n, 3);
    const test::Frame f = test::tilted_frame(3);
    for (std::size_t i = 0; i < n; ++i) {
        cp.set_state(i, y0);
        cp.set_frame(i, f.n.data(), f.t1.data(), f.t2.data());
        const double s = static_cast<double>(i);
        cp.input(contact_col::t_N)[i] = -100.0 - 3.0 * s;
        cp.input(contact_col::k_N)[i] = 1.0e5;
        cp.input(contact_col::dg1)[i] = 1.0e-5 * (1.0 + 0.3 * s);
        cp.input(contact_col::dg2)[i] = -2.0e-6 * s;
        cp.input(contact_col::s_p1)[i] = -50.0 - s;
        cp.input(contact_col::s_p2)[i] = -52.0 + 0.5 * s;
    }
    ContactOptions opt;
    opt.simd = simd;
    opt.interface.adaptive = adaptive;
    // A point's committed state as a previous increment left it: interface strains and a
    // carried sub-increment size are part of what is replayed.
    ContactEngine<M> engine;
    ASSERT_TRUE(engine.update(cp, params, opt).ok());
    cp.commit();
    const ContactReport rep = engine.update(cp, params, opt);
    ASSERT_TRUE(rep.ok());
    for (std::size_t i : {std::size_t{0}, std::size_t{5}, n - 1}) {
        const FailedContactPoint call = record_failed_point(cp, i, opt, 0.0, 0.0, "test point");
        EXPECT_NE(call.state[M::n_state + contact_state::eps_n], 0.0);
        const ContactPointOutcome again = evaluate_contact_point<M>(params, call, simd);
        ASSERT_TRUE(again.report.ok());
        for (int c = 0; c < 3; ++c) {
            EXPECT_EQ(again.traction[static_cast<std::size_t>(c)],
                      cp.output(contact_col::traction + c)[i])
                << "point " << i << " component " << c;
        }
        for (int k = 0; k < ContactPoints<M>::n_state_cols; ++k) {
            EXPECT_EQ(again.state[static_cast<std::size_t>(k)], cp.trial(k)[i])
                << "point " << i << " state " << k;
        }
    }
}

TEST(FailedContactPoint, HypoplasticCallReplaysBitwiseFixedAndAdaptive) {
    for (bool simd : {true, false}) {
        expect_replays_bitwise<Hypoplasticity>(test::l4c(), test::hypo_state(), false, simd);
        expect_replays_bitwise<Hypoplasticity>(test::l4c(), test::hypo_state(), true, simd);
    }
}

TEST(FailedContactPoint, SanisandCallReplaysBitwise) {
    for (bool simd : {true, false}) {
        expect_replays_bitwise<Sanisand>(test::karlsruhe_sanisand(), test::sanisand_state(), true,
                                         simd);
    }
}

} // namespace
} // namespace ifsim
