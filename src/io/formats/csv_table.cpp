#include "io/formats/csv_table.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>

#include "base/errors.hpp"

namespace codesign::io {

namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    if (comma == std::string::npos) {
      out.push_back(line.substr(start));
      return out;
    }
    out.push_back(line.substr(start, comma - start));
    start = comma + 1;
  }
}

}  // namespace

CsvTable::CsvTable(std::string path, std::vector<std::string> columns, std::vector<std::vector<std::string>> cells)
    : path_(std::move(path)), columns_(std::move(columns)), cells_(std::move(cells)) {}

bool CsvTable::has_column(const std::string& name) const {
  for (const std::string& c : columns_)
    if (c == name) return true;
  return false;
}

std::size_t CsvTable::column(const std::string& name) const {
  for (std::size_t i = 0; i < columns_.size(); ++i)
    if (columns_[i] == name) return i;
  std::string list;
  for (const std::string& c : columns_) list += (list.empty() ? "" : ", ") + c;
  throw InputError(path_ + ": no column '" + name + "' (columns: " + list + ")");
}

double CsvTable::number(std::size_t row, std::size_t col) const {
  const std::string& s = cell(row, col);
  const char* begin = s.c_str();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(begin, &end);
  if (s.empty() || end != begin + s.size() || !std::isfinite(v)) {
    throw InputError(path_ + ": line " + std::to_string(row + 2) + ", column '" + columns_[col] + "': '" + s +
                     "' is not a finite number");
  }
  return v;
}

std::int64_t CsvTable::integer(std::size_t row, std::size_t col) const {
  const std::string& s = cell(row, col);
  std::int64_t v = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || ptr != s.data() + s.size()) {
    throw InputError(path_ + ": line " + std::to_string(row + 2) + ", column '" + columns_[col] + "': '" + s +
                     "' is not an integer");
  }
  return v;
}

std::vector<double> CsvTable::numbers(const std::string& name) const {
  const std::size_t c = column(name);
  std::vector<double> out(rows());
  for (std::size_t r = 0; r < rows(); ++r) out[r] = number(r, c);
  return out;
}

CsvTable read_csv(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open (" + std::strerror(errno) + ")");
  std::ostringstream all;
  all << in.rdbuf();
  if (in.bad()) throw InputError(path + ": read error");
  const std::string text = all.str();

  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t nl = text.find('\n', start);
    if (nl == std::string::npos) break;  // unterminated last line: a writer in progress
    std::string line = text.substr(start, nl - start);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(std::move(line));
    start = nl + 1;
  }
  if (lines.empty() || lines.front().empty()) throw InputError(path + ": no header row (empty file?)");
  std::vector<std::string> columns = split(lines.front());
  std::set<std::string> seen;
  for (const std::string& c : columns) {
    if (c.empty()) throw InputError(path + ": line 1: empty column name in the header");
    if (!seen.insert(c).second) throw InputError(path + ": line 1: column '" + c + "' appears twice");
  }
  std::vector<std::vector<std::string>> cells;
  cells.reserve(lines.size() - 1);
  for (std::size_t i = 1; i < lines.size(); ++i) {
    std::vector<std::string> row = split(lines[i]);
    if (row.size() != columns.size()) {
      throw InputError(path + ": line " + std::to_string(i + 1) + ": " + std::to_string(row.size()) +
                       " cells, the header has " + std::to_string(columns.size()));
    }
    cells.push_back(std::move(row));
  }
  return CsvTable(path, std::move(columns), std::move(cells));
}

}  // namespace codesign::io
