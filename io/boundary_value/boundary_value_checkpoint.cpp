#include "io/boundary_value/boundary_value_checkpoint.hpp"

#include <fmt/format.h>

#include "io/output/checkpoint_file.hpp"

namespace ifsim::io {
namespace {

std::vector<std::int64_t> ints(std::initializer_list<std::int64_t> v) {
    return std::vector<std::int64_t>(v);
}

// The field collections: times as doubles, file names one per line.
void put_fields(CheckpointWriter& w, const FieldOutputState& f) {
    w.put("fields", ints({f.present ? 1 : 0, static_cast<std::int64_t>(f.next_time),
                          static_cast<std::int64_t>(f.outputs),
                          static_cast<std::int64_t>(f.collections.size())}));
    for (std::size_t k = 0; k < f.collections.size(); ++k) {
        std::vector<double> times;
        std::string files;
        for (const PvdCollection::Entry& e : f.collections[k]) {
            times.push_back(e.time);
            files += e.file + "\n";
        }
        w.put(fmt::format("fields{}.times", k), times);
        w.put(fmt::format("fields{}.files", k), files);
    }
}

FieldOutputState read_fields(const CheckpointReader& r, const std::filesystem::path& file) {
    FieldOutputState f;
    const auto head = r.integers("fields");
    if (head.size() != 4 || head[1] < 0 || head[2] < 0 || head[3] < 0) {
        throw CheckpointError(fmt::format("{}: malformed fields section", file.string()));
    }
    f.present = head[0] != 0;
    f.next_time = static_cast<std::size_t>(head[1]);
    f.outputs = static_cast<std::size_t>(head[2]);
    for (std::int64_t k = 0; k < head[3]; ++k) {
        const auto times = r.doubles(fmt::format("fields{}.times", k));
        const std::string files = r.text(fmt::format("fields{}.files", k));
        std::vector<PvdCollection::Entry> entries;
        std::size_t at = 0;
        for (double t : times) {
            const std::size_t end = files.find('\n', at);
            if (end == std::string::npos) {
                throw CheckpointError(fmt::format("{}: malformed fields section", file.string()));
            }
            entries.push_back({t, files.substr(at, end - at)});
            at = end + 1;
        }
        f.collections.push_back(std::move(entries));
    }
    return f;
}

} // namespace

void write_boundary_value_checkpoint(const std::filesystem::path& dir,
                                     const BoundaryValueCheckpoint& c) {
    CheckpointWriter w;
    const fem::SolverSnapshot& s = c.snapshot;
    RunCheckpointHeader header = c.run;
    header.kind = "boundary-value";
    put_run_header(w, header);
    w.put("position",
          ints({static_cast<std::int64_t>(c.stage_index), c.cursor.step, c.cursor.depth,
                c.cursor.streak, c.steps_before, s.stage_count, s.committed_references}));
    w.put("cursor_t", std::vector<double>{c.cursor.t_a});
    w.put("cursor_step_substeps", std::vector<double>{c.cursor.step_substeps});
    w.put("cursor_viscous_held", ints({c.cursor.viscous_held ? 1 : 0}));
    w.put("cursor_carry", ints({c.cursor.start_depth, c.cursor.calm_steps}));
    w.put("iterations", std::vector<std::int64_t>(c.iterations.begin(), c.iterations.end()));
    w.put("u", s.u);
    w.put("u_stage_start", s.u_stage_start);
    w.put("du_last", s.du_last);
    w.put("f_int", s.f_int_committed);
    w.put("f_ext", s.f_ext_committed);
    w.put("scalars", std::vector<double>{s.dt_last, s.reference_sum});
    w.put("materials", s.material_states);
    w.put("imbalance", std::vector<double>{s.imbalance.evaluated ? 1.0 : 0.0, s.imbalance.relative,
                                           double(s.imbalance.node), double(s.imbalance.direction),
                                           s.imbalance.force});
    w.put("springs", ints({static_cast<std::int64_t>(s.spring_references.size())}));
    for (std::size_t k = 0; k < s.spring_references.size(); ++k) {
        w.put(fmt::format("spring{}.reference", k), s.spring_references[k]);
    }
    w.put("pairs", ints({static_cast<std::int64_t>(s.contacts.size())}));
    for (std::size_t k = 0; k < s.contacts.size(); ++k) {
        const fem::ContactPairSnapshot& p = s.contacts[k];
        const std::string key = fmt::format("pair{}.", k);
        w.put(key + "started", ints({p.started ? 1 : 0}));
        w.put(key + "committed", p.committed);
        w.put(key + "gap_offset", p.gap_offset);
        w.put(key + "relax", p.relax);
        w.put(key + "calm", p.calm);
    }
    put_fields(w, c.fields);
    w.write(dir / checkpoint_file_name);
}

BoundaryValueCheckpoint read_boundary_value_checkpoint(const std::filesystem::path& dir) {
    const std::filesystem::path file = dir / checkpoint_file_name;
    const CheckpointReader r(file);
    BoundaryValueCheckpoint c;
    c.run = read_run_header(r, file, "boundary-value");
    const auto pos = r.integers("position");
    if (pos.size() != 7) {
        throw CheckpointError(fmt::format("{}: malformed position section", file.string()));
    }
    c.stage_index = static_cast<std::size_t>(pos[0]);
    c.cursor.step = static_cast<int>(pos[1]);
    c.cursor.depth = static_cast<int>(pos[2]);
    c.cursor.streak = static_cast<int>(pos[3]);
    c.steps_before = pos[4];
    fem::SolverSnapshot& s = c.snapshot;
    s.stage_count = static_cast<int>(pos[5]);
    s.committed_references = pos[6];
    c.cursor.t_a = r.real("cursor_t");
    // Checkpoints written before the FE step bound have no such section: a fresh budget.
    c.cursor.step_substeps = r.has("cursor_step_substeps") ? r.real("cursor_step_substeps") : 0.0;
    // Written since hold_slip_viscosity: without it the next increment tries without the viscosity.
    if (r.has("cursor_viscous_held")) {
        const auto held = r.integers("cursor_viscous_held");
        if (held.size() != 1 || held[0] < 0 || held[0] > 1) {
            throw CheckpointError(
                fmt::format("{}: malformed cursor_viscous_held section", file.string()));
        }
        c.cursor.viscous_held = held[0] == 1;
    }
    // Written since carry_cuts: without it the step started at full size.
    if (r.has("cursor_carry")) {
        const auto carry = r.integers("cursor_carry");
        if (carry.size() != 2 || carry[0] < 0 || carry[0] > 64 || carry[1] < 0) {
            throw CheckpointError(fmt::format("{}: malformed cursor_carry section", file.string()));
        }
        c.cursor.start_depth = static_cast<int>(carry[0]);
        c.cursor.calm_steps = static_cast<int>(carry[1]);
    }
    for (std::int64_t v : r.integers("iterations")) {
        c.iterations.push_back(static_cast<int>(v));
    }
    s.u = r.doubles("u");
    s.u_stage_start = r.doubles("u_stage_start");
    s.du_last = r.doubles("du_last");
    s.f_int_committed = r.doubles("f_int");
    s.f_ext_committed = r.doubles("f_ext");
    const auto scalars = r.doubles("scalars");
    const auto imb = r.doubles("imbalance");
    if (scalars.size() != 2 || imb.size() != 5) {
        throw CheckpointError(fmt::format("{}: malformed solver section", file.string()));
    }
    s.dt_last = scalars[0];
    s.reference_sum = scalars[1];
    s.material_states = r.doubles("materials");
    s.imbalance = {imb[0] != 0.0, imb[1], static_cast<int>(imb[2]), static_cast<int>(imb[3]),
                   imb[4]};
    const auto springs = r.integer("springs");
    for (std::int64_t k = 0; k < springs; ++k) {
        s.spring_references.push_back(r.doubles(fmt::format("spring{}.reference", k)));
    }
    const auto pairs = r.integer("pairs");
    for (std::int64_t k = 0; k < pairs; ++k) {
        const std::string key = fmt::format("pair{}.", k);
        fem::ContactPairSnapshot p;
        p.started = r.integer(key + "started") != 0;
        p.committed = r.doubles(key + "committed");
        p.gap_offset = r.doubles(key + "gap_offset");
        p.relax = r.doubles(key + "relax");
        p.calm = r.doubles(key + "calm");
        s.contacts.push_back(std::move(p));
    }
    c.fields = read_fields(r, file);
    return c;
}

} // namespace ifsim::io
