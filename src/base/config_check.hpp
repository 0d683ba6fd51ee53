#pragma once
// Checking values built in code against their key descriptions (base/config_keys.hpp): the
// same ranges and rules the config reader applies to a file.
//
//   rl::PpoConfig c = ...;
//   if (auto p = config::first_problem([&](auto& v) { rl::describe_ppo_table(v, c); }))
//     throw std::invalid_argument("PpoConfig: " + *p);
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "base/config_keys.hpp"
#include "base/enum_names.hpp"
#include "base/range.hpp"

namespace codesign::config {

// "[lo, hi]" as the messages print a range.
template <class T>
std::string range_text(Range<T> r) {
  std::ostringstream os;
  os << '[' << r.lo << ", " << r.hi << ']';
  return os.str();
}

// Records the first value outside its range or rule broken ("key: value 2 is out of range;
// allowed [0, 1]"). Keys that do not apply are not checked.
class KeyCheck {
 public:
  static constexpr bool kStructValues = true;

  void number(const Key& k, double& f, Range<double> r) { in_range(k, f, r); }
  void scaled(const Key& k, double& f, double scale, Range<double> r) { in_range(k, f / scale, r); }
  void degrees(const Key& k, double& f_rad, Range<double> deg) { in_range(k, f_rad * 180.0 / std::numbers::pi, deg); }
  template <class I>
  void integer(const Key& k, I& f, Range<std::int64_t> r) {
    if (k.applies && !r.contains(static_cast<std::int64_t>(f)))
      problem(k.name, "value " + std::to_string(f) + " is out of range; allowed " + range_text(r));
  }
  void boolean(const Key&, bool&) {}
  void text(const Key&, std::string&) {}
  template <class E, std::size_t N>
  void choice(const Key& k, E& f, const EnumNames<E, N>& names) {
    if (k.applies && !value_of(names, name_of(names, f))) problem(k.name, "not one of " + names_list(names));
  }
  void numbers(const Key& k, std::vector<double>& f, Range<double> each, Range<std::size_t> length) {
    sized(k, f.size(), length);
    for (double x : f) in_range(k, x, each);
  }
  void grid(const Key& k, std::vector<double>& f, Range<double> each, Range<std::size_t> length) {
    numbers(k, f, each, length);
  }
  void integers(const Key& k, std::vector<int>& f, Range<std::int64_t> each, Range<std::size_t> length) {
    sized(k, f.size(), length);
    for (int x : f) integer(k, x, each);
  }
  void optional_number(const Key& k, std::optional<double>& f, Range<double> r) {
    if (f) in_range(k, *f, r);
  }
  void window(const Key& ks, const Key& ke, std::optional<std::int64_t>& start, std::optional<std::int64_t>& end,
              Range<std::int64_t> r) {
    if (start.has_value() != end.has_value())
      problem(ks.name, std::string(ks.name) + " and " + std::string(ke.name) + " must be given together");
    if (!start || !end) return;
    integer(ks, *start, r);
    integer(ke, *end, r);
    if (!(*end > *start)) problem(ke.name, "must be greater than " + std::string(ks.name) + " (" + std::to_string(*start) + ")");
  }
  template <class Message>
  void require(bool holds, std::string_view key, Message message) {
    if (!holds) problem(key, message());
  }

  const std::optional<std::string>& first() const { return first_; }

 private:
  void in_range(const Key& k, double v, Range<double> r) {
    if (!k.applies || (std::isfinite(v) && r.contains(v))) return;
    std::ostringstream os;
    os << "value " << v << " is out of range; allowed " << range_text(r);
    problem(k.name, os.str());
  }
  void sized(const Key& k, std::size_t n, Range<std::size_t> length) {
    if (k.applies && !length.contains(n))
      problem(k.name, std::to_string(n) + " elements; allowed " + range_text(length));
  }
  void problem(std::string_view key, const std::string& what) {
    if (!first_) first_ = std::string(key) + ": " + what;
  }
  std::optional<std::string> first_;
};

// The first problem of the values a description visits, or nullopt when there is none.
template <class Describe>
std::optional<std::string> first_problem(Describe&& describe) {
  KeyCheck check;
  describe(check);
  return check.first();
}

}  // namespace codesign::config
