// rayunits util: CSV (see rayunits/util/csv.hpp).
#include "rayunits/util/csv.hpp"

#include <fstream>
#include <sstream>

namespace ru::util {

std::string csv_cell(const std::string& v) {
  if (v.find_first_of(",\"\r\n") == std::string::npos) return v;
  std::string q = "\"";
  for (char c : v) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string csv_row(const std::vector<std::string>& cells) {
  std::string s;
  for (size_t i = 0; i < cells.size(); ++i) s += (i ? "," : "") + csv_cell(cells[i]);
  return s + "\n";
}

std::vector<CsvRow> csv_parse(const std::string& text, char comment) {
  std::vector<CsvRow> rows;
  CsvRow row;
  std::string cell;
  bool quoted = false, at_line_start = true, any = false;
  size_t i = 0;
  auto end_record = [&] {
    if (any) {
      row.push_back(cell);
      rows.push_back(row);
    }
    row.clear();
    cell.clear();
    any = false;
    at_line_start = true;
  };
  while (i < text.size()) {
    const char c = text[i];
    if (at_line_start && comment && c == comment) {  // a comment line
      while (i < text.size() && text[i] != '\n') ++i;
      ++i;
      continue;
    }
    at_line_start = false;
    if (quoted) {
      if (c == '"') {
        if (i + 1 < text.size() && text[i + 1] == '"') {
          cell += '"';
          ++i;
        } else {
          quoted = false;
        }
      } else {
        cell += c;
      }
      ++i;
      continue;
    }
    if (c == '"') {
      quoted = true;
      any = true;
    } else if (c == ',') {
      row.push_back(cell);
      cell.clear();
      any = true;
    } else if (c == '\n' || c == '\r') {
      if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
      end_record();
    } else {
      cell += c;
      any = true;
    }
    ++i;
  }
  end_record();
  return rows;
}

std::vector<CsvRow> csv_read_file(const std::string& path, char comment) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return {};
  std::ostringstream s;
  s << f.rdbuf();
  return csv_parse(s.str(), comment);
}

}  // namespace ru::util
