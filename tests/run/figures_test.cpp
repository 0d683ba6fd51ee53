// The figures' data preparation (run/figures.hpp) against hand-computed values, on a small
// synthetic run folder; bad input named and nothing overwritten; the plots/*.gp scripts drawn by
// the real gnuplot when it is installed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "base/errors.hpp"
#include "io/formats/gnuplot.hpp"
#include "run/figures.hpp"

using namespace codesign;
using namespace codesign::core;
using namespace codesign::run;
namespace fs = std::filesystem;

namespace {

// Values in the data files carry 10 significant digits (%.10g): relative error ≤ 5e-10.
constexpr double kPrinted = 1e-9;

void expect_near_all(const std::vector<double>& got, const std::vector<double>& want, double rel) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i)
    EXPECT_NEAR(got[i], want[i], rel * std::max(1.0, std::abs(want[i]))) << "index " << i;
}

// Rows of numbers of a data file; blocks (gnuplot index) separated by blank lines.
std::vector<std::vector<std::vector<double>>> read_blocks(const fs::path& p) {
  std::ifstream in(p);
  EXPECT_TRUE(in) << p;
  std::vector<std::vector<std::vector<double>>> blocks(1);
  std::string line;
  int blanks = 0;
  while (std::getline(in, line)) {
    if (line.empty()) {
      if (++blanks == 2) blocks.emplace_back();
      continue;
    }
    blanks = 0;
    if (line[0] == '#') continue;
    std::istringstream s(line);
    std::vector<double> row;
    std::string cell;
    while (s >> cell) row.push_back(std::strtod(cell.c_str(), nullptr));
    blocks.back().push_back(row);
  }
  return blocks;
}

