#include "io/interface_test/interface_history.hpp"

namespace ifsim::io {

std::vector<std::string> interface_history_columns() {
    return {"step",
            "stage",
            "u_t1",
            "u_t2",
            "u_n",
            "t_n",
            "t_t1",
            "t_t2",
            "s_n",
            "s_p1",
            "s_p2",
            "eps_n",
            "eps_p1",
            "eps_p2",
            "gamma1",
            "gamma2",
            "band_thickness",
            "sample_s11",
            "sample_s22",
            "sample_s33",
            "e_interface",
            "e_sample",
            "sample_s12",
            "sample_s13",
            "slip1",
            "slip2",
            "newton_iterations"};
}

void write_interface_row(HistoryWriter& out, const InterfaceRow& r, double t_n) {
    out.integer(r.step);
    out.integer(r.stage);
    for (double v : {r.u_t1,       r.u_t2,       r.u_n,        t_n,           r.t_t1,
                     r.t_t2,       r.s_n,        r.s_p1,       r.s_p2,        r.eps_n,
                     r.eps_p1,     r.eps_p2,     r.gamma1,     r.gamma2,      r.band_thickness,
                     r.sample_s11, r.sample_s22, r.sample_s33, r.e_interface, r.e_sample,
                     r.sample_s12, r.sample_s13, r.slip1,      r.slip2}) {
        out.real(v);
    }
    out.integer(r.newton_iterations);
    out.end_row();
}

} // namespace ifsim::io
