#pragma once
// Bounded, derivative-free maximisation with NLopt from several starting points: the one search
// routine behind every tuned baseline (PID gains, the fixed base angle, the polish of p*).
//
// maximise(f, bounds, options) runs a local NLopt method (BOBYQA by default; COBYLA, Nelder–Mead
// or Sbplx by choice) from `starts` points and returns the best point it evaluated. Start 0 is
// the caller's x0 (clamped into the box), or the box centre; the others are the points 1, 2, ...
// of the Halton sequence (bases 2, 3, 5, 7, ...) mapped into the box — spread out and
// deterministic, so a search does not depend on a seed. The evaluation budget `max_evals` is the
// total over all starts, split evenly (the first starts get the remainder); every start also
// stops when a step changes x by less than xtol_rel (relative to the box width) or f by less
// than ftol_abs. f is never called outside the box, and never more than max_evals times.
// An exception thrown by f stops the search and is rethrown unchanged.
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "base/enum_names.hpp"

namespace codesign::core {

enum class LocalMethod { Bobyqa, Cobyla, NelderMead, Sbplx };
inline constexpr EnumNames<LocalMethod, 4> kLocalMethodNames{{{LocalMethod::Bobyqa, "bobyqa"},
                                                              {LocalMethod::Cobyla, "cobyla"},
                                                              {LocalMethod::NelderMead, "neldermead"},
                                                              {LocalMethod::Sbplx, "sbplx"}}};

inline const char* to_string(LocalMethod m) { return name_of(kLocalMethodNames, m).data(); }
// A name of kLocalMethodNames; anything else throws std::invalid_argument listing them.
LocalMethod local_method_from_name(const std::string& name);

struct SearchBox {
  std::vector<double> lower, upper;  // lower[i] <= upper[i], finite; equal bounds fix a variable
  std::size_t dim() const { return lower.size(); }
  // Throws std::invalid_argument naming the first bad coordinate (sizes, order, non-finite).
  void validate() const;
};

struct SearchOptions {
  LocalMethod method = LocalMethod::Bobyqa;
  int starts = 3;            // >= 1
  int max_evals = 60;        // total over all starts, >= starts
  double xtol_rel = 1e-3;    // per start: stop when |Δx_i| < xtol_rel·(upper_i − lower_i)
  double ftol_abs = 1e-6;    // per start: stop when |Δf| < ftol_abs
  // Throws std::invalid_argument naming the field and its range.
  void validate() const;
};

struct SearchResult {
  std::vector<double> x;     // the best point evaluated
  double value = 0.0;        // f(x)
  int evaluations = 0;       // calls of f over all starts
  int best_start = 0;        // the start whose run found x
  std::vector<double> start_values;  // best f of each start's run
};

// Halton point `index` (>= 1) in [0, 1)^dim.
std::vector<double> halton_point(std::size_t index, std::size_t dim);

using Objective = std::function<double(const std::vector<double>& x)>;

SearchResult maximise(const Objective& f, const SearchBox& box, const SearchOptions& options,
                      const std::optional<std::vector<double>>& x0 = std::nullopt);

}  // namespace codesign::core
