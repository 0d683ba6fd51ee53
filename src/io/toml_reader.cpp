#include "io/toml_reader.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <toml++/toml.h>

namespace codesign::io {

struct TableReader::State {
  std::string file;
  toml::table root;
};

namespace {

std::string format_number(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

std::string range_text(double lo, double hi) {
  std::ostringstream os;
  os << '[' << lo << ", " << hi << ']';
  return os.str();
}

std::string range_text(std::int64_t lo, std::int64_t hi) {
  std::ostringstream os;
  os << '[' << lo << ", " << hi << ']';
  return os.str();
}

std::string type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a number";
    case toml::node_type::boolean: return "a boolean";
    default: return "a date/time";
  }
}

std::string parse_error_text(const std::string& file, const toml::parse_error& e) {
  std::ostringstream os;
  os << file << ":" << e.source().begin.line << ":" << e.source().begin.column
     << ": invalid TOML: " << e.description();
  return os.str();
}

}  // namespace

TableReader::TableReader(std::shared_ptr<State> state, const toml::table* table, std::string path)
    : state_(std::move(state)),
      table_(table),
      path_(std::move(path)),
      read_keys_(std::make_shared<std::vector<std::string>>()) {}

TableReader TableReader::from_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError(path + ": cannot read config file: it is a directory; give a TOML file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open config file");
  std::stringstream ss;
  ss << in.rdbuf();
  return from_string(ss.str(), path);
}

TableReader TableReader::from_string(std::string_view text, std::string file_label) {
  auto state = std::make_shared<State>();
  state->file = std::move(file_label);
  try {
    state->root = toml::parse(text, state->file);
  } catch (const toml::parse_error& e) {
    throw InputError(parse_error_text(state->file, e));
  }
  const toml::table* root = &state->root;
  return TableReader(std::move(state), root, "");
}

std::string TableReader::where(std::string_view key) const {
  std::string full = path_.empty() ? std::string(key) : path_ + "." + std::string(key);
  return state_->file + ": " + full;
}

void TableReader::fail(std::string_view key, std::string_view problem) const {
  throw InputError(where(key) + ": " + std::string(problem));
}

const void* TableReader::lookup(std::string_view key) {
  read_keys_->emplace_back(key);
  if (table_ == nullptr) return nullptr;
  return table_->get(key);
}

bool TableReader::has(std::string_view key) const {
  return table_ != nullptr && table_->get(key) != nullptr;
}

double TableReader::number(std::string_view key, double def, double lo, double hi) {
  const auto* node = static_cast<const toml::node*>(lookup(key));
  if (node == nullptr) return def;
  double v = 0.0;
  if (auto i = node->value_exact<std::int64_t>()) {
    v = static_cast<double>(*i);
  } else if (auto d = node->value_exact<double>()) {
    v = *d;
  } else {
    fail(key, "expected a number in " + range_text(lo, hi) + ", got " + type_name(*node));
  }
  if (!std::isfinite(v) || v < lo || v > hi) {
    fail(key, "value " + format_number(v) + " is out of range; allowed " + range_text(lo, hi));
  }
  return v;
}

std::int64_t TableReader::integer(std::string_view key, std::int64_t def, std::int64_t lo,
                                  std::int64_t hi) {
  const auto* node = static_cast<const toml::node*>(lookup(key));
  if (node == nullptr) return def;
  auto i = node->value_exact<std::int64_t>();
  const std::string range = range_text(lo, hi);
  if (!i) fail(key, "expected an integer in " + range + ", got " + type_name(*node));
  if (*i < lo || *i > hi) {
    fail(key, "value " + std::to_string(*i) + " is out of range; allowed " + range);
  }
  return *i;
}

bool TableReader::boolean(std::string_view key, bool def) {
  const auto* node = static_cast<const toml::node*>(lookup(key));
  if (node == nullptr) return def;
  auto b = node->value_exact<bool>();
  if (!b) fail(key, "expected true or false, got " + type_name(*node));
  return *b;
}

std::string TableReader::string(std::string_view key, std::string def,
                                std::initializer_list<std::string_view> allowed) {
  const auto* node = static_cast<const toml::node*>(lookup(key));
  std::string allowed_text;
  for (auto a : allowed) allowed_text += (allowed_text.empty() ? "\"" : ", \"") + std::string(a) + "\"";
  if (node == nullptr) return def;
  auto s = node->value_exact<std::string>();
  if (!s) {
    fail(key, "expected a string" + (allowed_text.empty() ? "" : " (one of " + allowed_text + ")") +
                  ", got " + type_name(*node));
  }
  if (allowed.size() > 0 &&
      std::none_of(allowed.begin(), allowed.end(), [&](std::string_view a) { return a == *s; })) {
    fail(key, "value \"" + *s + "\" is not allowed; allowed: " + allowed_text);
  }
  return *s;
}