std::vector<double> column(const std::vector<std::vector<double>>& rows, std::size_t c) {
  std::vector<double> out;
  for (const auto& r : rows) out.push_back(r.at(c));
  return out;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

class FiguresTest : public testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::path(testing::TempDir()) / ("codesign_figures_" + std::to_string(::getpid()) + "_" +
                                            testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }

  static void put(const fs::path& p, const std::string& text) {
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
  }

  // A finished co-design run: 4 updates of 2 samples, T1 = 800, T2 = 1600, d* = j21, runner-up j63.
  // Returns in sample order: 1, 3, 2, 0, 4, 6, 5, 7.
  fs::path write_run(const std::string& name, const std::string& observation = "paper") {
    const fs::path d = root_ / name;
    put(d / "config.toml", "[task]\ntarget_force_mN = 20.0\ntolerance_fraction = 0.2\nobservation = \"" + observation +
                               "\"\n[codesign]\nexploration_end = 800\nexploitation_start = 1600\nbaseline = \"none\"\n");
    put(d / "sampled.csv",
        "k,t,i,j,p1_kPa,p2_kPa,return,mu1_kPa,mu2_kPa,sigma1_kPa,sigma2_kPa\n"
        "0,400,0,21,5,0,1,10,0,5,0\n"
        "0,400,1,63,6,7,3,10,10,5,5\n"
        "1,800,0,63,6,7,2,10,10,5,5\n"
        "1,800,1,5,1,0,0,10,0,5,0\n"
        "2,1200,0,21,9,0,4,8,0,3,0\n"
        "2,1200,1,21,7,0,6,8,0,3,0\n"
        "3,1600,0,21,8.5,0,5,8.5,0,2,0\n"
        "3,1600,1,21,8.5,0,7,8.5,0,2,0\n");
    put(d / "distribution.csv",
        "k,t,phase,beta,entropy,top1_j,top1_q,top2_j,top2_q,top3_j,top3_q,best_j,best_score,best_mu1_kPa,"
        "best_mu2_kPa,best_sigma1_kPa,best_sigma2_kPa\n"
        "0,400,exploration,0,4.7,0,0.01,1,0.01,2,0.01,63,3,10,10,5,5\n"
        "1,800,transition,0,4.7,63,0.02,21,0.02,5,0.01,63,3,10,10,5,5\n"
        "2,1200,transition,0.2,4.6,21,0.03,63,0.02,5,0.01,21,5,8,0,3,0\n"
        "3,1600,exploitation,0.5,4.5,21,0.04,63,0.02,5,0.01,21,5,8.5,0,2,0\n");
    put(d / "result.toml",
        "[best]\ndesign = 21\nn = 1\nl_mm = 28\nw_mm = 2.5\npressures_kPa = [8.5, 0]\ntest_return = 12.5\n"
        "[runner_up]\ndesign = 63\nn = 2\nl_mm = 22\nw_mm = 3.5\npressures_kPa = [10, 10]\ntest_return = 3.25\n"
        "[run]\ntimesteps = 1600\n");
    const double deg = std::numbers::pi / 180.0;
    std::ostringstream trace;
    trace.precision(17);
    trace << "decision,t_s,theta_rad,F_mN,strain,tip_x_mm,tip_y_mm,tip_z_mm,plate_z_mm,action\n"
          << "0,0,0,22,0.01,87,0,-49,-51,0\n"
          << "0,0.01," << 1.0 * deg << ",21,0.01,87,0,-49,-51,0.1\n"
          << "0,0.02," << -2.0 * deg << ",19.5,0.01,87,0,-49,-51,0.1\n";
    put(d / "eval" / "best_trace.csv", trace.str());
    put(d / "eval" / "runner_up_trace.csv", trace.str());
    put(d / "eval" / "best.csv", "episode,phase_rad,return,decisions,band_fraction,reason\n0,0.03,12.5,50,0.9,time_limit\n");
    put(d / "eval" / "runner_up.csv", "episode,phase_rad,return,decisions,band_fraction,reason\n0,0.03,3.25,50,0.4,time_limit\n");
    return d;
  }

  FigureOptions options(const fs::path& run) const {
    FigureOptions o;
    o.run_dir = run.string();
    o.plots_dir = std::string(CODESIGN_SOURCE_DIR) + "/plots";
    o.window = 3;
    o.bins = 3;
    return o;
  }

  fs::path root_;
};

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST(FigureData, TrailingMeanByHand) {
  const std::vector<double> x{1, 3, 2, 0, 4, 6, 5, 7};
  expect_near_all(trailing_mean(x, 3), {1, 2, 2, 5.0 / 3, 2, 10.0 / 3, 5, 6}, 1e-15);
  expect_near_all(trailing_mean(x, 1), x, 0.0);
  expect_near_all(trailing_mean(x, 100), {1, 2, 2, 1.5, 2, 16.0 / 6, 21.0 / 7, 28.0 / 8}, 1e-15);
  EXPECT_TRUE(trailing_mean({}, 5).empty());
  // A long series against the direct sum: the running sum is re-summed every window, so the
  // error stays at a few ulps of the window's sum (bound: 4 * window * eps * max|x|).
  std::vector<double> y;
  for (int i = 0; i < 5000; ++i) y.push_back(1e6 * std::sin(0.37 * i) + 0.001 * i);
  const std::vector<double> m = trailing_mean(y, 100);
  for (std::size_t i = 0; i < y.size(); ++i) {
    const std::size_t first = i >= 99 ? i - 99 : 0;
    double s = 0;
    for (std::size_t k = first; k <= i; ++k) s += y[k];
    ASSERT_NEAR(m[i], s / static_cast<double>(i - first + 1), 4 * 100 * 2.2e-16 * 1e6) << i;
  }
}

TEST(FigureData, RunningMaxPhasesAndHistogramByHand) {
  EXPECT_EQ(running_max({3, 1, 4, 1, 5, -9}), (std::vector<double>{3, 3, 4, 4, 5, 5}));
  EXPECT_EQ(last_of_each_run({5, 5, 7, 7, 7, 9}), (std::vector<std::size_t>{1, 4, 5}));
  EXPECT_EQ(last_of_each_run({4}), (std::vector<std::size_t>{0}));
  EXPECT_TRUE(last_of_each_run({}).empty());
  EXPECT_TRUE(running_max({}).empty());

  auto spans = phase_spans(220000, 800000, 1000000);
  ASSERT_EQ(spans.size(), 3u);
  EXPECT_EQ(spans[0].name, "exploration");
  EXPECT_EQ(spans[0].end, 220000);
  EXPECT_EQ(spans[1].start, 220000);
  EXPECT_EQ(spans[1].end, 800000);
  EXPECT_EQ(spans[2].name, "exploitation");
  EXPECT_EQ(spans[2].end, 1000000);
  spans = phase_spans(8000, 20000, 12000);  // the run ends inside the transition
  ASSERT_EQ(spans.size(), 2u);
  EXPECT_EQ(spans[1].name, "transition");
  EXPECT_EQ(spans[1].end, 12000);
  spans = phase_spans(0, 100, 50);  // no exploration at all
  ASSERT_EQ(spans.size(), 1u);
  EXPECT_EQ(spans[0].name, "transition");
  EXPECT_EQ(spans[0].start, 0);

  // Bins [1,3), [3,5), [5,7]: 5 falls in the third bin, 7 (the maximum) too.
  Histogram h = histogram({{1, 4, 6, 5, 7}, {3, 2}, {}}, 3);
  EXPECT_EQ(h.edges, (std::vector<double>{1, 3, 5, 7}));
  expect_near_all(h.fractions[0], {0.2, 0.2, 0.6}, 1e-15);
  expect_near_all(h.fractions[1], {0.5, 0.5, 0.0}, 1e-15);
  expect_near_all(h.fractions[2], {0, 0, 0}, 0.0);
  // One distinct value: one bin of width 1 around it.
  h = histogram({{2.5, 2.5}}, 10);
  EXPECT_EQ(h.edges, (std::vector<double>{2.0, 3.0}));
  EXPECT_EQ(h.fractions[0], (std::vector<double>{1.0}));
  // Values on edges that rounding puts near a boundary land in the bin whose edges hold them.
  const std::vector<double> tenths{0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7};
  h = histogram({tenths}, 7);
  for (std::size_t b = 0; b < 7; ++b) EXPECT_NEAR(h.fractions[0][b], b == 6 ? 2.0 / 8 : 1.0 / 8, 1e-15) << b;
}

