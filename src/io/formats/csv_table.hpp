#pragma once
// Reading a whole CSV file (as written by CsvLog / CsvWriter) into memory: a header row of
// column names, then rows of cells separated by commas (no quoting: our writers never emit a
// comma, quote or newline inside a cell).
//
//   const io::CsvTable t = io::read_csv("runs/quick/sampled.csv");
//   const std::size_t ret = t.column("return");
//   for (std::size_t r = 0; r < t.rows(); ++r) use(t.number(r, ret));
//
// A file that is being appended to by a running program may end in an unterminated line: that
// last line is ignored (see read_csv). Every defect is an InputError naming the file, the line
// and the column.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace codesign::io {

class CsvTable {
 public:
  CsvTable(std::string path, std::vector<std::string> columns, std::vector<std::vector<std::string>> cells);

  const std::string& path() const { return path_; }
  const std::vector<std::string>& columns() const { return columns_; }
  std::size_t rows() const { return cells_.size(); }
  bool has_column(const std::string& name) const;
  // Index of a column; throws InputError "PATH: no column 'name' (columns: a, b, ...)".
  std::size_t column(const std::string& name) const;
  const std::string& cell(std::size_t row, std::size_t col) const { return cells_.at(row).at(col); }
  // The cell as a finite number / an integer; throws InputError "PATH: line L, column 'c': 'x' is not
  // a (finite) number" (L counts from 1 and includes the header).
  double number(std::size_t row, std::size_t col) const;
  std::int64_t integer(std::size_t row, std::size_t col) const;
  // A whole column as numbers.
  std::vector<double> numbers(const std::string& name) const;

 private:
  std::string path_;
  std::vector<std::string> columns_;
  std::vector<std::vector<std::string>> cells_;
};

// Reads PATH. Throws InputError naming the file if it is missing or unreadable, has no header,
// an empty or repeated column name, or a row whose cell count differs from the header's (with its
// line number). A final line without its newline (a writer in progress) is dropped.
CsvTable read_csv(const std::string& path);

}  // namespace codesign::io
