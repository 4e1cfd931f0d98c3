#include "io/boundary_value/boundary_value_region.hpp"

#include <algorithm>
#include <limits>

#include <fmt/format.h>

namespace ifsim::io {

namespace {

template <class Names>
std::string quoted_list(const Names& names) {
    std::string list;
    for (const auto& n : names) {
        list += fmt::format("{}\"{}\"", list.empty() ? "" : ", ", n);
    }
    return list;
}

std::vector<std::string> element_set_names(const fem::Mesh& mesh) {
    std::vector<std::string> names;
    for (const auto& [name, elements] : mesh.element_sets) {
        names.push_back(name);
    }
    return names;
}

// The bounding box of the set's nodes as a body's origin and size.
void bounding_box(const fem::Mesh& mesh, const std::vector<int>& elements, BodySpec& body) {
    const auto d = static_cast<std::size_t>(mesh.dim());
    std::vector<double> lo(d, std::numeric_limits<double>::infinity());
    std::vector<double> hi(d, -std::numeric_limits<double>::infinity());
    for (int e : elements) {
        for (int a = 0; a < mesh.nodes_per_element(); ++a) {
            for (std::size_t i = 0; i < d; ++i) {
                const double x = mesh.coordinate(mesh.node(e, a), static_cast<int>(i));
                lo[i] = std::min(lo[i], x);
                hi[i] = std::max(hi[i], x);
            }
        }
    }
    body.origin = lo;
    body.size.resize(d);
    for (std::size_t i = 0; i < d; ++i) {
        body.size[i] = hi[i] - lo[i];
    }
}

} // namespace

std::vector<BodySpec> read_regions(const TableReader& root, const fem::Mesh& mesh,
                                   const std::vector<std::string>& materials) {
    std::vector<BodySpec> regions;
    std::vector<int> region_of(static_cast<std::size_t>(mesh.n_elements()), -1);
    for (const TableReader& t : root.array_of_tables("region")) {
        t.allow_only({"set", "material"});
        BodySpec body;
        body.name = t.string("set");
        if (!mesh.element_sets.contains(body.name)) {
            t.fail("set", fmt::format("expected an element set of the mesh (a physical group of "
                                      "the mesh dimension): {}; got \"{}\"",
                                      quoted_list(element_set_names(mesh)), body.name));
        }
        body.material = t.string("material");
        if (std::find(materials.begin(), materials.end(), body.material) == materials.end()) {
            t.fail("material", fmt::format("expected the name of a [material.NAME] table ({}), "
                                           "got \"{}\"",
                                           quoted_list(materials), body.material));
        }
        const std::vector<int>& elements = mesh.element_set(body.name);
        const int id = static_cast<int>(regions.size());
        for (int e : elements) {
            const int other = region_of[static_cast<std::size_t>(e)];
            if (other >= 0) {
                t.fail("set", fmt::format("expected a set sharing no element with another "
                                          "region's; element {} of \"{}\" is also in region {} "
                                          "(set \"{}\")",
                                          e, body.name, other + 1,
                                          regions[static_cast<std::size_t>(other)].name));
            }
            region_of[static_cast<std::size_t>(e)] = id;
        }
        bounding_box(mesh, elements, body);
        regions.push_back(std::move(body));
    }
    const auto missing = std::find(region_of.begin(), region_of.end(), -1);
    if (missing != region_of.end()) {
        const int e = static_cast<int>(missing - region_of.begin());
        const auto count = std::count(region_of.begin(), region_of.end(), -1);
        std::vector<std::string> sets;
        for (const auto& [name, elements] : mesh.element_sets) {
            if (name != "all" && std::find(elements.begin(), elements.end(), e) != elements.end()) {
                sets.push_back(name);
            }
        }
        root.fail("region",
                  fmt::format("expected [[region]] entries giving every element a material; {} "
                              "element(s) have none, the first is element {} ({})",
                              count, e,
                              sets.empty() ? std::string("in no physical group")
                                           : "in set(s) " + quoted_list(sets)));
    }
    return regions;
}

} // namespace ifsim::io
