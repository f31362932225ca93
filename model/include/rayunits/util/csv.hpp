// rayunits util: CSV writing and reading (RFC 4180 quoting), one implementation for every area.
//
// Cells are quoted only when they need it (a comma, a double quote, CR or LF inside); a quote
// inside a quoted cell is doubled. The reader accepts what the writer writes: quoted cells
// with commas, doubled quotes and line breaks inside, CRLF or LF line ends.
#pragma once

#include <string>
#include <vector>

namespace ru::util {

std::string csv_cell(const std::string& v);
// One record: the cells joined with ',' and a terminating '\n'.
std::string csv_row(const std::vector<std::string>& cells);

using CsvRow = std::vector<std::string>;
// Every record of `text`. Empty lines are skipped; so are lines starting with `comment` (when
// it is not '\0', e.g. '#' for the "# command" lines of the studies' CSV files).
std::vector<CsvRow> csv_parse(const std::string& text, char comment = '\0');
// The records of a file ("cannot read" -> empty).
std::vector<CsvRow> csv_read_file(const std::string& path, char comment = '\0');

}  // namespace ru::util
