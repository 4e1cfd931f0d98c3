// The ifsim command line; everything it does lives in the ifsim_io library (io/cli/cli.cpp).
#include <exception>

#include <fmt/format.h>

#include "io/cli/cli.hpp"

int main(int argc, char** argv) {
    try {
        return ifsim::io::run_cli(argc, argv);
    } catch (const std::exception& e) {
        fmt::print(stderr, "ifsim: internal error: {}\n", e.what());
        return 1;
    }
}
