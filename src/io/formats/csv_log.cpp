#include "io/formats/csv_log.hpp"

#include <cerrno>
#include <filesystem>
#include <stdexcept>

#include <unistd.h>

#include "base/errors.hpp"
#include "base/file_write.hpp"

namespace codesign::io {

namespace {

std::string join(const std::vector<std::string>& cells) {
  std::string line;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (i) line += ',';
    line += cells[i];
  }
  line += '\n';
  return line;
}

}  // namespace

CsvLog::CsvLog(std::string path, const std::vector<std::string>& columns, std::optional<std::uint64_t> resume_at)
    : path_(std::move(path)), columns_(columns.size()) {
  const std::string header = join(columns);
  if (!resume_at) {
    f_ = std::fopen(path_.c_str(), "wb");
    if (!f_) throw FileError(file_error_text(path_, "cannot create log file", errno));
    if (std::fputs(header.c_str(), f_) < 0) throw FileError(file_error_text(path_, "cannot write", errno));
    return;
  }
  check_resumable(path_, columns, *resume_at);
  f_ = std::fopen(path_.c_str(), "r+b");
  if (!f_) throw FileError(file_error_text(path_, "cannot open log file to resume", errno));
  if (::ftruncate(::fileno(f_), static_cast<off_t>(*resume_at)) != 0 ||
      std::fseek(f_, static_cast<long>(*resume_at), SEEK_SET) != 0) {
    std::fclose(f_);
    f_ = nullptr;
    throw InputError(path_ + ": cannot cut log file back to the checkpoint");
  }
}

void CsvLog::check_resumable(const std::string& path, const std::vector<std::string>& columns,
                             std::uint64_t resume_at) {
  const std::string header = join(columns);
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(path + ": log file to resume is missing (" + ec.message() + ")");
  if (size < resume_at || resume_at < header.size())
    throw InputError(path + ": log file has " + std::to_string(size) + " bytes, the checkpoint expects at least " +
                     std::to_string(resume_at) + "; the run folder does not belong to this checkpoint");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw InputError(path + ": cannot open log file to resume");
  std::string head(header.size(), '\0');
  const bool same = std::fread(head.data(), 1, head.size(), f) == head.size() && head == header;
  std::fclose(f);
  if (!same) throw InputError(path + ": log file header differs from this version's columns");
}

CsvLog::~CsvLog() {
  if (f_) std::fclose(f_);
}

void CsvLog::row(const std::vector<std::string>& cells) {
  if (cells.size() != columns_)
    throw std::logic_error(path_ + ": row has " + std::to_string(cells.size()) + " cells, expected " +
                           std::to_string(columns_));
  for (const std::string& c : cells)
    if (c.find_first_of(",\"\n") != std::string::npos) throw std::logic_error(path_ + ": cell needs quoting: " + c);
  // A failed write may leave part of a row at the end; a resume cuts the log back to its
  // checkpointed length, so only rows after the last checkpoint are at stake.
  if (std::fputs(join(cells).c_str(), f_) < 0) throw FileError(file_error_text(path_, "cannot write", errno));
}

std::uint64_t CsvLog::flush() {
  if (std::fflush(f_) != 0) throw FileError(file_error_text(path_, "cannot write", errno));
  const long pos = std::ftell(f_);
  if (pos < 0) throw std::runtime_error(path_ + ": ftell failed");
  return static_cast<std::uint64_t>(pos);
}

std::string CsvLog::num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string CsvLog::num(std::int64_t v) { return std::to_string(v); }

}  // namespace codesign::io
