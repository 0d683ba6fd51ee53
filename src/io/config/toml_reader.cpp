#include "io/config/toml_reader.hpp"

#include "base/config_check.hpp"
#include "base/grid_values.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include <toml++/toml.h>

namespace codesign::io {

struct TableReader::State {
  std::string file;
  toml::table root;
  std::vector<std::string> bases;  // files merged in through `extends`, nearest first
};

namespace {

// A TOML integer or float as a double; nullopt for any other type.
std::optional<double> number_of(const toml::node& n) {
  if (auto i = n.value_exact<std::int64_t>()) return static_cast<double>(*i);
  if (auto d = n.value_exact<double>()) return *d;
  return std::nullopt;
}

std::string format_number(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

// "[lo, hi]" as every config message prints a range (base/config_check.hpp).
template <class T>
std::string range_text(T lo, T hi) {
  return config::range_text(Range<T>{lo, hi});
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

namespace {

constexpr int kMaxExtendsDepth = 8;

std::string read_config_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError(path + ": cannot read config file: it is a directory; give a TOML file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open config file");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

toml::table parse_text(std::string_view text, const std::string& label) {
  try {
    return toml::parse(text, label);
  } catch (const toml::parse_error& e) {
    throw InputError(parse_error_text(label, e));
  }
}

// Keys of `over` replace those of `base`; tables present in both are merged key by key, so a
// derived config states only what differs. Arrays are replaced whole.
void merge_into(toml::table& base, const toml::table& over) {
  for (auto&& [key, node] : over) {
    const auto* over_table = node.as_table();
    auto* base_table = base.get_as<toml::table>(key);
    if (over_table != nullptr && base_table != nullptr) {
      merge_into(*base_table, *over_table);
    } else {
      base.insert_or_assign(key, node);
    }
  }
}

// Parses `path` and, if its root has `extends = "other.toml"` (relative to path's folder), the
// chain of files it extends, merged with the nearest file winning.
toml::table parse_with_bases(const std::string& path, std::vector<std::string>& bases,
                             std::vector<std::filesystem::path>& seen) {
  toml::table root = parse_text(read_config_file(path), path);
  const toml::node* ext = root.get("extends");
  if (ext == nullptr) return root;
  const auto base_name = ext->value_exact<std::string>();
  if (!base_name || base_name->empty())
    throw InputError(path + ": extends: expected the file name of a config to extend (a string), got " +
                     type_name(*ext));
  const std::filesystem::path base_path =
      std::filesystem::path(path).parent_path() / std::filesystem::path(*base_name);
  std::error_code ec;
  const auto canonical = std::filesystem::weakly_canonical(base_path, ec);
  if (std::find(seen.begin(), seen.end(), canonical) != seen.end())
    throw InputError(path + ": extends: \"" + *base_name + "\" leads back to a file already in the chain");
  if (static_cast<int>(seen.size()) >= kMaxExtendsDepth)
    throw InputError(path + ": extends: more than " + std::to_string(kMaxExtendsDepth) +
                     " files in the chain; allowed 1 to " + std::to_string(kMaxExtendsDepth));
  seen.push_back(canonical);
  bases.push_back(base_path.string());
  toml::table merged = parse_with_bases(base_path.string(), bases, seen);
  root.erase("extends");
  merge_into(merged, root);
  return merged;
}

}  // namespace

TableReader TableReader::from_file(const std::string& path) {
  auto state = std::make_shared<State>();
  state->file = path;
  std::error_code ec;
  std::vector<std::filesystem::path> seen{std::filesystem::weakly_canonical(path, ec)};
  state->root = parse_with_bases(path, state->bases, seen);
  const toml::table* root = &state->root;
  return TableReader(std::move(state), root, "");
}

std::string TableReader::input_text(const std::string& path) {
  const std::string text = read_config_file(path);
  TableReader reader = from_file(path);
  if (reader.state_->bases.empty()) return text;
  std::ostringstream os;
  os << "# " << path;
  for (const auto& b : reader.state_->bases) os << " extends " << b;
  os << "; merged:\n" << reader.state_->root << "\n";
  return os.str();
}

const std::vector<std::string>& TableReader::bases() const { return state_->bases; }

TableReader TableReader::from_string(std::string_view text, std::string file_label) {
  auto state = std::make_shared<State>();
  state->file = std::move(file_label);
  state->root = parse_text(text, state->file);
  if (state->root.get("extends") != nullptr)
    throw InputError(state->file + ": extends: only a config read from a file may extend another");
  const toml::table* root = &state->root;
  return TableReader(std::move(state), root, "");
}

std::string TableReader::where(std::string_view key) const {
  std::string full = path_.empty() ? std::string(key) : path_ + "." + std::string(key);
  // A value merged in from an extended file is reported at the file that states it.
  if (table_ != nullptr) {
    if (const toml::node* node = table_->get(key); node != nullptr && node->source().path)
      return *node->source().path + ": " + full;
  }
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
  const std::optional<double> n = number_of(*node);
  if (!n) fail(key, "expected a number in " + range_text(lo, hi) + ", got " + type_name(*node));
  const double v = *n;
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

std::string TableReader::string(std::string_view key, std::string def, std::span<const std::string_view> allowed) {
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
    const std::optional<double> n = number_of(el);
    if (!n) fail(key, "element " + std::to_string(i) + ": expected a number, got " + type_name(el));
    const double v = *n;
    if (!std::isfinite(v) || v < lo || v > hi) {
      fail(key, "element " + std::to_string(i) + " = " + format_number(v) +
                    " is out of range; allowed " + range_text(lo, hi));
    }
    out.push_back(v);
  }
  return out;
}

std::vector<double> TableReader::grid(std::string_view key, std::vector<double> def, double lo, double hi,
                                      std::size_t min_len, std::size_t max_len) {
  const auto* node = table_ == nullptr ? nullptr : static_cast<const toml::node*>(table_->get(key));
  if (node == nullptr || !node->is_table()) return numbers(key, std::move(def), lo, hi, min_len, max_len);
  (void)lookup(key);
  const toml::table& range = *node->as_table();
  for (auto&& [k, v] : range)
    if (k.str() != "from" && k.str() != "to" && k.str() != "step")
      fail(key, "unknown key \"" + std::string(k.str()) + "\" in {from, to, step}");
  double f[3] = {0.0, 0.0, 0.0};
  const char* names[3] = {"from", "to", "step"};
  for (int i = 0; i < 3; ++i) {
    const toml::node* n = range.get(names[i]);
    if (n == nullptr) fail(key, std::string("missing \"") + names[i] + "\" in {from, to, step}");
    const std::optional<double> x = number_of(*n);
    if (!x) fail(key, std::string(names[i]) + ": expected a number, got " + type_name(*n));
    f[i] = *x;
  }
  std::vector<double> out;
  try {
    out = grid_values(f[0], f[1], f[2]);
  } catch (const std::invalid_argument& e) {
    fail(key, std::string("{from, to, step}: ") + e.what());
  }
  if (out.size() < min_len || out.size() > max_len)
    fail(key, "{from, to, step} gives " + std::to_string(out.size()) + " values; allowed " + std::to_string(min_len) +
                  " to " + std::to_string(max_len));
  for (const double v : out)
    if (v < lo || v > hi)
      fail(key, "{from, to, step} gives " + format_number(v) + ", out of range; allowed " + range_text(lo, hi));
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
