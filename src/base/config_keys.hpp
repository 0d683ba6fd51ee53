#pragma once
// One description per config key. Each config table is described once, next to the struct that
// holds its values, by a function template
//
//   template <class V> void describe(V& v, fem::Material& m) {
//     v.scaled({"youngs_modulus_kPa", "kPa", "Young's modulus E of the silicone"},
//              m.youngs_modulus_Pa, 1e3, {1.0, 1e5});
//     v.number({"poisson_ratio", "", "Poisson's ratio"}, m.poisson_ratio, {0.0, 0.49});
//   }
//
// that names every key of the table once, in the order the resolved config.toml writes them,
// with its field, allowed range, unit and one-line meaning. The struct's member initialisers
// are the defaults (stated once; where a sub-command starts from other values, as the co-design
// from the paper's PPO settings, it passes those as the struct to read over). Visitors do the
// rest from that one list: src/io/config/ reads a TOML table with it (messages name file, key
// and range), writes the resolved config, checks a struct built in code, and prints the
// config-keys reference page (docs/config_reference.md). Adding a key is one line here plus its
// use.
//
// A visitor V has, for a key k (a Key below) and the field f it fills:
//   v.number(k, double& f, Range<double>)
//   v.scaled(k, double& f, double scale, Range<double>)   // the file states f / scale (kPa → Pa)
//   v.degrees(k, double& f_rad, Range<double> deg)         // the file states degrees
//   v.integer(k, I& f, Range<std::int64_t>)                // I: int, std::int64_t, std::uint64_t
//   v.boolean(k, bool& f)
//   v.text(k, std::string& f)                              // any string
//   v.choice(k, E& f, const EnumNames<E, N>& names)        // one of the names
//   v.numbers(k, std::vector<double>& f, Range<double> each, Range<std::size_t> length)
//   v.integers(k, std::vector<int>& f, Range<std::int64_t> each, Range<std::size_t> length)
//   v.grid(k, std::vector<double>& f, Range<double> each, Range<std::size_t> length)
//                                                          // an array, or {from, to, step}
//                                                          // (base/grid_values.hpp); written
//                                                          // as the array it gives
//   v.optional_number(k, std::optional<double>& f, Range<double>)   // written only when set
//   v.window(k_start, k_end, std::optional<std::int64_t>& start, std::optional<std::int64_t>& end,
//            Range<std::int64_t>)                          // both keys or neither, start < end
//   v.require(bool holds, std::string_view key, Message m) // a rule across keys; m() the
//                                                          // problem, called only when broken
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "base/enum_names.hpp"
#include "base/range.hpp"

namespace codesign::config {

// How the resolved config.toml carries a key.
enum class Written {
  Always,
  // Only when the value is not the default (Key::at_default false): keys added after runs were
  // made, so the resolved text (and the checkpoint fingerprint, a hash of it) of every run that
  // does not use them is the text it had before they existed.
  UnlessDefault,
  // An optional value: only when set.
  WhenSet,
  // Never: read and checked, but not part of the resolved config.
  Never,
};

struct Key {
  std::string_view name;
  std::string_view unit;     // "" when dimensionless
  std::string_view meaning;  // one line, for the reference page
  Written written = Written::Always;
  bool at_default = false;   // with Written::UnlessDefault: the value is the default
  // A key that applies only with another key's value (gru_hidden only with policy = "gru"):
  // given where it does not apply, reading fails with "applies only with <applies_with>;
  // <fix>"; it is written only where it applies.
  bool applies = true;
  std::string_view applies_with = {};
  std::string_view fix = {};
  // The range in words where it depends on other keys ("[1, task.episode_steps]").
  std::string_view range_note = {};
};

// Integral field types a description may use.
template <class I>
concept ConfigInteger = std::is_integral_v<I> && !std::is_same_v<I, bool>;

}  // namespace codesign::config