std::vector<double> TableReader::numbers(std::string_view key, std::vector<double> def, double lo,
                                         double hi, std::size_t min_len, std::size_t max_len) {
  const auto* node = static_cast<const toml::node*>(lookup(key));
  if (node == nullptr) return def;
  const std::string shape = "an array of " + std::to_string(min_len) + " to " +
                            std::to_string(max_len) + " numbers in " + range_text(lo, hi);
  const auto* arr = node->as_array();
  if (arr == nullptr) fail(key, "expected " + shape + ", got " + type_name(*node));
  if (arr->size() < min_len || arr->size() > max_len) {
    fail(key, "expected " + shape + ", got " + std::to_string(arr->size()) + " elements");
  }
  std::vector<double> out;
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const toml::node& el = *arr->get(i);
    double v = 0.0;
    if (auto n = el.value_exact<std::int64_t>()) {
      v = static_cast<double>(*n);
    } else if (auto d = el.value_exact<double>()) {
      v = *d;
    } else {
      fail(key, "element " + std::to_string(i) + ": expected a number, got " + type_name(el));
    }
    if (!std::isfinite(v) || v < lo || v > hi) {
      fail(key, "element " + std::to_string(i) + " = " + format_number(v) +
                    " is out of range; allowed " + range_text(lo, hi));
    }
    out.push_back(v);
  }
  return out;
}

std::vector<std::int64_t> TableReader::integers(std::string_view key,
                                                std::vector<std::int64_t> def, std::int64_t lo,
                                                std::int64_t hi, std::size_t min_len,
                                                std::size_t max_len) {
  const auto* node = static_cast<const toml::node*>(lookup(key));
  if (node == nullptr) return def;
  const std::string range = range_text(lo, hi);
  const std::string shape = "an array of " + std::to_string(min_len) + " to " +
                            std::to_string(max_len) + " integers in " + range;
  const auto* arr = node->as_array();
  if (arr == nullptr) fail(key, "expected " + shape + ", got " + type_name(*node));
  if (arr->size() < min_len || arr->size() > max_len) {
    fail(key, "expected " + shape + ", got " + std::to_string(arr->size()) + " elements");
  }
  std::vector<std::int64_t> out;
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const toml::node& el = *arr->get(i);
    auto n = el.value_exact<std::int64_t>();
    if (!n) fail(key, "element " + std::to_string(i) + ": expected an integer, got " + type_name(el));
    if (*n < lo || *n > hi) {
      fail(key, "element " + std::to_string(i) + " = " + std::to_string(*n) +
                    " is out of range; allowed " + range);
    }
    out.push_back(*n);
  }
  return out;
}

double TableReader::required_number(std::string_view key, double lo, double hi) {
  if (!has(key)) fail(key, "missing; a number in " + range_text(lo, hi) + " is required");
  return number(key, 0.0, lo, hi);
}

std::string TableReader::required_string(std::string_view key) {
  if (!has(key)) fail(key, "missing; a string is required");
  return string(key, "");
}

TableReader TableReader::table(std::string_view key) {
  const auto* node = static_cast<const toml::node*>(lookup(key));
  std::string sub_path = path_.empty() ? std::string(key) : path_ + "." + std::string(key);
  if (node == nullptr) return TableReader(state_, nullptr, sub_path);
  const auto* t = node->as_table();
  if (t == nullptr) fail(key, "expected a table, got " + type_name(*node));
  return TableReader(state_, t, sub_path);
}

void TableReader::finish() const {
  if (table_ == nullptr) return;
  for (const auto& [k, v] : *table_) {
    const std::string_view name = k.str();
    const bool known = std::find(read_keys_->begin(), read_keys_->end(), name) != read_keys_->end();
    if (!known) {
      std::vector<std::string> sorted = *read_keys_;
      std::sort(sorted.begin(), sorted.end());
      sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
      std::string list;
      for (const auto& s : sorted) list += (list.empty() ? "" : ", ") + s;
      const std::string scope = path_.empty() ? "at the top level" : "in [" + path_ + "]";
      throw InputError(where(name) + ": unknown key " + scope + "; allowed keys: " +
                       (list.empty() ? "(none)" : list));
    }
  }
}

}  // namespace codesign::io

namespace codesign::io {
const std::string& TableReader::file() const { return state_->file; }
}  // namespace codesign::io
