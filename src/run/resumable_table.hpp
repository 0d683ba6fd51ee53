#pragma once
// A results table that a stopped command continues where it was: `codesign evaluate`'s
// designs.csv and `codesign verify`'s conditions.csv, each with a stamp file beside it that says
// what the table is of (the state, the settings).
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "base/errors.hpp"
#include "io/formats/atomic_file.hpp"

namespace codesign::run {

// When `csv` exists under the same stamp (and not `force`): the rows `read` finds in it, with a
// half-written last line cut afterwards so that appends start on a fresh line. When the folder
// holds a table under another stamp and not `force`: InputError "FOLDER: holds WHAT with other
// settings (STAMP_PATH); pass --force to replace it", nothing changed. Otherwise, or when no row
// was kept: a new stamp file and a csv of `header` alone, and no rows.
template <class Row, class Read>
std::vector<Row> open_resumable_table(const std::filesystem::path& folder, const std::filesystem::path& stamp_path,
                                      const std::filesystem::path& csv, const std::string& stamp,
                                      const std::string& header, bool force, const std::string& what, Read read) {
  const auto text_of = [](const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  };
  std::vector<Row> rows;
  std::error_code ec;
  if (std::filesystem::exists(csv, ec)) {
    if (text_of(stamp_path) == stamp && !force) {
      rows = read(csv);
      std::filesystem::resize_file(csv, text_of(csv).rfind('\n') + 1);
    } else if (!force) {
      throw InputError(folder.string() + ": holds " + what + " with other settings (" + stamp_path.string() +
                       "); pass --force to replace it");
    }
  }
  if (rows.empty()) {
    io::write_file_atomically(stamp_path.string(), [&](std::ostream& out) { out << stamp; });
    io::write_file_atomically(csv.string(), [&](std::ostream& out) { out << header << '\n'; });
  }
  return rows;
}

}  // namespace codesign::run
