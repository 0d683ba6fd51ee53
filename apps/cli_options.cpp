#include "cli_options.hpp"

#include <cstdio>

#include "base/errors.hpp"
#include "fem/design.hpp"

namespace codesign::app {

CLI::Option* add_threads_option(CLI::App& cmd, int& threads, const std::string& help) {
  return cmd.add_option("--threads", threads, help)->check(CLI::Range(0, 1024));
}

CLI::Option* add_designs_option(CLI::App& cmd, std::string& designs, const std::string& default_text) {
  return cmd.add_option("--designs", designs, "design index or range A-B (default " + default_text + ")");
}

std::pair<int, int> parse_design_range(const std::string& text) {
  int a = -1, b = -1;
  char dash = 0;
  if (std::sscanf(text.c_str(), "%d%c%d", &a, &dash, &b) == 3 && dash == '-' && 0 <= a && a <= b &&
      b < fem::kDesignCount)
    return {a, b};
  if (std::sscanf(text.c_str(), "%d", &a) == 1 && text.find('-') == std::string::npos && 0 <= a &&
      a < fem::kDesignCount)
    return {a, a};
  throw InputError("--designs: '" + text + "' is not a design index or range A-B within 0.." +
                   std::to_string(fem::kDesignCount - 1));
}

}  // namespace codesign::app
