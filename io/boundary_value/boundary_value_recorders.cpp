#include "io/boundary_value/boundary_value_recorders.hpp"

#include <cmath>
#include <limits>
#include <set>

#include <fmt/format.h>

#include "io/boundary_value/boundary_value_scene.hpp"

namespace ifsim::io {
namespace {

// The columns of a point recorder after its name, with their units.
const std::vector<std::pair<std::string, ColumnDescription>>& point_columns() {
    static const std::vector<std::pair<std::string, ColumnDescription>> c = {
        {"t_n", {"kPa", "normal traction at the point, negative in compression"}},
        {"t_t1", {"kPa", "shear traction at the point along the pair's t1 (shear_direction)"}},
        {"t_t2", {"kPa", "shear traction at the point along the pair's t2 = t1 x n"}},
        {"s_p1", {"kPa", "interface in-plane stress sigma_p1 at the point"}},
        {"s_p2", {"kPa", "interface in-plane stress sigma_p2 at the point"}},
        {"eps_n", {"-", "interface normal strain epsilon_N at the point"}},
        {"eps_p1", {"-", "interface in-plane strain epsilon_p1 at the point"}},
        {"eps_p2", {"-", "interface in-plane strain epsilon_p2 at the point"}},
        {"band_thickness", {"m", "shear band thickness d_s at the point (Eq. 26)"}},
        {"e_interface", {"-", "void ratio of the interface zone at the point"}},
    };
    return c;
}

std::optional<double> finite(double v) {
    return std::isfinite(v) ? std::optional<double>(v) : std::nullopt;
}

} // namespace

Recorders read_recorders(const TableReader& root, const fem::Mesh& mesh,
                         const std::vector<BoundaryValueInterface>& contacts) {
    Recorders out;
    if (!root.has("recorder")) {
        return out;
    }
    std::set<std::string> names;
    const int D = mesh.dim();
    for (const TableReader& t : root.array_of_tables("recorder")) {
        const std::string name = t.string("name");
        const bool valid = !name.empty() && name.find_first_not_of(
                                                "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVW"
                                                "XYZ0123456789_-") == std::string::npos;
        if (!valid || !names.insert(name).second) {
            t.fail("name", fmt::format("expected a new name of letters, digits, _ and - (it "
                                       "names history.csv columns), got \"{}\"",
                                       name));
        }
        for (const char* column :
             {"increment", "stage", "time", "newton_iterations", "u_t1", "u_t2", "u_n", "t_n",
              "t_t1", "t_t2", "cuts", "residual", "closed_points", "s_p1", "s_p2", "eps_n",
              "band_thickness", "e_interface"}) {
            if (name == column) {
                t.fail("name", fmt::format("expected a name that is not a history.csv column "
                                           "of its own, got \"{}\"",
                                           name));
            }
        }
        for (const BoundaryValueInterface& c : contacts) {
            if (name == c.pair.name) {
                t.fail("name", fmt::format("expected a name that is not a contact pair's (its "
                                           "columns are <pair>.t_n, ...), got \"{}\"",
                                           name));
            }
        }
        if (t.has("nodes")) {
            t.allow_only({"name", "nodes", "direction"});
            NodeRecorder r;
            r.name = name;
            r.nodes = read_node_set(t, "nodes", mesh);
            const std::vector<double> d =
                t.numbers("direction", static_cast<std::size_t>(D), Bounds::any(),
                          D == 2 ? "a direction x, y" : "a direction x, y, z");
            double len = 0.0;
            for (double c : d) {
                len += c * c;
            }
            len = std::sqrt(len);
            if (!(len > 0.0)) {
                t.fail("direction", "expected a direction of non-zero length");
            }
            for (int k = 0; k < D; ++k) {
                r.direction[static_cast<std::size_t>(k)] = d[static_cast<std::size_t>(k)] / len;
            }
            out.nodes.push_back(std::move(r));
            continue;
        }
        if (!t.has("contact")) {
            t.fail_here("expected either nodes = \"SET\" with direction = [...] (a node set's "
                        "displacement) or contact = \"PAIR\" with position = [...] (the state of "
                        "the pair's point nearest to the position)");
        }
        t.allow_only({"name", "contact", "position"});
        PointRecorder r;
        r.name = name;
        const std::string pair = t.string("contact");
        std::string list;
        bool found = false;
        for (std::size_t k = 0; k < contacts.size(); ++k) {
            list += fmt::format("{}\"{}\"", list.empty() ? "" : ", ", contacts[k].pair.name);
            if (contacts[k].pair.name == pair) {
                r.contact = k;
                found = true;
            }
        }
        if (!found) {
            t.fail("contact",
                   fmt::format("expected the name of a contact pair{}{}; got \"{}\"",
                               list.empty() ? " (the scene has none)" : ": ", list, pair));
        }
        const std::vector<double> p =
            t.numbers("position", static_cast<std::size_t>(D), Bounds::any(),
                      D == 2 ? "a position x, y in m" : "a position x, y, z in m");
        for (int k = 0; k < D; ++k) {
            r.position[static_cast<std::size_t>(k)] = p[static_cast<std::size_t>(k)];
        }
        out.points.push_back(std::move(r));
    }
    return out;
}

std::vector<std::string> recorder_columns(const Recorders& r) {
    std::vector<std::string> out;
    for (const auto& [name, d] : recorder_descriptions(r)) {
        out.push_back(name);
    }
    return out;
}

std::vector<std::pair<std::string, ColumnDescription>> recorder_descriptions(const Recorders& r) {
    std::vector<std::pair<std::string, ColumnDescription>> out;
    for (const NodeRecorder& n : r.nodes) {
        out.push_back(
            {n.name,
             {"m", fmt::format("mean displacement of node set {} along ({:.6g}, {:.6g}, {:.6g})",
                               n.nodes, n.direction[0], n.direction[1], n.direction[2])}});
    }
    for (const PointRecorder& p : r.points) {
        for (const auto& [suffix, d] : point_columns()) {
            out.push_back({p.name + "." + suffix,
                           {d.unit, fmt::format("{} (recorder {})", d.meaning, p.name)}});
        }
    }
    return out;
}

RecorderProbe::RecorderProbe(const Recorders& r, const fem::Mesh& mesh,
                             const std::vector<BoundaryValueInterface>& contacts)
    : recorders_(r), mesh_(mesh) {
    for (const NodeRecorder& n : r.nodes) {
        node_sets_.push_back(mesh.node_set(n.nodes));
    }
    for (const PointRecorder& p : r.points) {
        const fem::ContactPairSpec& spec = contacts.at(p.contact).pair;
        frames_.push_back(pair_frame(mesh, spec.slave_faces, spec.shear_direction));
    }
    chosen_.assign(r.points.size(), -1);
    chosen_at_.assign(r.points.size(), Vec3{});
}

std::vector<std::optional<double>> RecorderProbe::initial() const {
    std::vector<std::optional<double>> out;
    for (std::size_t k = 0; k < recorders_.nodes.size(); ++k) {
        out.emplace_back(0.0);
    }
    out.resize(out.size() + recorders_.points.size() * point_columns().size());
    return out;
}

std::vector<std::optional<double>> RecorderProbe::measure(const fem::StaticSolver& solver) {
    std::vector<std::optional<double>> out;
    const int D = mesh_.dim();
    const std::vector<double>& u = solver.displacement();
    for (std::size_t k = 0; k < recorders_.nodes.size(); ++k) {
        const std::vector<int>& nodes = node_sets_[k];
        double v = 0.0;
        for (int d = 0; d < D; ++d) {
            double sum = 0.0;
            for (int n : nodes) {
                sum += u[static_cast<std::size_t>(n * D + d)];
            }
            v += sum / static_cast<double>(nodes.size()) *
                 recorders_.nodes[k].direction[static_cast<std::size_t>(d)];
        }
        out.emplace_back(v);
    }
    for (std::size_t k = 0; k < recorders_.points.size(); ++k) {
        const PointRecorder& p = recorders_.points[k];
        const auto& pair = *solver.contacts().at(p.contact);
        const std::vector<fem::ContactPointRecord> records = pair.point_records();
        if (chosen_[k] < 0 && !records.empty()) {
            double best = std::numeric_limits<double>::infinity();
            for (std::size_t i = 0; i < records.size(); ++i) {
                const Vec3 x = contact_point_position(mesh_, records[i]);
                double d2 = 0.0;
                for (std::size_t c = 0; c < 3; ++c) {
                    d2 += (x[c] - p.position[c]) * (x[c] - p.position[c]);
                }
                if (d2 < best) { // the first of equally near points: deterministic
                    best = d2;
                    chosen_[k] = static_cast<long>(i);
                    chosen_at_[k] = x;
                }
            }
        }
        if (chosen_[k] < 0) {
            out.resize(out.size() + point_columns().size());
            continue;
        }
        const fem::ContactPointRecord& r = records.at(static_cast<std::size_t>(chosen_[k]));
        const PairFrame& f = frames_[k];
        out.emplace_back(r.t_N);
        out.emplace_back(dot(r.shear, f.t1));
        out.emplace_back(D == 3 ? dot(r.shear, f.t2) : 0.0);
        for (double v : {r.sigma_p1, r.sigma_p2, r.eps_N, r.eps_p1, r.eps_p2, r.band_thickness,
                         r.void_ratio}) {
            out.push_back(finite(v));
        }
    }
    return out;
}

nlohmann::ordered_json RecorderProbe::chosen_points() const {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (std::size_t k = 0; k < recorders_.points.size(); ++k) {
        const PointRecorder& p = recorders_.points[k];
        nlohmann::ordered_json j = {{"name", p.name}, {"requested", p.position}};
        if (chosen_[k] >= 0) {
            j["point"] = chosen_[k];
            j["position"] = chosen_at_[k];
        } else {
            j["point"] = nullptr; // never paired (the run ended before)
        }
        out.push_back(j);
    }
    return out;
}

} // namespace ifsim::io