TEST_F(FiguresTest, DataFilesHoldTheHandComputedValues) {
  const fs::path run = write_run("run");
  const fs::path other = write_run("nofb", "no_feedback");
  FigureOptions o = options(run);
  o.compare = {{"no_feedback", other.string()}};
  const PreparedFigures p = prepare_figures(o);
  ASSERT_EQ(p.figures.size(), 5u);
  for (const auto& [f, call] : p.figures) EXPECT_TRUE(call.has_value()) << f.name << ": " << f.message;
  const fs::path data = run / "figures" / "data";

  // fig2a: every sample (t, k, j, return); per update (after its last sample) the moving mean
  // over 3 samples and the best so far: samples 1, 3 | 2, 0 | 4, 6 | 5, 7.
  auto rows = read_blocks(data / "fig2a_samples.dat").at(0);
  ASSERT_EQ(rows.size(), 8u);
  expect_near_all(column(rows, 0), {400, 400, 800, 800, 1200, 1200, 1600, 1600}, 0.0);
  expect_near_all(column(rows, 2), {21, 63, 63, 5, 21, 21, 21, 21}, 0.0);
  expect_near_all(column(rows, 3), {1, 3, 2, 0, 4, 6, 5, 7}, 0.0);
  rows = read_blocks(data / "fig2a_curves.dat").at(0);
  expect_near_all(column(rows, 0), {400, 800, 1200, 1600}, 0.0);
  expect_near_all(column(rows, 1), {2, 5.0 / 3, 10.0 / 3, 6}, kPrinted);
  expect_near_all(column(rows, 2), {3, 3, 6, 7}, kPrinted);
  // d*'s own samples (j21): returns 1 | 4, 6 | 5, 7; running mean over 3 after each of its updates.
  rows = read_blocks(data / "fig2a_dstar.dat").at(0);
  expect_near_all(column(rows, 0), {400, 1200, 1600}, 0.0);
  expect_near_all(column(rows, 1), {1, 11.0 / 3, 6}, kPrinted);
  // Phases: T1 = 800 inside the run, T2 = 1600 = its last timestep (zero-length exploitation).
  EXPECT_EQ(read_text(data / "fig2a_phases.dat").substr(read_text(data / "fig2a_phases.dat").find('\n') + 1),
            "exploration 0 800\ntransition 800 1600\n");
  const io::GnuplotCall& a = *p.figures[0].second;
  std::map<std::string, std::string> vars;
  for (const auto& v : a.variables) vars[v.name] = v.value;
  EXPECT_EQ(vars["t_transition"], "800");
  EXPECT_EQ(vars["t_exploitation"], "-1");
  EXPECT_EQ(vars["t_end"], "1600");
  EXPECT_EQ(vars["dstar_label"], "d* = j21 {1, 28 mm, 2.5 mm}");

  // fig2b: from d*'s first sample (k = 0), carried forward through k = 1, then 8/3, then 8.5/2.
  rows = read_blocks(data / "fig2b.dat").at(0);
  ASSERT_EQ(rows.size(), 4u);
  expect_near_all(column(rows, 0), {0, 1, 2, 3}, 0.0);
  expect_near_all(column(rows, 2), {10, 10, 8, 8.5}, kPrinted);
  expect_near_all(column(rows, 3), {5, 5, 3, 2}, kPrinted);
  vars.clear();
  for (const auto& v : p.figures[1].second->variables) vars[v.name] = v.value;
  EXPECT_EQ(vars["k_transition"], "1");
  EXPECT_EQ(vars["k_exploitation"], "3");
  EXPECT_EQ(vars["chambers"], "1");
  EXPECT_EQ(vars["p_star1"], "8.5");

  // fig2c: d* returns {1, 4, 6, 5, 7}, runner-up j63 {3, 2}; bins [1,3), [3,5), [5,7].
  const auto blocks = read_blocks(data / "fig2c_rewards.dat");
  ASSERT_EQ(blocks.size(), 2u);
  expect_near_all(column(blocks[0], 0), {1, 4, 6, 5, 7}, 0.0);
  expect_near_all(column(blocks[1], 0), {3, 2}, 0.0);
  rows = read_blocks(data / "fig2c_hist.dat").at(0);
  ASSERT_EQ(rows.size(), 3u);
  expect_near_all(column(rows, 2), {2, 4, 6}, kPrinted);
  expect_near_all(column(rows, 3), {0.2, 0.2, 0.6}, kPrinted);
  expect_near_all(column(rows, 4), {0.5, 0.5, 0}, kPrinted);

  // fig2d: one block per run, the same moving mean (the comparison run has the same returns).
  const auto runs = read_blocks(data / "fig2d.dat");
  ASSERT_EQ(runs.size(), 2u);
  expect_near_all(column(runs[1], 0), {400, 800, 1200, 1600}, 0.0);
  expect_near_all(column(runs[1], 1), {2, 5.0 / 3, 10.0 / 3, 6}, kPrinted);
  vars.clear();
  for (const auto& v : p.figures[3].second->variables) vars[v.name] = v.value;
  EXPECT_EQ(vars["label0"], "co-design");
  EXPECT_EQ(vars["label1"], "no_feedback");

  // fig3: d*, runner-up, and the no-feedback run's d*; θ in degrees; band 16..24 mN.
  const auto curves = read_blocks(data / "fig3.dat");
  ASSERT_EQ(curves.size(), 3u);
  expect_near_all(column(curves[0], 2), {0, 1, -2}, kPrinted);
  expect_near_all(column(curves[2], 1), {22, 21, 19.5}, kPrinted);
  vars.clear();
  for (const auto& v : p.figures[4].second->variables) vars[v.name] = v.value;
  EXPECT_EQ(vars["band_lo_mN"], "16");
  EXPECT_EQ(vars["band_hi_mN"], "24");
  EXPECT_EQ(vars["label0"], "d* j21 {1, 28 mm, 2.5 mm}, p = 8.500 kPa: return 12.50");
  EXPECT_EQ(vars["label1"], "runner-up j63 {2, 22 mm, 3.5 mm}, p = (10.000, 10.000) kPa: return 3.25");
  EXPECT_EQ(vars["label2"].rfind("no_feedback: d* j21", 0), 0u);

  // The command list names every script with its variables, shell-quoted.
  const std::string commands = read_text(run / "figures" / "gnuplot_commands.txt");
  EXPECT_NE(commands.find("fig3.gp'"), std::string::npos);
  EXPECT_NE(commands.find("'-e' 'plotsdir = "), std::string::npos);
}

