// The vocabulary tables: every name reads back to its value and every value has a name, the lists
// in help texts and messages follow the table, and unknown names are refused the same way.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "vocabulary.h"

using namespace corebox;

namespace {

template <class Enum>
void expectConsistent(const Vocabulary<Enum>& table) {
    SCOPED_TRACE(table.what());
    ASSERT_GT(table.size(), 0u);
    std::set<std::string> names;
    std::string list;
    for (const Term<Enum>& term : table) {
        EXPECT_TRUE(names.insert(term.name).second) << "name twice: " << term.name;
        Enum parsed{};
        ASSERT_TRUE(table.parse(term.name, &parsed)) << term.name;
        EXPECT_EQ(parsed, term.value);
        EXPECT_STREQ(table.name(term.value), term.name);
        EXPECT_LT(table.indexOf(term.value), table.size());
        list += (list.empty() ? "" : ", ") + std::string(term.name);
    }
    EXPECT_EQ(table.list(), list);
    EXPECT_EQ(table.names().size(), table.size());
    Enum untouched = table.begin()->value;
    EXPECT_FALSE(table.parse("no-such-name", &untouched));
    EXPECT_EQ(untouched, table.begin()->value);
    EXPECT_EQ(table.unknown("no-such-name"), "unknown " + std::string(table.what()) + " 'no-such-name'; one of: " + list);
}

}  // namespace

TEST(Vocabulary, EveryTableReadsBackWhatItNames) {
    expectConsistent(methodTable());
    expectConsistent(precisionTable());
    expectConsistent(backendTable());
    expectConsistent(thermostatTable());
    expectConsistent(shiftTable());
    expectConsistent(placementTable());
}

TEST(Vocabulary, EveryMethodHasANameAndANote) {
    for (Method m : {Method::Euler, Method::Rk2, Method::Rk4, Method::Dp5, Method::Hairer10, Method::Verlet}) {
        EXPECT_LT(methodTable().indexOf(m), methodTable().size()) << int(m);
    }
    for (const Term<Method>& term : methodTable()) EXPECT_STRNE(term.note, "") << term.name;
}

TEST(Vocabulary, ShorthandsAgreeWithTheTables) {
    Method m{};
    EXPECT_TRUE(parseMethod("hairer10", &m));
    EXPECT_EQ(m, Method::Hairer10);
    EXPECT_FALSE(parseMethod("Hairer10", &m));  // names are exact: what a file says is what runs
    EXPECT_STREQ(methodName(Method::Verlet), "verlet");
    EXPECT_STREQ(precisionName(Precision::Fp32), "fp32");
    EXPECT_STREQ(thermostatName(ThermostatKind::None), "none");
    EXPECT_STREQ(shiftName(CutoffShift::Energy), "energy");
}
