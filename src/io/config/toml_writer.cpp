#include "io/config/toml_writer.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <numbers>

namespace codesign::io {

namespace {

std::string shortest(double v) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

// An x with read(x) == stored for a nondecreasing read(), searched from `guess` in steps of
// one ulp (at most 64); of the neighbours that also map onto `stored` (64 either side) the one
// with the shortest decimal form, so a value written as 37.3 is written back as 37.3.
// `guess` itself if there is none.
template <class Read>
double preimage(double stored, double guess, Read read) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  double x = guess;
  for (int i = 0; i < 64 && std::isfinite(x) && read(x) != stored; ++i)
    x = std::nextafter(x, read(x) < stored ? inf : -inf);
  if (!std::isfinite(x) || read(x) != stored) return guess;
  double best = x;
  for (const double dir : {-inf, inf}) {
    double y = std::nextafter(x, dir);
    for (int k = 0; k < 64 && std::isfinite(y) && read(y) == stored; ++k, y = std::nextafter(y, dir))
      if (shortest(y).size() < shortest(best).size()) best = y;
  }
  return best;
}

}  // namespace

std::string toml_number(double v) {
  std::string s = shortest(v);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // "500" would be an integer
  return s;
}

TomlTableWriter::TomlTableWriter(std::ostream& out, std::string_view table) : out_(out) {
  out_ << '[' << table << "]\n";
}

TomlTableWriter::~TomlTableWriter() { out_ << '\n'; }

void TomlTableWriter::number(std::string_view key, double v) { out_ << key << " = " << toml_number(v) << '\n'; }

void TomlTableWriter::integer(std::string_view key, std::int64_t v) { out_ << key << " = " << v << '\n'; }

void TomlTableWriter::boolean(std::string_view key, bool v) {
  out_ << key << " = " << (v ? "true" : "false") << '\n';
}

void TomlTableWriter::string(std::string_view key, std::string_view v) {
  out_ << key << " = \"" << v << "\"\n";
}

void TomlTableWriter::integers(std::string_view key, const std::vector<int>& v) {
  out_ << key << " = [";
  for (std::size_t i = 0; i < v.size(); ++i) out_ << (i ? ", " : "") << v[i];
  out_ << "]\n";
}

void TomlTableWriter::numbers(std::string_view key, const std::vector<double>& v) {
  out_ << key << " = [";
  for (std::size_t i = 0; i < v.size(); ++i) out_ << (i ? ", " : "") << toml_number(v[i]);
  out_ << "]\n";
}

void TomlTableWriter::scaled(std::string_view key, double stored, double scale) {
  number(key, preimage(stored, stored / scale, [scale](double x) { return scale * x; }));
}

void TomlTableWriter::degrees(std::string_view key, double stored_rad) {
  // The readers' expression, evaluated in the same order: t.number(...) * pi / 180.0.
  number(key, preimage(stored_rad, stored_rad * 180.0 / std::numbers::pi,
                       [](double x) { return x * std::numbers::pi / 180.0; }));
}

}  // namespace codesign::io