TEST_F(FiguresTest, RunInProgressGivesTheFiguresItsDataAllows) {
  const fs::path run = write_run("live");
  fs::remove(run / "result.toml");
  fs::remove_all(run / "eval");
  const PreparedFigures p = prepare_figures(options(run));
  // d* = the last update's best design (j21); runner-up = first other design of its top-3 (j63).
  EXPECT_TRUE(p.figures[0].second.has_value());
  EXPECT_TRUE(p.figures[2].second.has_value());
  EXPECT_EQ(p.figures[2].second->variables.back().value.rfind("runner-up j63", 0), 0u);
  EXPECT_FALSE(p.figures[4].second.has_value());
  EXPECT_NE(p.figures[4].first.message.find("no evaluation traces"), std::string::npos);
}

TEST_F(FiguresTest, BadInputIsNamedAndLeavesEarlierFiguresAlone) {
  const fs::path run = write_run("bad");
  put(run / "figures" / "data" / "fig2a_samples.dat", "earlier\n");
  const std::string sampled = (run / "sampled.csv").string();
  std::string text = read_text(sampled);
  text.replace(text.find(",3,10,10,5,5"), 12, ",x,10,10,5,5");
  put(sampled, text);
  EXPECT_EQ(error_of([&] { prepare_figures(options(run)); }),
            sampled + ": line 3, column 'return': 'x' is not a finite number");
  EXPECT_EQ(read_text(run / "figures" / "data" / "fig2a_samples.dat"), "earlier\n");
  EXPECT_FALSE(fs::exists(run / "figures" / "gnuplot_commands.txt"));

  put(sampled, "k,t,i,j,p1_kPa,p2_kPa,return,mu1_kPa,mu2_kPa,sigma1_kPa,sigma2_kPa\n0,400,0,110,5,0,1,10,0,5,0\n");
  EXPECT_EQ(error_of([&] { prepare_figures(options(run)); }),
            sampled + ": line 2, column 'j': design 110 is out of range; allowed [0, 109]");
  put(sampled, "k,t,i,j,p1_kPa,p2_kPa,return,mu1_kPa,mu2_kPa,sigma1_kPa,sigma2_kPa\n");
  EXPECT_NE(error_of([&] { prepare_figures(options(run)); }).find("sampled.csv: no sampled designs yet"),
            std::string::npos);
  fs::remove(sampled);
  EXPECT_NE(error_of([&] { prepare_figures(options(run)); }).find("sampled.csv: cannot open"), std::string::npos);

  EXPECT_EQ(error_of([&] { prepare_figures(options(root_ / "absent")); }),
            (root_ / "absent").string() + ": no such run folder");
  FigureOptions o = options(write_run("ok"));
  o.plots_dir = (root_ / "noplots").string();
  EXPECT_NE(error_of([&] { prepare_figures(o); }).find("noplots/fig2a.gp: gnuplot script missing"), std::string::npos);
  o = options(write_run("ok2"));
  o.compare = {{"a b", (root_ / "ok").string()}};
  EXPECT_NE(error_of([&] { prepare_figures(o); }).find("--compare label 'a b' is not allowed"), std::string::npos);
  o.compare = {{"nofb", (root_ / "missing_run").string()}};
  EXPECT_NE(error_of([&] { prepare_figures(o); }).find("missing_run: no such run folder"), std::string::npos);
  EXPECT_FALSE(fs::exists(root_ / "ok2" / "figures"));
}

