// The JSON location scanner: the line where the value at a path starts, through strings with escapes, nested
// containers, a byte order mark and any depth; falling back to the deepest existing ancestor.
#include <gtest/gtest.h>

#include "scene/json_locate.h"

namespace pt {
namespace {

TEST(JsonLocate, FindsNestedValuesAndFallsBackToAncestors) {
  std::string text =
      "{\n"                               // 1
      " \"a\": [\n"                       // 2
      "  1,\n"                            // 3
      "  {\"b\": \"x\\\"y}]{\",\n"        // 4: a string with an escaped quote and brackets
      "   \"c\": 3}\n"                    // 5
      " ],\n"                             // 6
      " \"d\": {},\n"                     // 7
      " \"e\":\n"                         // 8
      "\n"                                // 9
      "   [[], [[\"deep\"]]]\n"           // 10
      "}";
  EXPECT_EQ(json_line_of(text, {}), 1);
  EXPECT_EQ(json_line_of(text, {"a"}), 2);
  EXPECT_EQ(json_line_of(text, {"a", "0"}), 3);
  EXPECT_EQ(json_line_of(text, {"a", "1"}), 4);
  EXPECT_EQ(json_line_of(text, {"a", "1", "b"}), 4);
  EXPECT_EQ(json_line_of(text, {"a", "1", "c"}), 5);
  EXPECT_EQ(json_line_of(text, {"d"}), 7);
  EXPECT_EQ(json_line_of(text, {"e"}), 10);  // the value, not the key
  EXPECT_EQ(json_line_of(text, {"e", "1", "0", "0"}), 10);
  // Missing parts: the deepest value that exists.
  EXPECT_EQ(json_line_of(text, {"a", "7"}), 2);
  EXPECT_EQ(json_line_of(text, {"a", "1", "zz"}), 4);
  EXPECT_EQ(json_line_of(text, {"nope", "x"}), 1);
  EXPECT_EQ(json_line_of(text, {"d", "0"}), 7);  // an index into an object
  EXPECT_EQ(json_line_of(text, {"a", "b"}), 2);  // a key into an array
}

TEST(JsonLocate, MatchesKeysWrittenWithEscapes) {
  // "\u00e9" and the raw UTF-8 "é" are the same key to a parser, as are "\/" and "/".
  std::string text = "{\n\"caf\\u00e9\": 1,\n\"a\\/b\": 2,\n\"\\ud83d\\ude00\": 3,\n\"tab\\tkey\": 4\n}";
  EXPECT_EQ(json_line_of(text, {"caf\xC3\xA9"}), 2);
  EXPECT_EQ(json_line_of(text, {"a/b"}), 3);
  EXPECT_EQ(json_line_of(text, {"\xF0\x9F\x98\x80"}), 4);  // a surrogate pair
  EXPECT_EQ(json_line_of(text, {"tab\tkey"}), 5);
  text = "{\"a\": 0,\n\"\\u20ac\": 1}";  // a three-byte character
  EXPECT_EQ(json_line_of(text, {"\xE2\x82\xAC"}), 2);
  text = "{\n\"two\\nlines\": 1}";
  EXPECT_EQ(json_line_of(text, {"two\nlines"}), 2);
}

// A path part that reads as a number is an index only into an array: into an object it is a key (a material may be
// named "0"). An index into an empty array is missing, and the line is then the array's.
TEST(JsonLocate, NumericKeysOfObjectsAndIndicesPastTheEnd) {
  std::string text =
      "{\n"                  // 1
      "\"m\": {\"1\": 0,\n"  // 2
      " \"0\": 1},\n"        // 3
      "\"e\": [\n"           // 4
      "\n"                   // 5
      "],\n"                 // 6
      "\"f\": [1,\n"         // 7
      " 2\n"                 // 8
      "]}";
  EXPECT_EQ(json_line_of(text, {"m", "0"}), 3);
  EXPECT_EQ(json_line_of(text, {"m", "1"}), 2);
  EXPECT_EQ(json_line_of(text, {"e", "0"}), 4);
  EXPECT_EQ(json_line_of(text, {"f", "1"}), 8);
  EXPECT_EQ(json_line_of(text, {"f", "2"}), 7);
}

TEST(JsonLocate, CountsLinesInEveryKindOfWhitespace) {
  // Tabs are whitespace between tokens; the newlines after a number are counted, not skipped with it.
  std::string text = "{\n\t\"a\":\t1\n\n ,\t\"b\": true \n,\"c\":\n\tnull}";
  EXPECT_EQ(json_line_of(text, {"a"}), 2);
  EXPECT_EQ(json_line_of(text, {"b"}), 4);
  EXPECT_EQ(json_line_of(text, {"c"}), 6);
}

TEST(JsonLocate, AKeyGivenTwiceIsFoundWhereTheParserTakesItsValue) {
  // nlohmann keeps the last value of a repeated key, so a message about that value names the last one's line.
  std::string text = "{\n\"a\": {\"b\": 1,\n \"b\": 2,\n \"c\": 0},\n\"a\":\n {\"b\": 3}\n}";
  EXPECT_EQ(json_line_of(text, {"a"}), 6);
  EXPECT_EQ(json_line_of(text, {"a", "b"}), 6);
  EXPECT_EQ(json_line_of(text.substr(0, text.find(",\n\"a\":\n")) + "}", {"a", "b"}), 3);
}

TEST(JsonLocate, SkipsAByteOrderMarkAndCountsCarriageReturnLineEnds) {
  std::string text = "\xEF\xBB\xBF{\r\n \"a\": 1,\r\n \"b\": 2\r\n}";
  EXPECT_EQ(json_line_of(text, {"b"}), 3);
}

TEST(JsonLocate, DeepNestingNeedsNoRecursion) {
  // A value nested a million levels deep before the key we want: a recursive skip would overflow the stack.
  const size_t depth = 1000000;
  std::string text = "{\"x\": " + std::string(depth, '[') + std::string(depth, ']') + ",\n\"y\": 1}";
  EXPECT_EQ(json_line_of(text, {"y"}), 2);
  EXPECT_EQ(json_line_of(text, {"x", "0", "0", "0"}), 1);
}

TEST(JsonLocate, FindsTokensOutsideStringsOnly) {
  std::string text = "{\"note\": \"1e999\",\n \"v\": [1,\n  1e999]}";
  EXPECT_EQ(json_line_of_token(text, "1e999"), 3);
  EXPECT_EQ(json_line_of_token(text, "2e999"), 0);
}

}  // namespace
}  // namespace pt
