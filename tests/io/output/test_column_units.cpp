// Every history.csv column of every scene kind and model has a unit in summary.json
// "columns": a column added without one is caught here (and by every run, which refuses to
// write a summary with an undescribed column).
#include <gtest/gtest.h>

#include "engine/model_registry.hpp"
#include "io/element_test/element_history.hpp"
#include "io/interface_test/interface_history.hpp"
#include "io/output/column_units.hpp"

using namespace ifsim;
using namespace ifsim::io;

TEST(ColumnUnits, EveryElementTestColumnOfEveryModelHasAUnit) {
    for_each_model([](auto m) {
        using M = decltype(m);
        const MaterialChoice choice = typename M::Params{};
        const auto cols = element_history_columns(choice);
        const auto j = describe_columns("element-test", cols);
        ASSERT_EQ(j.size(), cols.size()) << M::name;
        for (const auto& c : j) {
            EXPECT_FALSE(c["unit"].get<std::string>().empty()) << c["name"];
        }
    });
    EXPECT_EQ(describe_column("element-test", "s12")->unit, "kPa");
    EXPECT_EQ(describe_column("element-test", "eps33")->unit, "-");
    EXPECT_NE(describe_column("element-test", "ain13")->meaning.find("reversal"),
              std::string::npos);
}

TEST(ColumnUnits, InterfaceAndBoundaryValueColumnsHaveUnits) {
    const auto j = describe_columns("interface-test", interface_history_columns());
    EXPECT_EQ(j.size(), interface_history_columns().size());
    EXPECT_EQ(describe_column("interface-test", "u_n")->unit, "m");
    EXPECT_EQ(describe_column("interface-test", "t_t1")->unit, "kPa");
    EXPECT_EQ(describe_column("boundary-value", "band_thickness")->unit, "m");
    const auto pair = describe_column("boundary-value", "left.t_n");
    ASSERT_TRUE(pair.has_value());
    EXPECT_EQ(pair->unit, "kPa");
    EXPECT_NE(pair->meaning.find("pair left"), std::string::npos);
}

TEST(ColumnUnits, AnUnknownColumnIsRefusedByName) {
    EXPECT_FALSE(describe_column("boundary-value", "t_nn").has_value());
    EXPECT_FALSE(describe_column("element-test", "s14").has_value());
    try {
        describe_columns("interface-test", {"step", "mystery"});
        FAIL() << "no exception";
    } catch (const std::logic_error& e) {
        EXPECT_NE(std::string(e.what()).find("mystery"), std::string::npos);
    }
}
