#pragma once
// Running a gnuplot script file as a child process, with variables set on its command line.
//
//   io::GnuplotCall call;
//   call.script = "/path/plots/fig2a.gp";
//   call.set("datafile", "runs/quick/figures/data/fig2a_rewards.dat");   // a string variable
//   call.set("t1", 220000.0);                                              // a number variable
//   const io::GnuplotOutcome r = io::run_gnuplot(call);
//   if (!r.ok()) std::fprintf(stderr, "%s\n", r.message().c_str());
//
// gnuplot is started with fork/exec semantics (posix_spawnp, no shell): the argument vector is
//   gnuplot -e "name1 = value1; name2 = value2; ..." SCRIPT
// Every string value is written as a gnuplot single-quoted string (a quote inside is doubled),
// numbers with 17 significant digits, and names must be identifiers, so no value can end a
// statement or run a command: a file name such as  a'; system('rm x')  arrives in the script
// as that literal string. Values may not contain control characters (newline, NUL, ...).
// The child's stdout and stderr are captured together and returned (gnuplot reports script
// errors on stderr and exits with status 1).
#include <string>
#include <vector>

namespace codesign::io {

struct GnuplotVariable {
  std::string name;    // [A-Za-z_][A-Za-z0-9_]*
  std::string value;   // as given (string) or as formatted (number)
  bool is_string = true;
};

struct GnuplotCall {
  std::string script;                 // path of the .gp file (must exist and be readable)
  std::vector<GnuplotVariable> variables;
  std::string executable = "gnuplot"; // a name searched on PATH, or a path

  void set(const std::string& name, const std::string& value);
  void set(const std::string& name, const char* value) { set(name, std::string(value)); }
  void set(const std::string& name, double value);   // finite only
  // Throws codesign::InputError naming the offending script, variable or value:
  // empty or unreadable script, empty executable, a bad variable name, a duplicated name,
  // a control character in a string value, a non-finite number.
  void validate() const;
  // The argument vector passed to the executable (argv[0] = executable), after validate().
  std::vector<std::string> arguments() const;
};

struct GnuplotOutcome {
  enum class Status { ok, not_found, failed };
  Status status = Status::failed;
  int exit_code = -1;      // the child's exit status; -1 if it did not exit normally or never ran
  std::string output;      // what gnuplot printed (stdout and stderr, interleaved)
  std::string script;      // the script that ran, for messages

  bool ok() const { return status == Status::ok; }
  // One line for the user: "gnuplot not found (...)", or "gnuplot failed on SCRIPT (exit 1): <first
  // lines of its output>".
  std::string message() const;
};

// Runs the call (validate() first: its InputError propagates) and waits for gnuplot to finish.
// A missing executable gives Status::not_found, a non-zero exit or a signal Status::failed; the
// caller decides whether that is a warning or an error. Thread-safe (no global state touched).
GnuplotOutcome run_gnuplot(const GnuplotCall& call);

// True if `executable` (default "gnuplot") can be found: a path that is executable, or a name
// found executable in one of PATH's directories.
bool gnuplot_available(const std::string& executable = "gnuplot");

}  // namespace codesign::io
