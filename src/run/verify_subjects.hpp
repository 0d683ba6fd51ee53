#pragma once
// What `codesign verify` tests (docs/verify.md, "What it tests"): the run's final policy on d*,
// the runner-up, the next designs of the run's own order and two bodies outside that group, the
// d* of other seeds' runs (--with), and two baselines on d*. Pure: the caller reads the run folder.
#include <optional>
#include <string>
#include <vector>

namespace codesign::run {

struct DesignAtPressures {
  bool operator==(const DesignAtPressures&) const = default;
  int design = 0;
  double p1_kPa = 0.0, p2_kPa = 0.0;
};

// Controllers a subject is tested with.
inline constexpr const char* kControllerPolicy = "policy";
inline constexpr const char* kControllerPidForce = "pid_force";        // PID on the true force: an oracle sensor
inline constexpr const char* kControllerPidEstimate = "pid_estimate";  // PI(D) on F̂(ε, θ) fitted on nominal episodes
inline constexpr const char* kControllerSpecialist = "specialist";  // a fresh policy trained on the design alone

struct VerifySubject {
  std::string name;        // "d*", "runner_up", "next_1", "outside_wall", "d*_of_<run>", "pid_force", ...
  std::string controller;  // kControllerPolicy, kControllerPidForce or kControllerPidEstimate
  DesignAtPressures at;
  std::string why;         // one line for the report
  std::string policy_file; // kControllerSpecialist: its policy.bin
};

struct SubjectSources {
  DesignAtPressures best;                       // d* at p* (result.toml [best])
  std::optional<DesignAtPressures> runner_up;   // result.toml [runner_up]
  // The run's designs in its own order, best first, at the pressures its state tests them at:
  // the `evaluate` ranking when the run has one, else the final distribution by probability.
  std::vector<DesignAtPressures> ranked;
  std::string ranked_from;                      // what `ranked` is, for the report
  int next = 2;                                 // designs taken from `ranked` after d* and the runner-up
  bool single_design = false;                   // the run trained d* alone: no other design of its policy
  bool baselines = true;                        // the two PIDs on d*
  std::vector<std::pair<std::string, DesignAtPressures>> others;  // (run name, its d* at its p*)
};

// The subjects in report order: d*, runner-up, next designs, the two outside bodies, other runs'
// d*, then the baselines on d*. A design already in the list is not repeated (an other run's d*
// that is one of them is named once, as the earlier subject).
std::vector<VerifySubject> verify_subjects(const SubjectSources& s);

// Two bodies outside `group`, with d*'s chamber count, to contrast the body at d*'s pressures:
// at d*'s chamber length the wall farthest from d*'s (thicker on a tie), and at d*'s wall the
// chamber length farthest from d*'s (longer on a tie); each the next farthest when taken. Either is
// -1 when no such design is left.
std::pair<int, int> outside_designs(int best, const std::vector<int>& group);

}  // namespace codesign::run
