#pragma once
// The explicit scheme of the continuum models' substepping, as a scene key.

#include <string_view>

#include "io/scene/table_reader.hpp"
#include "kernels/model_api.hpp"

namespace ifsim::io {

// `key` = "rkf23" (Runge-Kutta-Fehlberg 2(3), the default) | "heun" (modified Euler 1(2)).
inline IntegrationScheme read_integration_scheme(const TableReader& t, std::string_view key,
                                                 IntegrationScheme fallback) {
    const std::string_view name = fallback == IntegrationScheme::heun ? "heun" : "rkf23";
    return t.choice_or(key, name, {"rkf23", "heun"}) == "heun" ? IntegrationScheme::heun
                                                               : IntegrationScheme::rkf23;
}

} // namespace ifsim::io
