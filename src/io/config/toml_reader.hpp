#pragma once
// Typed, validated reading of TOML tables into config structs.
//
// Every getter takes the default and the allowed range; a missing key yields the default, a
// present key of the wrong type or out of range throws InputError naming file, key and range.
// finish() throws for any key of the table that nobody read (a typo must not pass silently).
//
//   io::TableReader root = io::TableReader::from_file("run.toml");
//   io::TableReader mat = root.table("material");
//   cfg.youngs_modulus_kpa = mat.number("youngs_modulus_kPa", 500.0, 1.0, 1e5);
//   mat.finish();
//   root.finish();
#include <array>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "base/enum_names.hpp"
#include "base/errors.hpp"
#include "base/range.hpp"

namespace toml {
inline namespace v3 {
class table;
}
}  // namespace toml

namespace codesign::io {

class TableReader {
 public:
  // Parses a TOML file; a missing file or a syntax error throws InputError with the position.
  // A root key `extends = "base.toml"` (path relative to the file's folder) reads that file
  // first and lays this one over it: tables merge key by key, other values and arrays replace.
  // Chains are allowed (up to 8 files, no cycles). Messages name the file that states a value.
  static TableReader from_file(const std::string& path);
  // The text to keep as a record of the input: the file itself, or, when it extends others, a
  // comment naming the chain followed by the merged TOML.
  static std::string input_text(const std::string& path);
  // Files merged in through `extends`, nearest first (empty for a self-contained file).
  const std::vector<std::string>& bases() const;
  // Parses TOML text; `file_label` stands in for the file name in messages (used by tests).
  static TableReader from_string(std::string_view text, std::string file_label);

  // Optional scalars: default when absent. Ranges are inclusive.
  double number(std::string_view key, double def, double lo, double hi);
  std::int64_t integer(std::string_view key, std::int64_t def, std::int64_t lo, std::int64_t hi);
  // The same with the range stated once next to the config struct (base/range.hpp).
  double number(std::string_view key, double def, Range<double> r) {
    return number(key, def, r.lo, r.hi);
  }
  template <class I>
  std::int64_t integer(std::string_view key, std::int64_t def, Range<I> r) {
    return integer(key, def, r.lo, r.hi);
  }
  bool boolean(std::string_view key, bool def);
  // `allowed` empty: any string.
  std::string string(std::string_view key, std::string def,
                     std::initializer_list<std::string_view> allowed = {}) {
    return string(key, std::move(def), std::span<const std::string_view>(allowed.begin(), allowed.size()));
  }
  std::string string(std::string_view key, std::string def, std::span<const std::string_view> allowed);
  // A key naming one value of an enum by its string table (base/enum_names.hpp); def when absent.
  template <class E, std::size_t N>
  E choice(std::string_view key, E def, const EnumNames<E, N>& names) {
    const std::array<std::string_view, N> allowed = names_in(names);
    return *value_of(names, string(key, std::string(name_of(names, def)), allowed));
  }
  // Arrays of numbers / integers, every element in [lo, hi], length in [min_len, max_len].
  std::vector<double> numbers(std::string_view key, std::vector<double> def, double lo, double hi,
                              std::size_t min_len, std::size_t max_len);
  // An array as numbers() reads it, or a table {from, to, step} giving grid_values(from, to, step)
  // (base/grid_values.hpp); the same checks of each value and of the length.
  std::vector<double> grid(std::string_view key, std::vector<double> def, double lo, double hi, std::size_t min_len,
                           std::size_t max_len);
  std::vector<std::int64_t> integers(std::string_view key, std::vector<std::int64_t> def,
                                     std::int64_t lo, std::int64_t hi, std::size_t min_len,
                                     std::size_t max_len);

  // Required scalars: absent key throws.
  double required_number(std::string_view key, double lo, double hi);
  std::string required_string(std::string_view key);

  bool has(std::string_view key) const;
  // A sub-table; absent gives an empty table (so every getter returns its default).
  TableReader table(std::string_view key);
  // Throws InputError if a key of this table was never read, listing the keys that are allowed.
  void finish() const;

  const std::string& file() const;
  // Dotted path of this table ("" for the root), e.g. "fem.material".
  const std::string& path() const { return path_; }
  // "file: key" prefix used in messages, e.g. "run.toml: material.youngs_modulus_kPa".
  std::string where(std::string_view key) const;
  [[noreturn]] void fail(std::string_view key, std::string_view problem) const;

 private:
  struct State;
  TableReader(std::shared_ptr<State> state, const toml::table* table, std::string path);
  const void* lookup(std::string_view key);
  std::shared_ptr<State> state_;
  const toml::table* table_;  // nullptr: absent table
  std::string path_;
  std::shared_ptr<std::vector<std::string>> read_keys_;
};

}  // namespace codesign::io
