// Entry point of `codesign`: builds the command line from the sub-commands in apps/,
// runs the selected one, and turns user-input errors and files that cannot be written into one
// message and exit status 2.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include <optional>

#include "commands.hpp"
#include "base/errors.hpp"
#include "cluster/mpi_world.hpp"

namespace {

// `codesign --config run.toml -o runs/NAME` is the main job: the co-design run, i.e. the same as
// `codesign run --config run.toml -o runs/NAME`.
std::vector<std::string> with_default_command(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  const bool starts_with_option = !args.empty() && args.front().rfind("--", 0) == 0;
  bool has_config = false;
  for (const auto& a : args) has_config = has_config || a == "--config" || a.rfind("--config=", 0) == 0;
  const bool wants_help = args.size() == 1 && (args[0] == "--help" || args[0] == "--version");
  if (starts_with_option && has_config && !wants_help) args.insert(args.begin(), "run");
  return args;
}

}  // namespace

// Runs the selected command; returns its exit status. Errors are one message on stderr (status 2
// for bad input and unwritable files, 1 for internal errors).
int run_command(int argc, char** argv);

int main(int argc, char** argv) {
  // Under an MPI launcher (mpirun, srun) every rank runs this binary; only `codesign run` uses
  // them (docs/cluster.md). Without a launcher MPI is never touched.
  std::optional<codesign::cluster::MpiSession> mpi;
  if (codesign::cluster::launched_by_mpi()) mpi.emplace(&argc, &argv);
  const int rank = codesign::cluster::world_rank(), ranks = codesign::cluster::world_size();
  if (ranks > 1) {
    const std::vector<std::string> args = with_default_command(argc, argv);
    const bool multi_rank = !args.empty() && (args.front() == "run" || (args.front() == "bench" && args.size() > 1 &&
                                                                         args[1] == "cluster"));
    if (!multi_rank) {  // every rank ends here alike: no one waits
      if (rank == 0)
        std::fprintf(stderr, "codesign: error: only `codesign run` (or the main job) and `codesign bench cluster` run "
                             "on several MPI ranks; run '%s' without mpirun\n", args.empty() ? "" : args.front().c_str());
      return 2;
    }
  }
  const int status = run_command(argc, argv);
  // Rank 0 failing (status 1 or 2), or another rank failing inside (status 1), ends the whole job:
  // the others may be waiting for it. Bad input fails every rank alike before any waits, so the
  // other ranks just return 2 beside rank 0. A run stopped in order (4, 128 + signal) has released
  // the other ranks already (its rollout pool's destructor): they finish as usual and the launcher
  // reports rank 0's status.
  if (ranks > 1 && (status == 1 || (status == 2 && rank == 0))) {
    std::fflush(stdout);
    std::fflush(stderr);
    codesign::cluster::abort_world(status);
  }
  return status;
}

int run_command(int argc, char** argv) {
  using namespace codesign;
  const int rank = cluster::world_rank();
  CLI::App root{"codesign: co-design of a soft pneumatic whisker and its feedback controller"};
  root.set_version_flag("--version", std::string("codesign 0.1.0"));
  root.require_subcommand(1);
  root.footer("Main job: codesign --config run.toml -o runs/NAME  (see README.md)");

  app::Runner run;
  app::add_run_command(root, run);
  app::add_survey_command(root, run);
  app::add_mesh_command(root, run);
  app::add_sim_command(root, run);
  app::add_train_gym_command(root, run);
  app::add_figures_command(root, run);
  app::add_check_command(root, run);
  app::add_config_keys_command(root, run);
  app::add_render_command(root, run);
  app::add_baseline_command(root, run);
  app::add_sweep_command(root, run);
  app::add_refine_command(root, run);
  app::add_evaluate_command(root, run);
  app::add_verify_command(root, run);
  CLI::App* bench = root.add_subcommand("bench", "Speed benchmarks that print figures and ratios");
  bench->require_subcommand(1);
  app::add_bench_fem_command(*bench, run);
  app::add_bench_codesign_command(*bench, run);
  app::add_bench_cluster_command(*bench, run);
  app::add_bench_ppo_command(*bench, run);
  app::add_bench_telemetry_command(*bench, run);
  app::add_bench_render_command(*bench, run);

  std::vector<std::string> args = with_default_command(argc, argv);
  if (!args.empty() && !args.front().empty() && args.front().front() != '-') {
    std::string names;
    bool known = false;
    for (const CLI::App* c : root.get_subcommands([](CLI::App*) { return true; })) {
      known = known || c->get_name() == args.front();
      names += (names.empty() ? "" : ", ") + c->get_name();
    }
    if (!known) {
      std::fprintf(stderr, "codesign: error: unknown command '%s'; allowed: %s (codesign --help)\n",
                   args.front().c_str(), names.c_str());
      return 2;
    }
  }
  std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 parses a reversed vector
  try {
    root.parse(reversed);
  } catch (const CLI::ParseError& e) {
    const int code = root.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    if (!run) {
      std::fprintf(stderr, "codesign: error: no command selected\n");
      return 2;
    }
    return run();
  } catch (const InputError& e) {
    // Every rank reads the same input: rank 0 says what is wrong, once.
    if (rank == 0) std::fprintf(stderr, "codesign: error: %s\n", e.what());
    return 2;
  } catch (const FileError& e) {  // a file that could not be written: disk full, permissions
    std::fprintf(stderr, "codesign: error: %s\n", e.what());
    return 2;
  } catch (const std::filesystem::filesystem_error& e) {  // e.g. a folder that cannot be created
    std::fprintf(stderr, "codesign: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "codesign: internal error: %s\n", e.what());
    return 1;
  }
}
