#pragma once
// The columns of an interface test's history.csv: first exactly the contract's
//   step,stage,u_t1,u_t2,u_n,t_n,t_t1,t_t2,s_n,s_p1,s_p2,eps_n,eps_p1,eps_p2,gamma1,gamma2,
//   band_thickness,sample_s11,sample_s22,sample_s33,e_interface,e_sample
// then the extras sample_s12, sample_s13 (the sample's shear stresses), slip1, slip2 (the
// accumulated interface slip g_T, m) and newton_iterations (of the step's outer Newton).

#include <string>
#include <vector>

#include "engine/interface_test_driver.hpp"
#include "io/output/history_writer.hpp"

namespace ifsim::io {

std::vector<std::string> interface_history_columns();

// The normal contact stress of a row: t_N = t_N0 - K u_n (the prescribed t_N0 under CNL),
// which the step's Newton iteration imposed on the sample.
inline double contact_normal_stress(double t_N0, double stiffness, const InterfaceRow& row) {
    return t_N0 - stiffness * row.u_n;
}

// One row in the column order above; t_n is the prescribed normal contact stress.
void write_interface_row(HistoryWriter& out, const InterfaceRow& row, double t_n);

} // namespace ifsim::io
