// The model registry (engine/model_registry.hpp) is consistent with the kernels it lists:
// every built-in set it names exists, its history columns cover the model's state exactly, and
// the parameter variant maps back to the model.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>

#include "engine/model_registry.hpp"

namespace ifsim {
namespace {

TEST(ModelRegistry, EveryEntryMatchesItsKernel) {
    std::set<std::string> names;
    int listed = 0;
    for_each_model([&](auto m) {
        using M = decltype(m);
        using E = ModelEntry<M>;
        ++listed;
        EXPECT_TRUE(names.insert(M::name).second) << "model listed twice: " << M::name;
        for (std::string_view set : E::sets) {
            EXPECT_TRUE(E::set(set).has_value()) << M::name << " set " << set;
        }
        EXPECT_FALSE(E::set("no-such-set").has_value()) << M::name;
        // Stress (6), void ratio, six history columns per prefix, then the carried substep.
        EXPECT_EQ(7 + 6 * static_cast<int>(E::history_prefixes.size()) +
                      (CarriesSubstep<M> ? 1 : 0),
                  M::n_state)
            << M::name;
        static_assert(std::is_same_v<typename model_of<typename M::Params>::type, M>);
        const MaterialChoice choice = typename M::Params{};
        EXPECT_EQ(model_name(choice), M::name);
        EXPECT_EQ(state_size(choice), M::n_state);
        EXPECT_EQ(history_prefixes(choice).size(), E::history_prefixes.size());
        const auto sets = model_sets(M::name);
        EXPECT_EQ(sets.size(), E::sets.size()) << M::name;
    });
    EXPECT_EQ(listed, static_cast<int>(std::variant_size_v<MaterialChoice>));
    EXPECT_EQ(model_names().size(), names.size());
    // Interface models carry a state through Algorithm 1: the elastic model is not one.
    const auto interface_models = model_names(true);
    EXPECT_EQ(std::count(interface_models.begin(), interface_models.end(), LinearElastic::name), 0);
    EXPECT_TRUE(model_sets("no-such-model").empty());
}

} // namespace
} // namespace ifsim
