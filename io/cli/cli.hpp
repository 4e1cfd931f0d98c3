#pragma once
// The ifsim command line: subcommands `run` and `kernel-bench` (CLI11). Returns the process
// exit code (exit_codes.hpp); the tests call it in-process like main() does.

namespace ifsim::io {

int run_cli(int argc, const char* const* argv);

} // namespace ifsim::io