TEST_F(FiguresTest, MissingGnuplotIsReportedNotThrown) {
  const fs::path run = write_run("nognuplot");
  FigureOptions o = options(run);
  o.gnuplot = (root_ / "no_gnuplot_here").string();
  const FiguresReport r = make_figures(o);
  EXPECT_TRUE(r.gnuplot_missing);
  EXPECT_EQ(r.drawn(), 0u);
  ASSERT_EQ(r.figures.size(), 5u);
  EXPECT_NE(r.figures[0].message.find("gnuplot not found"), std::string::npos);
  EXPECT_TRUE(fs::exists(run / "figures" / "data" / "fig2a_samples.dat"));
  EXPECT_FALSE(fs::exists(run / "figures" / "fig2a.png"));
}

// The scripts in plots/ draw every figure from the synthetic data: PNG files of the size the
// scripts set (1100 x 650, Fig. 3 1100 x 800), read from the PNG header.
TEST_F(FiguresTest, ScriptsDrawEveryFigureWithGnuplot) {
  if (!io::gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  const fs::path run = write_run("drawn");
  const fs::path other = write_run("nofb", "no_feedback");
  FigureOptions o = options(run);
  o.compare = {{"no_feedback", other.string()}};
  const FiguresReport r = make_figures(o);
  EXPECT_FALSE(r.gnuplot_missing);
  for (const FigureOutcome& f : r.figures) {
    EXPECT_TRUE(f.drawn) << f.name << ": " << f.message;
    std::ifstream in(f.png, std::ios::binary);
    unsigned char h[24] = {};
    in.read(reinterpret_cast<char*>(h), sizeof h);
    ASSERT_TRUE(in) << f.png;
    EXPECT_EQ(std::string(reinterpret_cast<char*>(h + 1), 3), "PNG") << f.png;
    const std::uint32_t w = (h[16] << 24) | (h[17] << 16) | (h[18] << 8) | h[19];
    const std::uint32_t ht = (h[20] << 24) | (h[21] << 16) | (h[22] << 8) | h[23];
    EXPECT_EQ(w, 1100u) << f.png;
    EXPECT_EQ(ht, f.name == "fig3" ? 800u : 650u) << f.png;
    EXPECT_FALSE(fs::exists(f.png + ".tmp"));
  }
}
