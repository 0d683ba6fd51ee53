// `codesign verify --run DIR [--phases N] [--force] [--threads N]`
//
// The final policy of a finished co-design run on d* under held-out physics, into DIR/verify/
// (run/verify_run.hpp, docs/verify.md).
#include <cstdio>
#include <memory>

#include "cli_options.hpp"
#include "commands.hpp"
#include "run/verify_run.hpp"

namespace codesign::app {

namespace {

struct VerifyCliOptions {
  int threads = 0;
  run::VerifyOptions run;
};

}  // namespace

void add_verify_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<VerifyCliOptions>();
  CLI::App* cmd = root.add_subcommand(
      "verify", "Test a finished run's final policy on d* under held-out physics (modulus, mesh, plate, gauge)");
  cmd->add_option("--run", opt->run.dir, "a finished run folder (config.toml, result.toml, policy.bin)")->required();
  cmd->add_option("--phases", opt->run.phases, "test plate phases (episodes) per condition (default 100)")
      ->check(CLI::Range(2, 100000));
  cmd->add_flag("--force", opt->run.force, "replace a verify of the run made with other settings");
  add_threads_option(*cmd, opt->threads);
  cmd->callback([opt, &run] {
    run = [opt] {
      run::VerifyOptions o = opt->run;
      o.threads = static_cast<std::size_t>(opt->threads);
      const run::VerifySummary s = run::verify_run(o);
      std::printf("verify: %d conditions run now, %d before -> %s/report.md\n", s.conditions_run, s.conditions_before,
                  s.folder.c_str());
      return 0;
    };
  });
}

}  // namespace codesign::app
