#pragma once
// The constitutive models of ifsim, listed once. Each entry names its kernel (kernels/, a type
// satisfying the ConstitutiveModel concept of kernels/model_api.hpp) and what a scene and the
// outputs need to know of it: the built-in parameter sets (the first is the default where a
// scene may omit the set), the initial-state keys of its own state, the history column
// prefixes of that state (six columns each, Voigt order), and whether Algorithm 1 can use it
// as an interface model. MaterialChoice, the run-time choice of a batch's model, is the
// variant of the listed models' parameters.
//
// Adding a model: docs/architecture.md, "Add a constitutive model".

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <variant>
#include <vector>

#include "kernels/hypoplasticity.hpp"
#include "kernels/linear_elastic.hpp"
#include "kernels/model_api.hpp"
#include "kernels/parameter_sets.hpp"
#include "kernels/sanisand.hpp"

namespace ifsim {

template <ConstitutiveModel M>
struct ModelEntry;

template <>
struct ModelEntry<Hypoplasticity> {
    static constexpr std::array<std::string_view, 2> sets{"l4c", "karlsruhe-sand"};
    static constexpr std::array<std::string_view, 1> state_keys{"intergranular_strain"};
    static constexpr std::array<std::string_view, 1> history_prefixes{"h"};
    static constexpr bool interface_model = true;
    static std::optional<HypoplasticityParams> set(std::string_view name) {
        return parameter_sets::hypoplasticity(name);
    }
};

template <>
struct ModelEntry<Sanisand> {
    static constexpr std::array<std::string_view, 1> sets{"karlsruhe-sand"};
    static constexpr std::array<std::string_view, 2> state_keys{"back_stress", "fabric"};
    // back stress alpha, fabric z, alpha at the last load reversal
    static constexpr std::array<std::string_view, 3> history_prefixes{"a", "z", "ain"};
    static constexpr bool interface_model = true;
    static std::optional<SanisandParams> set(std::string_view name) {
        return parameter_sets::sanisand(name);
    }
};

template <>
struct ModelEntry<LinearElastic> {
    static constexpr std::array<std::string_view, 0> sets{};
    static constexpr std::array<std::string_view, 0> state_keys{};
    static constexpr std::array<std::string_view, 0> history_prefixes{};
    static constexpr bool interface_model = false; // no state to carry through Algorithm 1
    static std::optional<LinearElasticParams> set(std::string_view) { return std::nullopt; }
};

// The list, in the order of MaterialChoice's alternatives.
using Models = std::tuple<Hypoplasticity, Sanisand, LinearElastic>;

namespace detail {
template <class Tuple>
struct params_variant;
template <class... M>
struct params_variant<std::tuple<M...>> {
    using type = std::variant<typename M::Params...>;
};
} // namespace detail

using MaterialChoice = detail::params_variant<Models>::type;

// Calls f(M{}) (a value of the model type, for its static members) for every listed model.
template <class F>
void for_each_model(F&& f) {
    std::apply([&](auto... m) { (f(m), ...); }, Models{});
}

// Model of a parameter type: the listed model whose Params it is.
namespace detail {
template <class P, class... M>
struct find_model {
    using type = void;
};
template <class P, class M, class... Rest>
struct find_model<P, M, Rest...> {
    using type = std::conditional_t<std::is_same_v<typename M::Params, P>, M,
                                    typename find_model<P, Rest...>::type>;
};
template <class P, class Tuple>
struct find_in_list;
template <class P, class... M>
struct find_in_list<P, std::tuple<M...>> : find_model<P, M...> {};
} // namespace detail

template <class P>
struct model_of {
    using type = typename detail::find_in_list<P, Models>::type;
    static_assert(!std::is_void_v<type>, "a parameter type of no listed model");
};

// The scene names of the models ("hypoplasticity", ...); only_interface: those usable as
// interface models.
inline std::vector<std::string_view> model_names(bool only_interface = false) {
    std::vector<std::string_view> names;
    for_each_model([&](auto m) {
        using M = decltype(m);
        if (!only_interface || ModelEntry<M>::interface_model) {
            names.emplace_back(M::name);
        }
    });
    return names;
}

// The built-in parameter sets of a model by scene name ("" when it has none; unknown model:
// empty list), the first being the default.
inline std::vector<std::string_view> model_sets(std::string_view model) {
    std::vector<std::string_view> sets;
    for_each_model([&](auto m) {
        using M = decltype(m);
        if (model == M::name) {
            sets.assign(ModelEntry<M>::sets.begin(), ModelEntry<M>::sets.end());
        }
    });
    return sets;
}

// The model-specific initial-state keys of a model by scene name.
inline std::vector<std::string_view> model_state_keys(std::string_view model) {
    std::vector<std::string_view> keys;
    for_each_model([&](auto m) {
        using M = decltype(m);
        if (model == M::name) {
            keys.assign(ModelEntry<M>::state_keys.begin(), ModelEntry<M>::state_keys.end());
        }
    });
    return keys;
}

inline int state_size(const MaterialChoice& m) {
    return std::visit(
        [](const auto& p) { return model_of<std::decay_t<decltype(p)>>::type::n_state; }, m);
}
// The part of the state results report: stress, void ratio and the history blocks, without
// integration data after them (the carried substep size, kernels/explicit_integration.hpp).
inline int reported_state_size(const MaterialChoice& m) {
    return std::visit(
        [](const auto& p) {
            using E = ModelEntry<typename model_of<std::decay_t<decltype(p)>>::type>;
            return 7 + 6 * static_cast<int>(E::history_prefixes.size());
        },
        m);
}
inline std::string model_name(const MaterialChoice& m) {
    return std::visit(
        [](const auto& p) { return std::string(model_of<std::decay_t<decltype(p)>>::type::name); },
        m);
}
// History column prefixes of the model's own state (six columns each).
inline std::vector<std::string_view> history_prefixes(const MaterialChoice& m) {
    return std::visit(
        [](const auto& p) {
            using E = ModelEntry<typename model_of<std::decay_t<decltype(p)>>::type>;
            return std::vector<std::string_view>(E::history_prefixes.begin(),
                                                 E::history_prefixes.end());
        },
        m);
}

} // namespace ifsim
