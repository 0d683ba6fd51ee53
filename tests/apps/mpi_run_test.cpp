// `mpirun -np N codesign run` (issue 20 §1, docs/cluster.md): the same run folder as one process,
// file for file (wall-clock fields aside), on 2 and 3 ranks of a 4-environment tiny run; bad rank
// counts and other commands under mpirun are one message and exit 2. Open MPI is pinned to this
// machine: shared memory between the ranks (btl self,vader) and its own control channel on the
// loopback interface only.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <array>
#include <cstdio>
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

RunResult run_mpi(int ranks, const std::string& args) {
  // Open MPI refuses root unless told; CI containers run as root.
  const std::string cmd = std::string("OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 ") + CODESIGN_MPIEXEC +
                          " -np " + std::to_string(ranks) +
                          " --oversubscribe --mca btl self,vader --mca oob_tcp_if_include lo " + CODESIGN_BINARY + " " +
                          args + " 2>&1";
  RunResult r;
  FILE* p = popen(cmd.c_str(), "r");
  if (p == nullptr) return r;
  std::array<char, 4096> buf;
  while (std::fgets(buf.data(), buf.size(), p) != nullptr) r.output += buf.data();
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

TEST(MpiRun, TwoAndThreeRanksWriteTheRunFolderOfOneProcess) {
  const fs::path dir = codesign::test::scratch_dir("codesign_mpi_", "same");
  // 4 environments of 2 decisions, 12 iterations through every phase of Algorithm 2, a checkpoint
  // every 2 iterations: short, but every call of the rollout interface crosses the ranks.
  codesign::test::TinyRun t = codesign::test::TinyRun::minimal();
  t.total_timesteps = 96;
  t.exploration_end = 32;
  t.exploitation_start = 64;
  t.checkpoint_every = 16;
  std::ofstream(dir / "tiny.toml") << t.toml();
  const std::string common = "run --config " + (dir / "tiny.toml").string() + " --threads 1 --quiet --no-figures -o ";
  RunResult one = codesign::test::run_codesign(common + (dir / "one").string());
  ASSERT_EQ(one.status, 0) << one.output;
  for (int ranks : {2, 3}) {
    const fs::path out = dir / ("ranks" + std::to_string(ranks));
    const RunResult r = run_mpi(ranks, common + out.string());
    ASSERT_EQ(r.status, 0) << r.output;
    for (const char* f : {"policy.bin", "sampled.csv", "distribution.csv", "q_disc.csv", "episodes.csv"})
      EXPECT_EQ(slurp(out / f), slurp(dir / "one" / f)) << f << " on " << ranks << " ranks";
    EXPECT_EQ(without_wall(slurp(out / "result.toml")), without_wall(slurp(dir / "one" / "result.toml")))
        << ranks << " ranks";
    EXPECT_FALSE(fs::exists(out / ".lock"));
  }
}

TEST(MpiRun, BadRankCountsAndOtherCommandsAreOneMessage) {
  const fs::path dir = codesign::test::scratch_dir("codesign_mpi_", "bad");
  codesign::test::TinyRun t = codesign::test::TinyRun::minimal();
  std::ofstream(dir / "tiny.toml") << t.toml();
  RunResult r = run_mpi(5, "run --config " + (dir / "tiny.toml").string() + " --threads 1 --quiet -o " +
                               (dir / "five").string());
  EXPECT_NE(r.status, 0) << r.output;
  const std::string m = "codesign: error: mpirun -np 5: codesign.designs_per_update = 4 environments cannot give "
                        "every rank one; allowed: 1 to 4 ranks";
  ASSERT_NE(r.output.find(m), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find(m), r.output.rfind(m)) << "said more than once:\n" << r.output;
  EXPECT_FALSE(fs::exists(dir / "five"));
  r = run_mpi(2, "evaluate --run " + (dir / "five").string());
  EXPECT_NE(r.status, 0) << r.output;
  const std::string m2 = "codesign: error: only `codesign run` (or the main job) runs on several MPI ranks; run "
                         "'evaluate' without mpirun";
  ASSERT_NE(r.output.find(m2), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find(m2), r.output.rfind(m2)) << r.output;
}

}  // namespace
