#include "core/nlopt_search.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <stdexcept>

#include <nlopt.hpp>

namespace codesign::core {

namespace {

nlopt::algorithm nlopt_algorithm(LocalMethod m) {
  switch (m) {
    case LocalMethod::Bobyqa: return nlopt::LN_BOBYQA;
    case LocalMethod::Cobyla: return nlopt::LN_COBYLA;
    case LocalMethod::NelderMead: return nlopt::LN_NELDERMEAD;
    case LocalMethod::Sbplx: return nlopt::LN_SBPLX;
  }
  return nlopt::LN_BOBYQA;
}

// The i-th prime (i < 16 is all a search here needs).
unsigned prime(std::size_t i) {
  static constexpr unsigned kPrimes[] = {2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53};
  if (i >= std::size(kPrimes)) throw std::invalid_argument("halton_point: more than 16 dimensions");
  return kPrimes[i];
}

// What one start's NLopt run needs to see of the search.
struct Context {
  const Objective* f;
  const SearchBox* box;
  std::vector<std::size_t> free;     // coordinates with lower < upper
  std::vector<double> full;          // a full-length point; fixed coordinates stay at their bound
  int budget_left = 0;
  int evaluations = 0;
  double run_best = -HUGE_VAL;
  std::vector<double> best_x;
  double best = -HUGE_VAL;
  std::exception_ptr error;
};

double nlopt_objective(unsigned n, const double* z, double* grad, void* data) {
  auto* c = static_cast<Context*>(data);
  if (grad) std::fill(grad, grad + n, 0.0);  // derivative-free methods never ask; keep it defined
  if (c->budget_left <= 0) throw nlopt::forced_stop();
  try {
    for (unsigned i = 0; i < n; ++i) {
      const std::size_t k = c->free[i];
      // NLopt keeps the local methods inside the box; clamp anyway so f never sees a rounding
      // step past a bound.
      c->full[k] = std::clamp(z[i], c->box->lower[k], c->box->upper[k]);
    }
    const double v = (*c->f)(c->full);
    --c->budget_left;
    ++c->evaluations;
    const double score = std::isnan(v) ? -HUGE_VAL : v;  // a NaN never wins
    c->run_best = std::max(c->run_best, score);
    if (score > c->best || c->best_x.empty()) {
      c->best = score;
      c->best_x = c->full;
    }
    return score;
  } catch (...) {
    c->error = std::current_exception();
    throw nlopt::forced_stop();
  }
}

}  // namespace

LocalMethod local_method_from_name(const std::string& name) {
  if (const std::optional<LocalMethod> m = value_of(kLocalMethodNames, name)) return *m;
  throw std::invalid_argument("unknown local search method '" + name + "'; allowed: " + names_list(kLocalMethodNames));
}

void SearchBox::validate() const {
  if (lower.empty() || lower.size() != upper.size())
    throw std::invalid_argument("search box: lower and upper bounds need the same, non-zero length (got " +
                                std::to_string(lower.size()) + " and " + std::to_string(upper.size()) + ")");
  for (std::size_t i = 0; i < lower.size(); ++i) {
    if (!std::isfinite(lower[i]) || !std::isfinite(upper[i]))
      throw std::invalid_argument("search box: bound of coordinate " + std::to_string(i) + " is not finite");
    if (lower[i] > upper[i])
      throw std::invalid_argument("search box: coordinate " + std::to_string(i) + " has lower bound " +
                                  std::to_string(lower[i]) + " above its upper bound " + std::to_string(upper[i]));
  }
}

void SearchOptions::validate() const {
  if (starts < 1) throw std::invalid_argument("search: starts must be >= 1 (got " + std::to_string(starts) + ")");
  if (max_evals < starts)
    throw std::invalid_argument("search: max_evals must be >= starts (" + std::to_string(starts) + "), got " +
                                std::to_string(max_evals));
  if (!(xtol_rel >= 0.0 && xtol_rel < 1.0)) throw std::invalid_argument("search: xtol_rel must lie in [0, 1)");
  if (!(ftol_abs >= 0.0 && std::isfinite(ftol_abs))) throw std::invalid_argument("search: ftol_abs must be >= 0");
}

std::vector<double> halton_point(std::size_t index, std::size_t dim) {
  std::vector<double> p(dim);
  for (std::size_t d = 0; d < dim; ++d) {
    const unsigned b = prime(d);
    double f = 1.0, r = 0.0;
    for (std::size_t i = index; i > 0; i /= b) {
      f /= b;
      r += f * static_cast<double>(i % b);
    }
    p[d] = r;
  }
  return p;
}

SearchResult maximise(const Objective& f, const SearchBox& box, const SearchOptions& options,
                      const std::optional<std::vector<double>>& x0) {
  box.validate();
  options.validate();
  if (!f) throw std::invalid_argument("search: no objective");
  const std::size_t dim = box.dim();
  if (x0 && x0->size() != dim)
    throw std::invalid_argument("search: start point has " + std::to_string(x0->size()) + " coordinates, the box " +
                                std::to_string(dim));
  Context c;
  c.f = &f;
  c.box = &box;
  c.full = box.lower;
  for (std::size_t i = 0; i < dim; ++i)
    if (box.lower[i] < box.upper[i]) c.free.push_back(i);

  SearchResult out;
  // Every variable fixed: the box is one point.
  if (c.free.empty()) {
    c.budget_left = 1;
    nlopt_objective(0, nullptr, nullptr, &c);
    out.x = c.best_x;
    out.value = c.best;
    out.evaluations = 1;
    out.start_values = {c.best};
    return out;
  }
  const auto nfree = static_cast<unsigned>(c.free.size());
  // BOBYQA needs at least two variables in NLopt; with one free variable it is run as COBYLA.
  LocalMethod method = options.method;
  if (method == LocalMethod::Bobyqa && nfree < 2) method = LocalMethod::Cobyla;

  std::vector<double> lo(nfree), hi(nfree), step(nfree), xtol(nfree);
  for (unsigned i = 0; i < nfree; ++i) {
    const std::size_t k = c.free[i];
    lo[i] = box.lower[k];
    hi[i] = box.upper[k];
    step[i] = 0.25 * (hi[i] - lo[i]);
    xtol[i] = options.xtol_rel * (hi[i] - lo[i]);
  }
  int remaining = options.max_evals;
  for (int s = 0; s < options.starts; ++s) {
    // Start point in the box.
    std::vector<double> z(nfree);
    if (s == 0) {
      for (unsigned i = 0; i < nfree; ++i) {
        const std::size_t k = c.free[i];
        z[i] = x0 ? std::clamp((*x0)[k], lo[i], hi[i]) : 0.5 * (lo[i] + hi[i]);
      }
    } else {
      const std::vector<double> u = halton_point(static_cast<std::size_t>(s), nfree);
      for (unsigned i = 0; i < nfree; ++i) z[i] = lo[i] + u[i] * (hi[i] - lo[i]);
    }
    const int share = remaining / (options.starts - s);
    remaining -= share;
    c.budget_left = share;
    c.run_best = -HUGE_VAL;
    nlopt::opt opt(nlopt_algorithm(method), nfree);
    opt.set_lower_bounds(lo);
    opt.set_upper_bounds(hi);
    opt.set_max_objective(nlopt_objective, &c);
    opt.set_maxeval(share);
    opt.set_xtol_abs(xtol);
    opt.set_ftol_abs(options.ftol_abs);
    opt.set_initial_step(step);
    double fz = 0.0;
    try {
      opt.optimize(z, fz);
    } catch (const nlopt::roundoff_limited&) {
      // The method could not improve further: keep what it evaluated.
    } catch (const nlopt::forced_stop&) {
      // Budget exhausted, or the objective threw (rethrown below).
    } catch (const std::runtime_error&) {
      // NLopt's generic failure: likewise keep the best evaluated point.
    }
    if (c.error) std::rethrow_exception(c.error);
    remaining += c.budget_left;  // a start that converged early leaves its budget to the others
    out.start_values.push_back(c.run_best);
  }
  out.best_start = static_cast<int>(std::max_element(out.start_values.begin(), out.start_values.end()) -
                                     out.start_values.begin());
  out.x = c.best_x;
  out.value = c.best;
  out.evaluations = c.evaluations;
  return out;
}

}  // namespace codesign::core
