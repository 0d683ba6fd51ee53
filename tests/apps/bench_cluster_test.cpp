// `codesign bench cluster` in one process on a recurrent policy: its spread update is priced from
// minibatches of whole sequences (apps/bench/bench_cluster.cpp), not taken as u / N.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "run_binary.hpp"
#include "tiny_run.hpp"

namespace {

// The minimal tiny run with a GRU: 4 environments of 2 decisions, batch_size 4, so a minibatch
// holds 4 / 2 = 2 sequences; on N = 2 and 4 ranks the busiest rank's share is one sequence.
TEST(BenchCluster, PricesTheRecurrentSpreadUpdateBySequences) {
  const std::filesystem::path dir = codesign::test::scratch_dir("codesign_bench_", "gru");
  std::string toml = codesign::test::TinyRun::minimal().toml();
  const std::string ppo = "[ppo]\n";
  ASSERT_NE(toml.find(ppo), std::string::npos);
  toml.replace(toml.find(ppo), ppo.size(), ppo + "policy = \"gru\"\ngru_hidden = 4\n");
  std::ofstream(dir / "gru.toml") << toml;
  const codesign::test::RunResult r = codesign::test::run_codesign(
      "bench cluster --config " + (dir / "gru.toml").string() + " --warmup 1 --iterations 1 --threads 1");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("one minibatch's loss and gradient on one thread, 2 sequences of 2 decisions: "),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find(" N = 2 (1 sequence(s)) "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(" N = 4 (1 sequence(s)) "), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("not measured: e = 1"), std::string::npos) << r.output;
}

// --from-run: a finished run's ppo.csv projected iteration by iteration (the arithmetic is
// ScalingModel.AWholeRunIsProjectedIterationByIteration's); a folder without one is one message
// naming the file, exit 2, before any iteration.
TEST(BenchCluster, ProjectsAWholeRunFromItsPpoCsv) {
  const std::filesystem::path dir = codesign::test::scratch_dir("codesign_bench_", "from_run");
  std::ofstream(dir / "tiny.toml") << codesign::test::TinyRun::minimal().toml();
  std::filesystem::create_directories(dir / "run");
  std::ofstream(dir / "run" / "ppo.csv") << "k,collect_s,policy_s,update_s\n0,4.2,0.2,0.1\n1,2.2,0.2,0.5\n";
  const std::string bench = "bench cluster --config " + (dir / "tiny.toml").string() + " --warmup 1 --iterations 1 --threads 2 --from-run ";
  const codesign::test::RunResult r = codesign::test::run_codesign(bench + (dir / "run").string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("fed with the whole run (2 iterations, --from-run): "), std::string::npos) << r.output;
  const codesign::test::RunResult bad = codesign::test::run_codesign(bench + (dir / "none").string());
  EXPECT_EQ(bad.status, 2) << bad.output;
  EXPECT_NE(bad.output.find((dir / "none" / "ppo.csv").string()), std::string::npos) << bad.output;
  EXPECT_EQ(bad.output.find("bench cluster: measured"), std::string::npos) << bad.output;
}

}  // namespace
