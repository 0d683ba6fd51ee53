// base/enum_names.hpp: a table's names and values map both ways, and a name the table lacks
// has no value. The project's tables themselves are checked where their enums live.
#include <gtest/gtest.h>

#include "base/enum_names.hpp"

namespace codesign {
namespace {

enum class Colour { Red, Green, Blue };
inline constexpr EnumNames<Colour, 3> kColourNames{{{Colour::Red, "red"}, {Colour::Green, "green"}, {Colour::Blue, "blue"}}};

TEST(EnumNames, NamesAndValuesMapBothWays) {
  for (const EnumName<Colour>& n : kColourNames) {
    EXPECT_EQ(name_of(kColourNames, n.value), n.name);
    EXPECT_EQ(value_of(kColourNames, n.name), n.value);
  }
  EXPECT_FALSE(value_of(kColourNames, "Red"));  // names are exact
  EXPECT_FALSE(value_of(kColourNames, ""));
  const auto names = names_in(kColourNames);
  EXPECT_EQ(names[0], "red");
  EXPECT_EQ(names[2], "blue");
  static_assert(name_of(kColourNames, Colour::Green) == "green");  // usable in constant expressions
}

TEST(EnumNames, AValueMissingFromItsTableIsNamedQuestionMark) {
  constexpr EnumNames<Colour, 2> partial{{{Colour::Red, "red"}, {Colour::Green, "green"}}};
  EXPECT_EQ(name_of(partial, Colour::Blue), "?");
}

}  // namespace
}  // namespace codesign
