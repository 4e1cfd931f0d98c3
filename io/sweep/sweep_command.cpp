#include "io/sweep/sweep_command.hpp"

#include <optional>

#include <fmt/format.h>

#include "io/cli/exit_codes.hpp"
#include "io/sweep/mpi_sweep.hpp"
#include "io/sweep/sweep_coordinator.hpp"
#include "io/sweep/sweep_plan.hpp"

namespace ifsim::io {

namespace {

// Reads the sweep, or says why not (exit 2).
std::optional<SweepPlan> planned(const SweepOptions& opt) {
    try {
        return plan_sweep(opt);
    } catch (const std::exception& e) {
        fmt::print(stderr, "ifsim sweep: error: {}\n", e.what());
        return std::nullopt;
    }
}

} // namespace

int sweep_command(const SweepOptions& opt) {
    if (launched_by_mpi() && !opt.list) {
        // Rank 0 reads the sweep and hands out its runs; the other ranks only run them.
        return run_on_mpi_ranks(opt, [&](const SweepLayout& layout, RemoteWorkers& workers) {
            std::optional<SweepPlan> plan = planned(opt);
            if (!plan) {
                return exit_code::bad_input;
            }
            std::size_t reused = 0;
            const std::vector<std::size_t> pending = pending_members(*plan, opt.scalar, reused);
            return coordinate_sweep(opt, *plan, pending, reused, layout, &workers);
        });
    }
    std::optional<SweepPlan> read = planned(opt);
    if (!read) {
        return exit_code::bad_input;
    }
    SweepPlan& plan = *read;
    if (opt.list) {
        for (const SweepMember& m : plan.members) {
            fmt::print("{} {} {}", m.index, m.id, plan.file.scenes[m.scene]);
            for (const std::string& s : m.sets) {
                fmt::print(" --set {}", s);
            }
            fmt::print("\n");
        }
        return exit_code::ok;
    }
    std::size_t reused = 0;
    const std::vector<std::size_t> pending = pending_members(plan, opt.scalar, reused);
    return coordinate_sweep(opt, plan, pending, reused, local_layout(pending.size(), opt), nullptr);
}

} // namespace ifsim::io
