// `mpirun -np N codesign run` (docs/cluster.md): the same run folder as one process,
// file for file (wall-clock fields aside), on 2 and 3 ranks of a 4-environment tiny run whose
// environments move between the ranks as their costs say (cluster::assign_by_cost); bad rank
// counts and other commands under mpirun are one message and exit 2. Open MPI is pinned to this
// machine: shared memory between the ranks (btl self,vader) and its own control channel on the
// loopback interface only.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>
#include <utility>
#include <vector>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "run_binary.hpp"
#include "tiny_run.hpp"

namespace {

namespace fs = std::filesystem;
using codesign::test::RunResult;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// result.toml without its wall-clock line.
std::string without_wall(const std::string& toml) {
  std::istringstream in(toml);
  std::string line, out;
  while (std::getline(in, line))
    if (line.rfind("wall_s", 0) != 0) out += line + "\n";
  return out;
}

// The launch of `args` on `ranks` ranks of this machine. Open MPI refuses root unless told (CI
// containers run as root); no single-copy transfers between the ranks' memories (they need ptrace
// rights that containers often withhold; our messages are small); on SIGTERM mpirun gives the
// ranks 10 s before it kills them.
// Under AddressSanitizer the ranks run without LeakSanitizer: Open MPI loads its components with
// dlopen and closes them at MPI_Finalize, so the allocations they keep until exit are reported
// from "<unknown module>" frames that no suppression can name (some 3 300 allocations, 116 kB
// per rank). Memory errors and UBSan stay on; the leak check of our own code
// runs in every test that does not start MPI, the one-process runs here included.
constexpr const char* kMpiEnv =
    "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 ASAN_OPTIONS=\"${ASAN_OPTIONS}:detect_leaks=0\" ";

std::string mpi_command(int ranks, const std::string& args) {
  return std::string(CODESIGN_MPIEXEC) + " -np " +
         std::to_string(ranks) +
         " --oversubscribe --mca btl self,vader --mca btl_vader_single_copy_mechanism none"
         " --mca oob_tcp_if_include lo --mca odls_base_sigkill_timeout 10 " +
         CODESIGN_BINARY + " " + args;
}

RunResult run_mpi(int ranks, const std::string& args) {
  return codesign::test::run_shell(kMpiEnv + mpi_command(ranks, args));
}

TEST(MpiRun, TwoAndThreeRanksWriteTheRunFolderOfOneProcess) {
  const fs::path dir = codesign::test::scratch_dir("codesign_mpi_", "same");
  // 4 environments of 2 decisions, 12 iterations through every phase of Algorithm 2, a checkpoint
  // every 2 iterations: short, but every call of the rollout interface crosses the ranks. With the
  // feed-forward policy and no observation statistics each rank runs its environments' whole
  // rollouts (core/run_ahead.hpp); with observation statistics the rollouts go step by step
  // across the ranks. Either way the run folder is the one-process run's.
  for (const bool statistics : {false, true}) {
    codesign::test::TinyRun t = codesign::test::TinyRun::minimal();
    t.total_timesteps = 96;
    t.exploration_end = 32;
    t.exploitation_start = 64;
    t.checkpoint_every = 16;
    std::string toml = t.toml();
    if (statistics) toml.replace(toml.find("[ppo]\n"), 6, "[ppo]\nnormalize_observations = true\n");
    const std::string name = statistics ? "statistics" : "plain";
    std::ofstream(dir / (name + ".toml")) << toml;
    const std::string common =
        "run --config " + (dir / (name + ".toml")).string() + " --threads 1 --quiet --no-figures -o ";
    const fs::path one_dir = dir / (name + "_one");
    RunResult one = codesign::test::run_codesign(common + one_dir.string());
    ASSERT_EQ(one.status, 0) << one.output;
    // Launches of ranks x threads; 2 x 2 (rank 0's own threads hold the update's two) is the one
    // whose other rank starts its environments during rank 0's update (MpiEnvPool::prestart).
    const std::vector<std::pair<int, int>> launches =
        statistics ? std::vector<std::pair<int, int>>{{2, 1}} : std::vector<std::pair<int, int>>{{2, 1}, {3, 1}, {2, 2}};
    for (const auto& [ranks, threads] : launches) {
      const fs::path out = dir / (name + std::to_string(ranks) + "x" + std::to_string(threads));
      std::string args = common + out.string();
      args.replace(args.find("--threads 1"), 11, "--threads " + std::to_string(threads));
      const RunResult r = run_mpi(ranks, args);
      ASSERT_EQ(r.status, 0) << r.output;
      for (const char* f : {"policy.bin", "sampled.csv", "distribution.csv", "q_disc.csv", "episodes.csv"})
        EXPECT_EQ(slurp(out / f), slurp(one_dir / f)) << f << " on " << ranks << " ranks, " << name;
      EXPECT_EQ(without_wall(slurp(out / "result.toml")), without_wall(slurp(one_dir / "result.toml")))
          << ranks << " ranks, " << name;
      EXPECT_FALSE(fs::exists(out / ".lock"));
      // The environments moved between the ranks (by their designs' costs) in some iterations, so
      // the files above also show that which rank steps an environment changes nothing. With
      // random costs a 2 + 2 split stays contiguous at a start with probability 1/6, 2 + 1 + 1
      // with 1/12, so all 11 starts after the first (costs unknown: contiguous) staying so is
      // below 1e-8.
      const std::string key = "environments shared out by cost at ";
      const std::size_t at = r.output.find(key);
      ASSERT_NE(at, std::string::npos) << r.output;
      EXPECT_GT(std::stoi(r.output.substr(at + key.size())), 0) << r.output;
      // Whole rollouts on the ranks in all 12 iterations, or in none.
      const std::string ahead = "meeting the others once, in ";
      const std::size_t at2 = r.output.find(ahead);
      ASSERT_NE(at2, std::string::npos) << r.output;
      EXPECT_EQ(std::stoi(r.output.substr(at2 + ahead.size())), statistics ? 0 : 12) << r.output;
      // Started during the update: after each of the first 11 iterations (the 12th has no next),
      // and only where rank 0 has two threads of its own.
      const std::string early = "starting their environments during it in ";
      const std::size_t at4 = r.output.find(early);
      ASSERT_NE(at4, std::string::npos) << r.output;
      EXPECT_EQ(std::stoi(r.output.substr(at4 + early.size())), !statistics && threads >= 2 ? 11 : 0) << r.output;
      // In the first iteration every rank meshes the designs it gets (rank 0 has none to send) and
      // sends rank 0 the meshes; how many reach a rank that had not built the design afterwards
      // depends on the costs measured, so only the first count is certain.
      const std::string made = "designs' meshes: ";
      const std::size_t at3 = r.output.find(made);
      ASSERT_NE(at3, std::string::npos) << r.output;
      EXPECT_GT(std::stoi(r.output.substr(at3 + made.size())), 0) << r.output;
    }
  }
}

// The launch of `cmd` through /bin/sh (exec'd, so the pid is mpirun's), output to `log`.
pid_t spawn_mpi(const std::string& cmd, const fs::path& log) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const std::string line = std::string(kMpiEnv) + "exec " + cmd + " > '" + log.string() + "' 2>&1";
    ::execl("/bin/sh", "sh", "-c", line.c_str(), static_cast<char*>(nullptr));
    std::_Exit(127);
  }
  return pid;
}

