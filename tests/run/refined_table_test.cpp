// The [refined] table of `codesign refine`: appended to result.toml with every earlier byte kept,
// an earlier [refined] table replaced (idempotent), readable as TOML.
#include <gtest/gtest.h>

#include "core/refine.hpp"
#include "io/config/toml_reader.hpp"
#include "run/run_folder.hpp"

namespace codesign::run {
namespace {

using core::RefineResult;

const char* kResult =
    "# codesign result: d* and the runner-up\n\n"
    "[best]\ndesign = 21\nn = 1\npressures_kPa = [0.069000000000000006, 0]\ntest_return = 4.58   # mean\n\n"
    "[run]\ntimesteps = 100000\nwall_s = 356.2   # wall-clock\n";

RefineResult sample_result() {
  RefineResult r;
  r.design = 21;
  r.p_before = {0.069, 0.0};
  r.p_after = {1.25, 0.0};
  r.tuning_before = 4.0;
  r.tuning_after = 4.5;
  r.evaluations = 21;
  r.test_before.returns = {4.5, 4.7};
  r.test_before.mean_return = 4.6;
  r.test_before.std_return = 0.1;
  r.test_after.returns = {4.8, 5.0};
  r.test_after.mean_return = 4.9;
  r.test_after.std_return = 0.1;
  r.test_after.mean_band_fraction = 0.3;
  return r;
}

TEST(RefinedTable, IsAppendedWithEveryEarlierByteKept) {
  const std::string out = with_refined_table(kResult, sample_result());
  ASSERT_GT(out.size(), std::string(kResult).size());
  EXPECT_EQ(out.substr(0, std::string(kResult).size()), kResult);
  EXPECT_EQ(out.substr(std::string(kResult).size(), 10), "\n[refined]");
  // Applied again (a second refine): the same text, not a second table.
  EXPECT_EQ(with_refined_table(out, sample_result()), out);
  // A changed result replaces the table.
  RefineResult other = sample_result();
  other.p_after = {2.5, 0.0};
  const std::string out2 = with_refined_table(out, other);
  EXPECT_EQ(out2.substr(0, std::string(kResult).size()), kResult);
  EXPECT_EQ(out2, with_refined_table(kResult, other));
  // The result reads as TOML, the other tables untouched.
  io::TableReader root = io::TableReader::from_string(out2, "result.toml");
  io::TableReader refined = root.table("refined");
  EXPECT_EQ(refined.integer("design", -1, 0, 109), 21);
  EXPECT_EQ(refined.numbers("pressures_kPa", {}, 0, 20, 2, 2), (std::vector<double>{2.5, 0.0}));
  EXPECT_EQ(refined.numbers("pressures_kPa_before", {}, 0, 20, 2, 2), (std::vector<double>{0.069, 0.0}));
  EXPECT_EQ(root.table("best").integer("design", -1, 0, 109), 21);
  // A file without a final newline gets one before the table; nothing else changes.
  const std::string cut = std::string(kResult).substr(0, std::string(kResult).size() - 1);
  EXPECT_EQ(with_refined_table(cut, sample_result()).substr(0, cut.size()), cut);
}

}  // namespace
}  // namespace codesign::run
