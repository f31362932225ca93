// util/csv.hpp: the writer's quoting and the reader reading it back.
#include <gtest/gtest.h>

#include "rayunits/util/csv.hpp"

namespace {
using namespace ru::util;

TEST(UtilCsv, QuotesOnlyWhenNeeded) {
  EXPECT_EQ(csv_cell("e8m23"), "e8m23");
  EXPECT_EQ(csv_cell(""), "");
  EXPECT_EQ(csv_cell("a,b"), "\"a,b\"");
  EXPECT_EQ(csv_cell("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(csv_cell("two\nlines"), "\"two\nlines\"");
  EXPECT_EQ(csv_row({"unit", "a,b", ""}), "unit,\"a,b\",\n");
}

TEST(UtilCsv, ReadsWhatItWrites) {
  const std::vector<CsvRow> rows = {{"unit", "format", "note"},
                                    {"ru_fp_add", "e8m23", "a,b \"q\"\nsecond line"},
                                    {"", "", ""},
                                    {"x", "", "last"}};
  std::string text;
  for (const auto& r : rows) text += csv_row(r);
  EXPECT_EQ(csv_parse(text), rows);
  EXPECT_EQ(csv_parse("a,b\r\n1,2\r\n\r\n"), (std::vector<CsvRow>{{"a", "b"}, {"1", "2"}}));
  EXPECT_EQ(csv_parse("# rayunits study tri\nh1,h2\n#x\n1,2", '#'), (std::vector<CsvRow>{{"h1", "h2"}, {"1", "2"}}));
  EXPECT_EQ(csv_parse("# not a comment\n", '\0'), (std::vector<CsvRow>{{"# not a comment"}}));
  EXPECT_TRUE(csv_parse("").empty());
  EXPECT_TRUE(csv_read_file("/nonexistent/ru.csv").empty());
}

}  // namespace