int wait_exit(pid_t pid) {
  int st = 0;
  if (::waitpid(pid, &st, 0) != pid) return -1;
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

// The pid of MPI rank `rank` of the run writing `out` (its command line names `out`), 0 if none.
pid_t rank_pid(const fs::path& out, int rank) {
  const std::string want = "OMPI_COMM_WORLD_RANK=" + std::to_string(rank);
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator("/proc", ec)) {
    const std::string name = e.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const std::string cmdline = slurp(e.path() / "cmdline"), environ = slurp(e.path() / "environ");
    if (cmdline.find(out.string()) == std::string::npos || cmdline.find("mpiexec") != std::string::npos) continue;
    std::size_t from = 0;
    while (from < environ.size()) {
      const std::size_t to = environ.find('\0', from);
      if (environ.compare(from, (to == std::string::npos ? environ.size() : to) - from, want) == 0)
        return static_cast<pid_t>(std::stol(name));
      if (to == std::string::npos) break;
      from = to + 1;
    }
  }
  return 0;
}

bool wait_for(const fs::path& f, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (!fs::exists(f))
    if (std::chrono::steady_clock::now() > end) return false;
    else std::this_thread::sleep_for(std::chrono::milliseconds(5));
  return true;
}

// The pid of rank `rank` of the run writing `out`, waiting up to `seconds` for it to start.
pid_t wait_for_rank(const fs::path& out, int rank, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  pid_t pid = rank_pid(out, rank);
  while (pid == 0 && std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    pid = rank_pid(out, rank);
  }
  return pid;
}

