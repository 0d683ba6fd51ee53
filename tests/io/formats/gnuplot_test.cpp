// io::run_gnuplot: argument vector and quoting, validation, a missing executable, a failing
// script, and (when gnuplot is installed) values arriving in the script literally.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/stat.h>
#include <unistd.h>

#include "base/errors.hpp"
#include "io/formats/gnuplot.hpp"

using namespace codesign;
namespace fs = std::filesystem;

namespace {

// A fresh folder per test, removed at the end.
class GnuplotTest : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(testing::TempDir()) /
           ("codesign_gnuplot_" + std::to_string(::getpid()) + "_" +
            testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text, bool executable = false) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    if (executable) ::chmod(p.c_str(), 0755);
    return p.string();
  }
  static std::string read(const std::string& path) {
    std::ifstream in(path);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }

  fs::path dir_;
};

const std::string kHostile = "a'; system('touch pwned'); b = '\"$(touch pwned2)\" `x` \\n";

}  // namespace

TEST_F(GnuplotTest, ArgumentsQuoteStringsAndFormatNumbers) {
  io::GnuplotCall call;
  call.script = write("s.gp", "");
  call.set("out", "it's.png");
  call.set("t1", 220000.0);
  call.set("x", 0.1);
  const std::vector<std::string> args = call.arguments();
  ASSERT_EQ(args.size(), 4u);
  EXPECT_EQ(args[0], "gnuplot");
  EXPECT_EQ(args[1], "-e");
  EXPECT_EQ(args[2], "out = 'it''s.png'; t1 = 220000; x = 0.10000000000000001");
  EXPECT_EQ(args[3], call.script);

  io::GnuplotCall bare;
  bare.script = call.script;
  EXPECT_EQ(bare.arguments(), (std::vector<std::string>{"gnuplot", call.script}));
}

TEST_F(GnuplotTest, ValidationNamesTheProblem) {
  const std::string script = write("s.gp", "");
  auto message_of = [](const io::GnuplotCall& c) {
    try {
      c.validate();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  io::GnuplotCall ok;
  ok.script = script;
  ok.set("a_1", "x");
  EXPECT_EQ(message_of(ok), "no error");

  io::GnuplotCall missing;
  missing.script = (dir_ / "absent.gp").string();
  EXPECT_NE(message_of(missing).find("absent.gp: cannot read the gnuplot script"), std::string::npos);

  io::GnuplotCall bad_name;
  bad_name.script = script;
  bad_name.set("1x", "v");
  EXPECT_NE(message_of(bad_name).find("variable name '1x' is not allowed"), std::string::npos);
  io::GnuplotCall injected_name;
  injected_name.script = script;
  injected_name.set("a=1;system('x')", "v");
  EXPECT_NE(message_of(injected_name).find("is not allowed"), std::string::npos);

  io::GnuplotCall twice;
  twice.script = script;
  twice.set("a", "v");
  twice.set("a", 1.0);
  EXPECT_NE(message_of(twice).find("variable a is set twice"), std::string::npos);

  io::GnuplotCall newline;
  newline.script = script;
  newline.set("a", "x\nsystem('touch y')");
  EXPECT_NE(message_of(newline).find("control character"), std::string::npos);

  io::GnuplotCall number;
  number.script = script;
  EXPECT_THROW(number.set("a", std::nan("")), InputError);
  number.variables.push_back({"b", "1; system('x')", false});
  EXPECT_NE(message_of(number).find("is not a finite number"), std::string::npos);
}

// The child gets exactly the argument vector (no shell in between): a stand-in executable
// prints its arguments one per line, and the hostile value arrives whole and quoted.
TEST_F(GnuplotTest, ChildReceivesTheArgumentVectorWithoutAShell) {
  io::GnuplotCall call;
  call.executable = write("fake_gnuplot", "#!/bin/sh\nfor a in \"$@\"; do printf '[%s]\\n' \"$a\"; done\n", true);
  call.script = write("s.gp", "");
  call.set("name", kHostile);
  const io::GnuplotOutcome r = io::run_gnuplot(call);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r.exit_code, 0);
  std::string quoted;  // gnuplot's single-quoted form: every ' doubled
  for (const char c : kHostile) quoted += c == '\'' ? std::string("''") : std::string(1, c);
  EXPECT_EQ(r.output, "[-e]\n[name = '" + quoted + "']\n[" + call.script + "]\n");
  EXPECT_FALSE(fs::exists("pwned"));
  EXPECT_FALSE(fs::exists("pwned2"));
}

TEST_F(GnuplotTest, MissingExecutableIsNotFoundAndFailingScriptIsFailed) {
  io::GnuplotCall call;
  call.script = write("s.gp", "");
  call.executable = (dir_ / "no_such_gnuplot").string();
  EXPECT_FALSE(io::gnuplot_available(call.executable));
  io::GnuplotOutcome r = io::run_gnuplot(call);
  EXPECT_EQ(r.status, io::GnuplotOutcome::Status::not_found);
  EXPECT_NE(r.message().find("gnuplot not found"), std::string::npos);

  call.executable = "codesign_no_such_program_on_path";
  EXPECT_FALSE(io::gnuplot_available(call.executable));
  EXPECT_EQ(io::run_gnuplot(call).status, io::GnuplotOutcome::Status::not_found);

  // A stand-in that reports an error and exits with status 3.
  call.executable = write("failing", "#!/bin/sh\necho 'line 7: undefined variable: foo' >&2\nexit 3\n", true);
  EXPECT_TRUE(io::gnuplot_available(call.executable));
  r = io::run_gnuplot(call);
  EXPECT_EQ(r.status, io::GnuplotOutcome::Status::failed);
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_EQ(r.message(), "gnuplot failed on " + call.script +
                             " (exit status 3): line 7: undefined variable: foo");
}

// With the real gnuplot: the script sees the values as set, the hostile one literally.
TEST_F(GnuplotTest, RealGnuplotSeesTheValues) {
  if (!io::gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  const std::string out = (dir_ / "printed.txt").string();
  io::GnuplotCall call;
  call.script = write("print.gp", "set print outfile\nprint name\nprint sprintf('%.6f', t1 * 2)\n");
  call.set("outfile", out);
  call.set("name", kHostile);
  call.set("t1", 1.25);
  const io::GnuplotOutcome r = io::run_gnuplot(call);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(read(out), kHostile + "\n2.500000\n");
  EXPECT_FALSE(fs::exists("pwned"));
  EXPECT_FALSE(fs::exists(dir_ / "pwned"));

  io::GnuplotCall broken;
  broken.script = write("broken.gp", "plot undefined_thing_xyz(x)\n");
  const io::GnuplotOutcome b = io::run_gnuplot(broken);
  EXPECT_EQ(b.status, io::GnuplotOutcome::Status::failed);
  EXPECT_NE(b.exit_code, 0);
  EXPECT_NE(b.message().find("broken.gp"), std::string::npos);
}
