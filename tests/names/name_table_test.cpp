// The one name table (names/): both directions from one table, one way to refuse a word.
#include "leafdig/names/name_table.hpp"

#include <gtest/gtest.h>

#include "leafdig/model/leaf/markers.hpp"

namespace {

enum class Colour { Red, Green, Blue };
constexpr leafdig::NameTable<Colour, 3> kColours{
    {{Colour::Red, "red"}, {Colour::Green, "green"}, {Colour::Blue, "blue"}}};

TEST(NameTable, AValueAndItsWordComeFromOneTable) {
  static_assert(std::string_view(leafdig::nameIn(kColours, Colour::Green)) == "green");
  static_assert(leafdig::valueIn(kColours, "blue") == Colour::Blue);
  static_assert(!leafdig::valueIn(kColours, "Blue").has_value());  // words are exact
  EXPECT_STREQ(leafdig::nameIn(kColours, static_cast<Colour>(7)), "?");
  for (const auto& [value, word] : kColours) EXPECT_EQ(leafdig::parseName(kColours, word, "colour"), value) << word;
}

TEST(NameTable, AnUnknownWordIsRefusedOneWayNamingWhatAndTheChoices) {
  EXPECT_EQ(leafdig::choicesIn(kColours), "red, green or blue");
  EXPECT_EQ(leafdig::choicesIn(leafdig::NameTable<Colour, 1>{{{Colour::Red, "red"}}}), "red");
  EXPECT_EQ(leafdig::choicesIn(leafdig::NameTable<Colour, 2>{{{Colour::Red, "red"}, {Colour::Blue, "blue"}}}),
            "red or blue");
  try {
    (void)leafdig::parseName(kColours, "mauve", "colour");
    FAIL() << "mauve is not a colour here";
  } catch (const leafdig::UnknownName& e) {
    EXPECT_STREQ(e.what(), "unknown colour \"mauve\": use red, green or blue");
    EXPECT_EQ(e.word(), "mauve");
  }
  // It is bad input like any other: a std::invalid_argument.
  EXPECT_THROW((void)leafdig::parseName(kColours, "", "colour"), std::invalid_argument);
  // Every module's enums answer the same way.
  try {
    (void)leafdig::model::serrationFromString("wavy");
    FAIL();
  } catch (const leafdig::UnknownName& e) {
    EXPECT_STREQ(e.what(), "unknown serration \"wavy\": use none, round, sharp, straight or acuminate");
  }
  // The choices a list offers are the table's words, in its order.
  EXPECT_EQ(leafdig::wordsIn(kColours), (std::vector<std::string>{"red", "green", "blue"}));
  EXPECT_EQ(leafdig::wordsIn(leafdig::model::kSerrationNames),
            (std::vector<std::string>{"none", "round", "sharp", "straight", "acuminate"}));
}

}  // namespace
