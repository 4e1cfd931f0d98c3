#pragma once
// The scalar results of a run, read from its history.csv when the run ends (so a resumed run
// counts the rows written before it stopped): what summary.json gives as "results" and a sweep
// gathers into its table. Which results a run has follows from its columns:
//   t_t1 [, t_t2]     peak_shear_stress (max |t_t|), final_shear_stress (t_t1 of the last row)
//   t_n               final_normal_stress
//   u_t1, u_n         final_shear_displacement, final_normal_displacement
//   s11 ... s23       final_mean_stress (trace / 3, compression negative), peak_q, final_q
//                     (q = sqrt(3/2 s_dev : s_dev))
//   e, e_interface    final_void_ratio, final_interface_void_ratio
// plus "rows". Empty fields and non-finite values are skipped.

#include <filesystem>

#include <nlohmann/json.hpp>

namespace ifsim::io {

// The results of DIR/history.csv (an empty object when there is no such file or no row).
nlohmann::ordered_json history_results(const std::filesystem::path& history_csv);

} // namespace ifsim::io
