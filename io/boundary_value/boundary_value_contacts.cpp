#include "io/boundary_value/boundary_value_contacts.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace ifsim::io {

namespace {

bool valid_name(const std::string& name) {
    return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
        return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
               c == '_' || c == '-';
    });
}

BoundaryValueInterface read_named_pair(const TableReader& t, const fem::Mesh& mesh,
                                       const std::map<std::string, BodyMaterial>& materials,
                                       const std::vector<BoundaryValueInterface>& before) {
    std::vector<std::string_view> keys = boundary_value_interface_keys();
    keys.insert(keys.begin(), "name");
    t.allow_only(keys);
    const std::string name = t.string("name");
    if (!valid_name(name)) {
        t.fail("name", fmt::format("expected a name of letters, digits, '_' and '-' "
                                   "([A-Za-z0-9_-]+), got \"{}\"",
                                   name));
    }
    for (const BoundaryValueInterface& other : before) {
        if (other.pair.name == name) {
            t.fail("name", fmt::format("expected a name not used by another [[contact]] entry, "
                                       "got \"{}\"",
                                       name));
        }
    }
    return read_boundary_value_pair(t, name, mesh, materials);
}

} // namespace

std::vector<BoundaryValueInterface>
read_boundary_value_contacts(const TableReader& root, const fem::Mesh& mesh,
                             const std::map<std::string, BodyMaterial>& materials) {
    std::vector<BoundaryValueInterface> out;
    if (root.has("interface") && root.has("contact")) {
        root.fail("contact", "expected either [interface] (one contact pair) or [[contact]] "
                             "entries (named pairs), not both");
    }
    if (root.has("interface")) {
        out.push_back(read_boundary_value_interface(root.table("interface"), mesh, materials));
        return out;
    }
    if (!root.has("contact")) {
        return out;
    }
    for (const TableReader& t : root.array_of_tables("contact")) {
        out.push_back(read_named_pair(t, mesh, materials, out));
    }
    return out;
}

} // namespace ifsim::io
