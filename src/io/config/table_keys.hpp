#pragma once
// Reading and writing a config table from its key descriptions (base/config_keys.hpp):
//
//   fem::Material m;                                   // the defaults to read over
//   io::read_keys(root, "material", [&](auto& v) { fem::describe_material_table(v, m); });
//   io::write_keys(out, "material", [&](auto& v) { fem::describe_material_table(v, m); });
//
// KeyReader fills each field from the table (a missing key keeps the field's value: the
// default), with TableReader's messages naming file, key and allowed range; read_keys then calls
// finish(), so a key the description does not name is an error. KeyWriter writes each key the
// resolved config carries (Key::written), in the order described, so that reading the text back
// gives the same values bit for bit (TomlTableWriter).
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "base/config_keys.hpp"
#include "base/enum_names.hpp"
#include "base/range.hpp"
#include "io/config/toml_writer.hpp"
#include "io/config/toml_reader.hpp"

namespace codesign::io {

class KeyReader {
 public:
  // Reader and reference page see what a file states (e.g. "auto"); writer and check the value
  // a struct holds.
  static constexpr bool kStructValues = false;

  explicit KeyReader(TableReader& t) : t_(t) {}

  void number(const config::Key& k, double& f, Range<double> r) {
    const bool a = applies(k);
    const double v = t_.number(k.name, f, r);
    if (a) f = v;
  }
  void scaled(const config::Key& k, double& f, double scale, Range<double> r) {
    const bool a = applies(k);
    const double x = t_.number(k.name, 0.0, r);
    if (a && t_.has(k.name)) f = scale * x;
  }
  void degrees(const config::Key& k, double& f_rad, Range<double> deg) {
    const bool a = applies(k);
    const double x = t_.number(k.name, 0.0, deg);
    if (a && t_.has(k.name)) f_rad = x * std::numbers::pi / 180.0;
  }
  template <class I>
  void integer(const config::Key& k, I& f, Range<std::int64_t> r) {
    const bool a = applies(k);
    const std::int64_t v = t_.integer(k.name, static_cast<std::int64_t>(f), r.lo, r.hi);
    if (a) f = static_cast<I>(v);
  }
  void boolean(const config::Key& k, bool& f) {
    const bool a = applies(k);
    const bool v = t_.boolean(k.name, f);
    if (a) f = v;
  }
  void text(const config::Key& k, std::string& f) {
    const bool a = applies(k);
    std::string v = t_.string(k.name, f);
    if (a) f = std::move(v);
  }
  template <class E, std::size_t N>
  void choice(const config::Key& k, E& f, const EnumNames<E, N>& names) {
    const bool a = applies(k);
    const E v = t_.choice(k.name, f, names);
    if (a) f = v;
  }
  void numbers(const config::Key& k, std::vector<double>& f, Range<double> each, Range<std::size_t> length) {
    const bool a = applies(k);
    std::vector<double> v = t_.numbers(k.name, f, each.lo, each.hi, length.lo, length.hi);
    if (a) f = std::move(v);
  }
  void grid(const config::Key& k, std::vector<double>& f, Range<double> each, Range<std::size_t> length) {
    const bool a = applies(k);
    std::vector<double> v = t_.grid(k.name, f, each.lo, each.hi, length.lo, length.hi);
    if (a) f = std::move(v);
  }
  void integers(const config::Key& k, std::vector<int>& f, Range<std::int64_t> each, Range<std::size_t> length) {
    const bool a = applies(k);
    const std::vector<std::int64_t> v =
        t_.integers(k.name, std::vector<std::int64_t>(f.begin(), f.end()), each.lo, each.hi, length.lo, length.hi);
    if (a) f.assign(v.begin(), v.end());
  }
  void optional_number(const config::Key& k, std::optional<double>& f, Range<double> r) {
    const bool a = applies(k);
    const double v = t_.number(k.name, 0.0, r);
    if (a && t_.has(k.name)) f = v;
  }
  void window(const config::Key& ks, const config::Key& ke, std::optional<std::int64_t>& start,
              std::optional<std::int64_t>& end, Range<std::int64_t> r);
  template <class Message>
  void require(bool holds, std::string_view key, Message message) {
    if (!holds) t_.fail(key, message());
  }

 private:
  // False for a key that does not apply here, after failing if the table gives it anyway.
  bool applies(const config::Key& k) {
    if (!k.applies && t_.has(k.name))
      t_.fail(k.name, "applies only with " + std::string(k.applies_with) + "; " + std::string(k.fix));
    return k.applies;
  }
  TableReader& t_;
};

class KeyWriter {
 public:
  static constexpr bool kStructValues = true;

  explicit KeyWriter(TomlTableWriter& w) : w_(w) {}

  void number(const config::Key& k, double& f, Range<double>) {
    if (writes(k)) w_.number(k.name, f);
  }
  void scaled(const config::Key& k, double& f, double scale, Range<double>) {
    if (writes(k)) w_.scaled(k.name, f, scale);
  }
  void degrees(const config::Key& k, double& f_rad, Range<double>) {
    if (writes(k)) w_.degrees(k.name, f_rad);
  }
  template <class I>
  void integer(const config::Key& k, I& f, Range<std::int64_t>) {
    if (writes(k)) w_.integer(k.name, static_cast<std::int64_t>(f));
  }
  void boolean(const config::Key& k, bool& f) {
    if (writes(k)) w_.boolean(k.name, f);
  }
  void text(const config::Key& k, std::string& f) {
    if (writes(k)) w_.string(k.name, f);
  }
  template <class E, std::size_t N>
  void choice(const config::Key& k, E& f, const EnumNames<E, N>& names) {
    if (writes(k)) w_.string(k.name, name_of(names, f));
  }
  void numbers(const config::Key& k, std::vector<double>& f, Range<double>, Range<std::size_t>) {
    if (writes(k)) w_.numbers(k.name, f);
  }
  void grid(const config::Key& k, std::vector<double>& f, Range<double>, Range<std::size_t>) {
    if (writes(k)) w_.numbers(k.name, f);
  }
  void integers(const config::Key& k, std::vector<int>& f, Range<std::int64_t>, Range<std::size_t>) {
    if (writes(k)) w_.integers(k.name, f);
  }
  void optional_number(const config::Key& k, std::optional<double>& f, Range<double>) {
    if (f && writes(k)) w_.number(k.name, *f);
  }
  void window(const config::Key& ks, const config::Key& ke, std::optional<std::int64_t>& start,
              std::optional<std::int64_t>& end, Range<std::int64_t>) {
    if (!start || !end || !writes(ks)) return;
    w_.integer(ks.name, *start);
    w_.integer(ke.name, *end);
  }
  template <class Message>
  void require(bool, std::string_view, Message) {}

 private:
  static bool writes(const config::Key& k) {
    if (!k.applies) return false;
    switch (k.written) {
      case config::Written::Always:
      case config::Written::WhenSet: return true;
      case config::Written::UnlessDefault: return !k.at_default;
      case config::Written::Never: return false;
    }
    return true;
  }
  TomlTableWriter& w_;
};

// Reads table `name` of root with `describe(KeyReader&)`, then finish() on it.
template <class Describe>
void read_keys(TableReader& root, std::string_view name, Describe&& describe) {
  TableReader t = root.table(name);
  KeyReader r(t);
  describe(r);
  t.finish();
}

// Writes table `name` with `describe(KeyWriter&)`.
template <class Describe>
void write_keys(std::ostream& out, std::string_view name, Describe&& describe) {
  TomlTableWriter t(out, name);
  KeyWriter w(t);
  describe(w);
}

}  // namespace codesign::io
