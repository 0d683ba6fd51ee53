#pragma once
// A small CSV writer with atomic finalisation: rows go to "<path>.tmp", and close() renames it
// onto <path>, so a reader never sees a half-written file under the final name and an earlier
// file is only replaced by a complete one. Numbers are written with 10 significant digits.
#include <cstdio>
#include <string>
#include <vector>

namespace codesign::io {

class CsvWriter {
 public:
  // Opens "<path>.tmp" and writes the header; throws std::runtime_error if it cannot.
  CsvWriter(std::string path, const std::vector<std::string>& columns);
  ~CsvWriter();  // without close(): removes the temporary file, leaves <path> untouched
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;

  // One row; fields are numbers, except a trailing free-text field allowed via row(…, text).
  void row(const std::vector<double>& values);
  void row(const std::vector<double>& values, const std::string& text);
  // Flushes, closes and renames onto the final path; throws std::runtime_error on failure.
  void close();
  const std::string& path() const { return path_; }

 private:
  std::string path_, tmp_;
  std::FILE* f_ = nullptr;
  std::size_t columns_ = 0;
};

}  // namespace codesign::io
