#pragma once
// Writing TOML tables: "key = value" lines whose numbers read back as the same doubles. Used by
// the key writer (table_keys.hpp) for the resolved config.toml.
#include <cstdint>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace codesign::io {

// One TOML table, "key = value" per line, in the order written; the header at construction,
// a blank line at destruction. Keys and strings are written as given (no escaping: the config
// keys and their string values are plain identifiers).
class TomlTableWriter {
 public:
  TomlTableWriter(std::ostream& out, std::string_view table);
  ~TomlTableWriter();
  TomlTableWriter(const TomlTableWriter&) = delete;
  TomlTableWriter& operator=(const TomlTableWriter&) = delete;

  void number(std::string_view key, double v);
  void integer(std::string_view key, std::int64_t v);
  void boolean(std::string_view key, bool v);
  void string(std::string_view key, std::string_view v);
  void integers(std::string_view key, const std::vector<int>& v);
  void numbers(std::string_view key, const std::vector<double>& v);
  // For a reader that stores `scale * x` (e.g. 1e3 * kPa): writes the x, nearest stored / scale,
  // with scale * x == stored exactly (scale > 0). Every value such a reader produced has one.
  void scaled(std::string_view key, double stored, double scale);
  // For a reader that stores `x * pi / 180.0` (a key in degrees read into radians): the same.
  void degrees(std::string_view key, double stored_rad);

 private:
  std::ostream& out_;
};

// A double as a TOML float, in the shortest form that reads back bit-identical ("0.3", "1e-05",
// "500.0"; always with '.' or an exponent so TOML parses a float).
std::string toml_number(double v);

}  // namespace codesign::io
