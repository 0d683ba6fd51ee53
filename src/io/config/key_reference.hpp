#pragma once
// The config-keys reference, printed from the key descriptions (base/config_keys.hpp): one row
// per key with its type, default, allowed values, unit and meaning, as docs/config_reference.md
// shows them.
//
//   std::vector<io::KeyRow> rows = io::key_rows([&](auto& v) { fem::describe_material_table(v, m); });
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "base/config_check.hpp"
#include "base/config_keys.hpp"
#include "base/enum_names.hpp"
#include "base/range.hpp"
#include "io/config/toml_writer.hpp"

namespace codesign::io {

struct KeyRow {
  std::string name, type, default_value, allowed, unit, meaning;
  config::Written written = config::Written::Always;
  std::string applies_with;  // "" when the key always applies
};

class KeyDoc {
 public:
  // Shows what a file states (matmul_precision "auto"), as the reader sees it.
  static constexpr bool kStructValues = false;

  void number(const config::Key& k, double& f, Range<double> r) { row(k, "float", toml_number(f), range(k, r)); }
  void scaled(const config::Key& k, double& f, double scale, Range<double> r) {
    row(k, "float", toml_number(f / scale), range(k, r));
  }
  void degrees(const config::Key& k, double& f_rad, Range<double> deg) {
    row(k, "float", toml_number(f_rad * 180.0 / std::numbers::pi), range(k, deg));
  }
  template <class I>
  void integer(const config::Key& k, I& f, Range<std::int64_t> r) {
    row(k, "integer", std::to_string(f), range(k, r));
  }
  void boolean(const config::Key& k, bool& f) { row(k, "boolean", f ? "true" : "false", "true, false"); }
  void text(const config::Key& k, std::string& f) { row(k, "string", "\"" + f + "\"", "any"); }
  template <class E, std::size_t N>
  void choice(const config::Key& k, E& f, const EnumNames<E, N>& names) {
    std::string allowed;
    for (const auto& n : names) allowed += (allowed.empty() ? "\"" : ", \"") + std::string(n.name) + "\"";
    row(k, "string", "\"" + std::string(name_of(names, f)) + "\"", allowed);
  }
  void numbers(const config::Key& k, std::vector<double>& f, Range<double> each, Range<std::size_t> length) {
    std::string d = "[";
    for (std::size_t i = 0; i < f.size(); ++i) d += (i ? ", " : "") + toml_number(f[i]);
    row(k, "array of floats", d + "]", k.range_note.empty() ? lengths(length) + ", each in " + config::range_text(each) : "");
  }
  void grid(const config::Key& k, std::vector<double>& f, Range<double> each, Range<std::size_t> length) {
    std::string d = "[";
    for (std::size_t i = 0; i < f.size(); ++i) d += (i ? ", " : "") + toml_number(f[i]);
    row(k, "array of floats or {from, to, step}", d + "]",
        k.range_note.empty() ? lengths(length) + ", each in " + config::range_text(each) : "");
  }
  void integers(const config::Key& k, std::vector<int>& f, Range<std::int64_t> each, Range<std::size_t> length) {
    std::string d = "[";
    for (std::size_t i = 0; i < f.size(); ++i) d += (i ? ", " : "") + std::to_string(f[i]);
    row(k, "array of integers", d + "]", k.range_note.empty() ? lengths(length) + ", each in " + config::range_text(each) : "");
  }
  void optional_number(const config::Key& k, std::optional<double>& f, Range<double> r) {
    row(k, "float", f ? toml_number(*f) : "unset", range(k, r));
  }
  void window(const config::Key& ks, const config::Key& ke, std::optional<std::int64_t>& start,
              std::optional<std::int64_t>& end, Range<std::int64_t> r) {
    row(ks, "integer", start ? std::to_string(*start) : "unset", range(ks, r) + ", below " + std::string(ke.name));
    row(ke, "integer", end ? std::to_string(*end) : "unset", range(ke, r) + ", above " + std::string(ks.name));
  }
  template <class Message>
  void require(bool, std::string_view, Message) {}

  const std::vector<KeyRow>& rows() const { return rows_; }

 private:
  template <class T>
  static std::string range(const config::Key& k, Range<T> r) {
    return k.range_note.empty() ? config::range_text(r) : std::string(k.range_note);
  }
  static std::string lengths(Range<std::size_t> n) {
    return n.lo == n.hi ? std::to_string(n.lo) + " elements" : std::to_string(n.lo) + " to " + std::to_string(n.hi) + " elements";
  }
  void row(const config::Key& k, std::string type, std::string def, std::string allowed) {
    if (allowed.empty()) allowed = k.range_note;
    rows_.push_back({std::string(k.name), std::move(type), std::move(def), std::move(allowed), std::string(k.unit),
                     std::string(k.meaning), k.written, std::string(k.applies_with)});
  }
  std::vector<KeyRow> rows_;
};

template <class Describe>
std::vector<KeyRow> key_rows(Describe&& describe) {
  KeyDoc doc;
  describe(doc);
  return doc.rows();
}

}  // namespace codesign::io
