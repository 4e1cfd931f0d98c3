#pragma once
// The constitutive model of a batch, chosen at run time from a scene: its parameters select
// the kernel (one kernel per batch, no branch on the model inside the hot loop).

#include <string>
#include <variant>
#include <vector>

#include "kernels/hypoplasticity.hpp"
#include "kernels/linear_elastic.hpp"
#include "kernels/sanisand.hpp"

namespace ifsim {

using MaterialChoice = std::variant<HypoplasticityParams, SanisandParams, LinearElasticParams>;

// Model of a parameter type.
template <class P>
struct model_of;
template <>
struct model_of<HypoplasticityParams> {
    using type = Hypoplasticity;
};
template <>
struct model_of<SanisandParams> {
    using type = Sanisand;
};
template <>
struct model_of<LinearElasticParams> {
    using type = LinearElastic;
};

inline int state_size(const MaterialChoice& m) {
    return std::visit(
        [](const auto& p) { return model_of<std::decay_t<decltype(p)>>::type::n_state; }, m);
}
inline std::string model_name(const MaterialChoice& m) {
    return std::visit(
        [](const auto& p) { return std::string(model_of<std::decay_t<decltype(p)>>::type::name); },
        m);
}

} // namespace ifsim
