#pragma once
// Exit codes of the ifsim command line (documented in docs/scenes.md).

namespace ifsim::io::exit_code {

inline constexpr int ok = 0;
inline constexpr int io_error = 1;   // output directory or files could not be written
inline constexpr int bad_input = 2;  // bad command line or scene (file, key, expectation)
inline constexpr int run_failed = 3; // the simulation itself failed (summary status "failed")

} // namespace ifsim::io::exit_code
