// The resolved config.toml of every shipped config, to the byte. A checkpoint's fingerprint is a
// hash of that text, so a change in how any key is read, defaulted or written would stop the run
// folders made before it from resuming. tests/data/resolved_configs/ holds the text each config
// resolved to when the file was added; a config that is not a co-design run (its tables are
// refused by the run's reader) has no file there.
//
// When a text differs or a golden file is missing, the text the code gives now is written under
// the build folder (resolved_configs_actual/) and the test fails naming it: a deliberate change of
// a resolved config is then a reviewed copy of that file, stated in CHANGELOG.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "base/errors.hpp"
#include "rl/gemm.hpp"
#include "run/codesign_tables_writer.hpp"
#include "run/run_settings.hpp"
#include "run/run_config.hpp"
#include "test_files.hpp"

namespace codesign::run {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = CODESIGN_SOURCE_DIR;
const fs::path kGolden = kSource / "tests/data/resolved_configs";

// "experiments/configs/x.toml" → "experiments__configs__x.toml".
std::string golden_name(const fs::path& config) {
  std::string name = fs::relative(config, kSource).generic_string();
  for (std::size_t p = name.find('/'); p != std::string::npos; p = name.find('/', p + 2)) name.replace(p, 1, "__");
  return name;
}

std::vector<fs::path> shipped_configs() {
  std::vector<fs::path> files;
  for (const char* dir : {"configs", "experiments/configs"})
    for (const auto& e : fs::directory_iterator(kSource / dir))
      if (e.path().extension() == ".toml") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

// The recorded text, as this build resolves it: the texts were recorded where the CPU has
// AVX-512 BF16, so matmul_precision = "auto" (the default) resolved to "bf16". No shipped config
// states "bf16" itself, so where this build has no BF16 products every "bf16" is "float32".
std::string expected_text(const fs::path& golden) {
  std::string text = test_files::slurp(golden.string());
  if (!rl::bf16_gemm_available()) {
    const std::string from = "matmul_precision = \"bf16\"", to = "matmul_precision = \"float32\"";
    for (std::size_t p = text.find(from); p != std::string::npos; p = text.find(from, p + to.size()))
      text.replace(p, from.size(), to);
  }
  return text;
}

TEST(ResolvedConfig, EveryShippedConfigResolvesToItsRecordedText) {
  const fs::path actual_dir = fs::current_path() / "resolved_configs_actual";
  int compared = 0;
  std::vector<std::string> problems;
  for (const fs::path& config : shipped_configs()) {
    const fs::path golden = kGolden / golden_name(config);
    std::string text;
    try {
      const RunConfig setup = read_run_config(config.string());
      const RunSettings s = run_settings(setup);
      text = resolved_run_config(s.spec, s.scene, s.solver, s.loop);
    } catch (const InputError&) {
      // Not a co-design run config (pendulum, the gym's tables): it must have no golden text.
      if (fs::exists(golden)) problems.push_back(config.string() + " no longer reads as a run config");
      continue;
    }
    if (fs::exists(golden) && expected_text(golden) == text) {
      ++compared;
      continue;
    }
    fs::create_directories(actual_dir);
    std::ofstream(actual_dir / golden_name(config), std::ios::binary) << text;
    problems.push_back(config.string() + (fs::exists(golden) ? " resolves to another text" : " has no golden text") +
                       " (now: " + (actual_dir / golden_name(config)).string() + ")");
  }
  for (const std::string& p : problems) ADD_FAILURE() << p;
  // Most shipped configs are co-design runs; an empty comparison would prove nothing.
  EXPECT_GE(compared, 20);
}

}  // namespace
}  // namespace codesign::run
