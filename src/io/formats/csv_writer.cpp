#include "io/formats/csv_writer.hpp"

#include <cstdio>
#include <stdexcept>

namespace codesign::io {

CsvWriter::CsvWriter(std::string path, const std::vector<std::string>& columns)
    : path_(std::move(path)), tmp_(path_ + ".tmp"), columns_(columns.size()) {
  f_ = std::fopen(tmp_.c_str(), "w");
  if (!f_) throw std::runtime_error("cannot write " + tmp_);
  for (std::size_t i = 0; i < columns.size(); ++i) std::fprintf(f_, "%s%s", i ? "," : "", columns[i].c_str());
  std::fputc('\n', f_);
}

CsvWriter::~CsvWriter() {
  if (f_) {
    std::fclose(f_);
    std::remove(tmp_.c_str());
  }
}

void CsvWriter::row(const std::vector<double>& values) {
  if (values.size() != columns_) throw std::logic_error("CsvWriter: wrong number of fields");
  for (std::size_t i = 0; i < values.size(); ++i) std::fprintf(f_, "%s%.10g", i ? "," : "", values[i]);
  std::fputc('\n', f_);
}

void CsvWriter::row(const std::vector<double>& values, const std::string& text) {
  if (values.size() + 1 != columns_) throw std::logic_error("CsvWriter: wrong number of fields");
  for (std::size_t i = 0; i < values.size(); ++i) std::fprintf(f_, "%.10g,", values[i]);
  std::fprintf(f_, "%s\n", text.c_str());
}

void CsvWriter::close() {
  if (!f_) return;
  const bool ok = std::fflush(f_) == 0 && !std::ferror(f_);
  std::fclose(f_);
  f_ = nullptr;
  if (!ok || std::rename(tmp_.c_str(), path_.c_str()) != 0) {
    std::remove(tmp_.c_str());
    throw std::runtime_error("cannot write " + path_);
  }
}

}  // namespace codesign::io
