#pragma once
// A closed interval [lo, hi] of allowed values. Each validated config field states its range once,
// as an inline constexpr Range next to its struct; the struct's validate() and the config reader
// (src/io) both use that constant, so the two cannot disagree.
namespace codesign {

template <class T>
struct Range {
  T lo;
  T hi;
  constexpr bool contains(T v) const { return v >= lo && v <= hi; }
};

}  // namespace codesign
