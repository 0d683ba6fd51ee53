#pragma once
// An append-only CSV file for the logs of a long run that can be resumed after a crash.
//
// Rows are written as they come; flush() pushes them to the operating system and returns the
// file's length in bytes. A checkpoint stores that length; resuming opens the file at it
// (truncating rows written after the checkpoint), so the log continues exactly where the
// checkpointed state left it. Numbers are written with 17 significant digits (%.17g: a double
// reads back bit-identical), or as given when already formatted.
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace codesign::io {

class CsvLog {
 public:
  // resume_at empty: creates (or replaces) the file and writes the header row. Otherwise the
  // file must exist with at least resume_at bytes, starting with this header; it is cut to
  // resume_at bytes and appended to. Throws codesign::InputError naming the file otherwise.
  CsvLog(std::string path, const std::vector<std::string>& columns,
         std::optional<std::uint64_t> resume_at = std::nullopt);
  ~CsvLog();
  // The checks of a resume (file exists with at least resume_at bytes and this header), without
  // changing the file: throws the constructor's InputError.
  static void check_resumable(const std::string& path, const std::vector<std::string>& columns,
                              std::uint64_t resume_at);
  CsvLog(const CsvLog&) = delete;
  CsvLog& operator=(const CsvLog&) = delete;

  // One row of already formatted cells (must match the column count; a cell must not contain
  // a comma, quote or newline: checked).
  void row(const std::vector<std::string>& cells);
  std::uint64_t flush();
  const std::string& path() const { return path_; }

  static std::string num(double v);           // %.17g
  static std::string num(std::int64_t v);

 private:
  std::string path_;
  std::FILE* f_ = nullptr;
  std::size_t columns_ = 0;
};

}  // namespace codesign::io
