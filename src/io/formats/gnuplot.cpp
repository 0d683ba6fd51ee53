#include "io/formats/gnuplot.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <set>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "base/errors.hpp"

extern char** environ;

namespace codesign::io {

namespace {

constexpr std::size_t kMaxOutput = 64 * 1024;  // bytes of gnuplot's output kept

bool is_identifier(const std::string& s) {
  if (s.empty()) return false;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    const bool letter = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_';
    const bool digit = c >= '0' && c <= '9';
    if (!letter && !(digit && i > 0)) return false;
  }
  return true;
}

bool has_control_character(const std::string& s) {
  for (const char ch : s) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c < 0x20 || c == 0x7f) return true;
  }
  return false;
}

// A gnuplot single-quoted string: no escapes are interpreted inside, '' stands for one quote.
std::string single_quoted(const std::string& s) {
  std::string out = "'";
  for (const char c : s) {
    if (c == '\'') out += "''";
    else out += c;
  }
  out += "'";
  return out;
}

bool is_executable_file(const std::string& path) { return ::access(path.c_str(), X_OK) == 0; }

}  // namespace

void GnuplotCall::set(const std::string& name, const std::string& value) {
  variables.push_back({name, value, true});
}

void GnuplotCall::set(const std::string& name, double value) {
  if (!std::isfinite(value)) {
    throw InputError("gnuplot variable " + name + ": value is not a finite number");
  }
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", value);
  variables.push_back({name, buf, false});
}

void GnuplotCall::validate() const {
  if (script.empty()) throw InputError("gnuplot: no script file given");
  if (std::FILE* f = std::fopen(script.c_str(), "rb")) {
    std::fclose(f);
  } else {
    throw InputError(script + ": cannot read the gnuplot script (" + std::strerror(errno) + ")");
  }
  if (executable.empty()) throw InputError("gnuplot: empty executable name");
  std::set<std::string> seen;
  for (const GnuplotVariable& v : variables) {
    if (!is_identifier(v.name)) {
      throw InputError(script + ": gnuplot variable name '" + v.name +
                       "' is not allowed; allowed: letters, digits and _, not starting with a digit");
    }
    if (!seen.insert(v.name).second) {
      throw InputError(script + ": gnuplot variable " + v.name + " is set twice");
    }
    if (v.is_string && has_control_character(v.value)) {
      throw InputError(script + ": gnuplot variable " + v.name +
                       ": value contains a control character (newline, tab, NUL, ...); not allowed");
    }
    if (!v.is_string) {
      char* end = nullptr;
      const double x = std::strtod(v.value.c_str(), &end);
      if (v.value.empty() || *end != '\0' || !std::isfinite(x)) {
        throw InputError(script + ": gnuplot variable " + v.name + ": '" + v.value +
                         "' is not a finite number");
      }
    }
  }
}

std::vector<std::string> GnuplotCall::arguments() const {
  std::vector<std::string> args{executable};
  if (!variables.empty()) {
    std::string statements;
    for (const GnuplotVariable& v : variables) {
      if (!statements.empty()) statements += "; ";
      statements += v.name + " = " + (v.is_string ? single_quoted(v.value) : v.value);
    }
    args.push_back("-e");
    args.push_back(statements);
  }
  args.push_back(script);
  return args;
}

std::string GnuplotOutcome::message() const {
  switch (status) {
    case Status::ok:
      return "gnuplot: " + script + ": ok";
    case Status::not_found:
      return "gnuplot not found (install the Debian package gnuplot-nox, see scripts/setup.sh): " +
             output;
    case Status::failed:
      break;
  }
  // The first lines of gnuplot's output carry the error and the offending script line.
  // Non-blank lines joined with " | ", at most 6.
  std::string head;
  int lines = 0;
  std::size_t start = 0;
  while (start < output.size() && lines < 6) {
    std::size_t end = output.find('\n', start);
    if (end == std::string::npos) end = output.size();
    const std::string line = output.substr(start, end - start);
    start = end + 1;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    head += (lines++ ? " | " : "") + line;
  }
  std::string m = "gnuplot failed on " + script;
  m += exit_code >= 0 ? " (exit status " + std::to_string(exit_code) + ")" : " (killed by a signal)";
  if (!head.empty()) m += ": " + head;
  return m;
}

GnuplotOutcome run_gnuplot(const GnuplotCall& call) {
  call.validate();
  GnuplotOutcome outcome;
  outcome.script = call.script;

  const std::vector<std::string> args = call.arguments();
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);

  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) {
    outcome.output = std::string("cannot create a pipe: ") + std::strerror(errno);
    return outcome;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDERR_FILENO);

  pid_t pid = -1;
  const int spawn_error = ::posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(pipe_fds[1]);
  if (spawn_error != 0) {
    ::close(pipe_fds[0]);
    outcome.status = (spawn_error == ENOENT || spawn_error == EACCES || spawn_error == ENOTDIR)
                         ? GnuplotOutcome::Status::not_found
                         : GnuplotOutcome::Status::failed;
    outcome.output = call.executable + ": " + std::strerror(spawn_error);
    return outcome;
  }

  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(pipe_fds[0], buf, sizeof buf);
    if (n > 0) {
      const std::size_t room = kMaxOutput - std::min(kMaxOutput, outcome.output.size());
      outcome.output.append(buf, std::min(room, static_cast<std::size_t>(n)));
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    break;
  }
  ::close(pipe_fds[0]);

  int status = 0;
  pid_t waited;
  do {
    waited = ::waitpid(pid, &status, 0);
  } while (waited < 0 && errno == EINTR);
  if (waited == pid && WIFEXITED(status)) {
    outcome.exit_code = WEXITSTATUS(status);
    outcome.status = outcome.exit_code == 0 ? GnuplotOutcome::Status::ok : GnuplotOutcome::Status::failed;
  } else {
    outcome.exit_code = -1;
    outcome.status = GnuplotOutcome::Status::failed;
  }
  return outcome;
}

bool gnuplot_available(const std::string& executable) {
  if (executable.empty()) return false;
  if (executable.find('/') != std::string::npos) return is_executable_file(executable);
  const char* path = std::getenv("PATH");
  const std::string dirs = path ? path : "/usr/local/bin:/usr/bin:/bin";
  std::size_t start = 0;
  while (start <= dirs.size()) {
    std::size_t end = dirs.find(':', start);
    if (end == std::string::npos) end = dirs.size();
    const std::string dir = end > start ? dirs.substr(start, end - start) : ".";
    if (is_executable_file(dir + "/" + executable)) return true;
    start = end + 1;
  }
  return false;
}

}  // namespace codesign::io