// True once `pid` is stopped (SIGSTOP takes effect a moment after kill() returns) or gone.
bool is_stopped(pid_t pid) {
  std::istringstream status(slurp(fs::path("/proc") / std::to_string(pid) / "status"));
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("State:", 0) == 0) return line.find('T') != std::string::npos;
  return true;
}

// True once `pid` has SIGTERM pending (it is stopped, so the signal waits) or is gone.
bool sigterm_pending(pid_t pid) {
  std::istringstream status(slurp(fs::path("/proc") / std::to_string(pid) / "status"));
  std::string line;
  bool any = false;
  while (std::getline(status, line)) {
    any = true;
    if (line.rfind("ShdPnd:", 0) == 0 || line.rfind("SigPnd:", 0) == 0) {
      const unsigned long long mask = std::stoull(line.substr(line.find(':') + 1), nullptr, 16);
      if (mask & (1ULL << (SIGTERM - 1))) return true;
    }
  }
  return !any;
}

// A scheduler's SIGTERM to mpirun, and a rank killed outright: either way the run folder keeps a
// checkpoint and its lock is not in the way, and `--resume` under mpirun ends with the files of
// an uninterrupted one-process run.
TEST(MpiRun, StoppedOrBrokenRunsResumeToTheUninterruptedRun) {
  const fs::path dir = codesign::test::scratch_dir("codesign_mpi_", "stop");
  codesign::test::TinyRun t = codesign::test::TinyRun::minimal();
  t.total_timesteps = 240;  // 30 iterations of 8 decisions; the signal lands after the first checkpoint
  t.exploration_end = 80;
  t.exploitation_start = 160;
  t.checkpoint_every = 24;
  std::ofstream(dir / "tiny.toml") << t.toml();
  const std::string common = "run --config " + (dir / "tiny.toml").string() + " --threads 1 --quiet --no-figures -o ";
  const RunResult ref = codesign::test::run_codesign(common + (dir / "ref").string());
  ASSERT_EQ(ref.status, 0) << ref.output;
  // The ranks on two threads each: rank 1 starts each next iteration's environments during rank
  // 0's update (MpiEnvPool::prestart), so every checkpoint is written with the next designs
  // already drawn, and the resumed run must draw them again.
  std::string ranks_common = common;
  ranks_common.replace(ranks_common.find("--threads 1"), 11, "--threads 2");
  for (const std::string how : {"sigterm", "kill_rank1"}) {
    const fs::path out = dir / how;
    const pid_t mpirun = spawn_mpi(mpi_command(2, ranks_common + out.string()), dir / (how + ".log"));
    // Rank 0 drives the training. It is held (SIGSTOP) as soon as the first checkpoint is on
    // disk and let go only once the signal has reached it, so the stop always lands mid-training
    // (with a free-running rank 0 the rest of this short run can end first). Open MPI 4.1's
    // mpirun, on SIGTERM, sends the ranks SIGCONT, waits odls_base_sigkill_timeout seconds, sends
    // SIGTERM, waits as long again, then SIGKILL (docs/cluster.md): rank 0 is held again after
    // that SIGCONT, until its SIGTERM is pending.
    const pid_t r0 = wait_for_rank(out, 0, 120);
    ASSERT_NE(r0, 0) << how << ": rank 0 of the run not found\n" << slurp(dir / (how + ".log"));
    ASSERT_TRUE(wait_for(out / "checkpoint.bin", 120)) << how << ": no checkpoint after 120 s\n"
                                                       << slurp(dir / (how + ".log"));
    ::kill(r0, SIGSTOP);
    for (int i = 0; i < 2000 && !is_stopped(r0); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (how == "sigterm") {
      ::kill(mpirun, SIGTERM);
      const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
      while (!sigterm_pending(r0) && std::chrono::steady_clock::now() < end) {
        if (!is_stopped(r0)) ::kill(r0, SIGSTOP);
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
      }
    } else {
      const pid_t r1 = wait_for_rank(out, 1, 2);
      if (r1 == 0) ::kill(r0, SIGCONT);
      ASSERT_NE(r1, 0) << "rank 1 of the run not found";
      ::kill(r1, SIGKILL);
    }
    ::kill(r0, SIGCONT);
    const int status = wait_exit(mpirun);
    const std::string log = slurp(dir / (how + ".log"));
    EXPECT_NE(status, 0) << how << "\n" << log;
    if (how == "sigterm") {
      EXPECT_NE(log.find("codesign: SIGTERM: stopped after the iteration ending at t = "), std::string::npos) << log;
      EXPECT_FALSE(fs::exists(out / ".lock")) << log;
    } else {
      EXPECT_NE(log.find("rank 1"), std::string::npos) << log;  // mpirun names the rank that died
    }
    EXPECT_FALSE(fs::exists(out / "result.toml")) << how << ": the run ended before the signal\n" << log;
    const RunResult resumed = run_mpi(2, ranks_common + out.string() + " --resume");
    ASSERT_EQ(resumed.status, 0) << how << "\n" << resumed.output;
    for (const char* f : {"policy.bin", "sampled.csv", "distribution.csv", "q_disc.csv", "episodes.csv"})
      EXPECT_EQ(slurp(out / f), slurp(dir / "ref" / f)) << f << " after " << how;
    EXPECT_EQ(without_wall(slurp(out / "result.toml")), without_wall(slurp(dir / "ref" / "result.toml"))) << how;
  }
}

TEST(MpiRun, BadRankCountsAndOtherCommandsAreOneMessage) {
  const fs::path dir = codesign::test::scratch_dir("codesign_mpi_", "bad");
  codesign::test::TinyRun t = codesign::test::TinyRun::minimal();
  std::ofstream(dir / "tiny.toml") << t.toml();
  RunResult r = run_mpi(5, "run --config " + (dir / "tiny.toml").string() + " --threads 1 --quiet -o " +
                               (dir / "five").string());
  EXPECT_NE(r.status, 0) << r.output;
  const std::string m = "codesign: error: 5 MPI ranks (mpirun -np / srun -n): codesign.designs_per_update = 4 environments cannot give "
                        "every rank one; allowed: 1 to 4 ranks";
  ASSERT_NE(r.output.find(m), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find(m), r.output.rfind(m)) << "said more than once:\n" << r.output;
  EXPECT_FALSE(fs::exists(dir / "five"));
  r = run_mpi(2, "evaluate --run " + (dir / "five").string());
  EXPECT_NE(r.status, 0) << r.output;
  const std::string m2 = "codesign: error: only `codesign run` (or the main job) and `codesign bench cluster` run on "
                         "several MPI ranks; run 'evaluate' without mpirun";
  ASSERT_NE(r.output.find(m2), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find(m2), r.output.rfind(m2)) << r.output;
}

// `bench cluster` feeds its scaling model with c, the collection of a thread with a core of its
// own. A launch with more threads than cores on rank 0's machine (2 ranks of as many threads as
// the machine has cores: always twice too many) must say that its c is a share of a core; one
// process of one thread never is, nor are 2 ranks of one thread on a machine of >= 2 cores.
TEST(MpiRun, BenchClusterSaysWhenItsRanksShareCores) {
  const fs::path dir = codesign::test::scratch_dir("codesign_mpi_", "bench");
  codesign::test::TinyRun t = codesign::test::TinyRun::minimal();
  std::ofstream(dir / "tiny.toml") << t.toml();
  const std::string bench = "bench cluster --config " + (dir / "tiny.toml").string() + " --warmup 1 --iterations 1 ";
  const std::string said = "the ranks share cores, so the model's c below is not one core's collection";
  const unsigned cores = std::thread::hardware_concurrency();
  ASSERT_GT(cores, 0u);
  RunResult r = run_mpi(2, bench + "--threads " + std::to_string(cores));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("this launch runs 2 rank(s) x " + std::to_string(cores) + " thread(s) on the " +
                          std::to_string(cores) + " cores of rank 0's machine"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find(said), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("(this launch: measured above; cores shared)"), std::string::npos) << r.output;
  // Where the core-seconds went: builds summed over the ranks, the machine's counters.
  EXPECT_NE(r.output.find("CPU in building simulators and meshing designs, every rank: "), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("the machine over the timed iterations (/proc/stat, every process): "), std::string::npos)
      << r.output;
  r = codesign::test::run_codesign(bench + "--threads 1");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output.find(said), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("(this launch: measured above)"), std::string::npos) << r.output;
  if (cores >= 2) {
    r = run_mpi(2, bench + "--threads 1");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(r.output.find(said), std::string::npos) << r.output;
  }
}

}  // namespace
