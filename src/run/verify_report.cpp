#include "run/verify_report.hpp"

#include <cstdio>
#include <sstream>

#include "fem/design.hpp"

namespace codesign::run {

namespace {

const VerifyRow* find_row(const std::vector<VerifyRow>& rows, const std::string& subject, const std::string& condition) {
  for (const VerifyRow& r : rows)
    if (r.subject == subject && r.condition == condition) return &r;
  return nullptr;
}

std::string interval(const VerifyRow& r) {
  char s[96];
  std::snprintf(s, sizeof s, "%.1f [%.1f, %.1f]", r.mean_return, r.mean_return - r.ci95, r.mean_return + r.ci95);
  return s;
}

std::string design_name(const VerifyRow& r) {
  std::string s = "j";  // appended, not "j" + …: GCC 12 warns falsely on that form (-Wstringop-overflow)
  return s += std::to_string(r.at.design);
}

}  // namespace

std::vector<Verdict> verdicts(const std::vector<VerifyRow>& rows, const std::vector<std::string>& conditions) {
  std::vector<Verdict> out;
  for (const std::string& c : conditions) {
    const VerifyRow* dstar = find_row(rows, "d*", c);
    if (!dstar) continue;
    const VerifyRow* best = dstar;
    int designs = 0;
    for (const VerifyRow& r : rows)
      if (r.condition == c && r.controller == kControllerPolicy) {
        ++designs;
        if (r.mean_return > best->mean_return) best = &r;
      }
    Verdict v;
    v.condition = c;
    v.best_subject = best->subject;
    v.within = dstar->mean_return + dstar->ci95 >= best->mean_return - best->ci95;
    std::string line = c + ": d* (" + design_name(*dstar) + ") " + interval(*dstar);
    if (designs == 1) line += ", the only design tested";
    else if (best == dstar) line += " leads the designs tested";
    else
      line += std::string(v.within ? " is within" : " is below") + " the best group (best: " + best->subject + ", " +
              design_name(*best) + ", " + interval(*best) + ")";
    for (const VerifyRow& r : rows)
      if (r.condition == c && r.controller == kControllerSpecialist && r.at.design == dstar->at.design)
        line += "; " + r.subject + " " + interval(r);
    for (const char* b : {kControllerPidForce, kControllerPidEstimate})
      if (const VerifyRow* r = find_row(rows, b, c)) line += "; " + std::string(b) + " " + interval(*r);
    v.line = line;
    out.push_back(v);
  }
  return out;
}

std::string verify_report(const VerifyReportInput& in) {
  std::ostringstream o;
  o << "# verify: " << in.run << "\n\n";
  std::vector<std::string> names;
  for (const auto& c : in.conditions) names.push_back(c.first);
  const std::vector<Verdict> vs = verdicts(in.rows, names);
  int designs = 0;
  for (const VerifySubject& s : in.subjects) designs += s.controller == kControllerPolicy ? 1 : 0;
  // The nominal cell when the conditions run include it (`verify --conditions` may leave it out).
  const VerifyRow* nominal = find_row(in.rows, "d*", "nominal");
  const VerifyRow* worst = nullptr;
  for (const VerifyRow& r : in.rows)
    if (r.subject == "d*" && (!worst || r.mean_return < worst->mean_return)) worst = &r;
  if (worst) {
    int within = 0;
    for (const Verdict& v : vs) within += v.within ? 1 : 0;
    char line[512];
    if (nominal)
      std::snprintf(line, sizeof line,
                    "The final policy on d* = %s tracks to %.1f of 50 on the nominal model and to %.1f at worst (%s)",
                    fem::design_label(nominal->at.design).c_str(), nominal->mean_return, worst->mean_return,
                    worst->condition.c_str());
    else
      std::snprintf(line, sizeof line, "The final policy on d* = %s tracks to %.1f of 50 at worst (%s) over the conditions run",
                    fem::design_label(worst->at.design).c_str(), worst->mean_return, worst->condition.c_str());
    o << line;
    if (const VerifyRow* oracle = find_row(in.rows, kControllerPidForce, worst->condition))
      o << ", where a PID on the true force gets " << interval(*oracle).substr(0, interval(*oracle).find(' '));
    if (designs > 1)
      o << "; d* is within the best group of the " << designs << " designs tested under " << within << " of "
        << vs.size() << " conditions";
    o << ".\n\n";
  }
  o << "Each cell: the return over " << in.phases << " " << in.phase_set << " plate phases 2π(k + "
    << (in.phase_set == "test" ? "½" : "¼")
    << ")/n (Σ of the 50 decisions' rewards, max 50 for the force term), mean and the 95 % interval of the mean "
       "(1.96 s/√n). d* is within the best group when its interval reaches the best design's.\n\n";
  o << "## Verdicts\n\n";
  for (const Verdict& v : vs) o << "- " << v.line << "\n";
  o << "\n## What was tested\n\n| subject | design | pressures (kPa) | controller | why |\n|---|---|---|---|---|\n";
  for (const VerifySubject& s : in.subjects) {
    char p[64];
    std::snprintf(p, sizeof p, "%.3f, %.3f", s.at.p1_kPa, s.at.p2_kPa);
    o << "| " << s.name << " | " << fem::design_label(s.at.design) << " | " << p << " | " << s.controller << " | "
      << s.why << " |\n";
  }
  if (!in.notes.empty()) o << "\n" << in.notes << "\n";
  o << "\n| condition | what it is |\n|---|---|\n";
  for (const auto& [name, what] : in.conditions) o << "| " << name << " | " << what << " |\n";
  o << "\n## Returns\n\nmean ± std [95 % interval], decisions in band\n\n| condition |";
  for (const VerifySubject& s : in.subjects) o << " " << s.name << " |";
  o << "\n|---|";
  for (std::size_t i = 0; i < in.subjects.size(); ++i) o << "---|";
  o << "\n";
  for (const std::string& c : names) {
    o << "| " << c << " |";
    for (const VerifySubject& s : in.subjects) {
      const VerifyRow* r = find_row(in.rows, s.name, c);
      if (!r) {
        o << " |";
        continue;
      }
      char cell[160];
      std::snprintf(cell, sizeof cell, " %.2f ± %.2f [%.2f, %.2f], %.0f %% |", r->mean_return, r->std_return,
                    r->mean_return - r->ci95, r->mean_return + r->ci95, 100.0 * r->band_fraction);
      o << cell;
    }
    o << "\n";
  }
  return o.str();
}

}  // namespace codesign::run
