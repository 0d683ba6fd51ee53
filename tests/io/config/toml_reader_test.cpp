// The config reader must turn every malformed input into one message that names the file,
// the dotted key and the allowed range, and must never let a misspelt key pass silently.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "io/config/toml_reader.hpp"

namespace codesign::io {
namespace {

std::string error_of(const std::string& text, void (*read)(TableReader&)) {
  try {
    TableReader r = TableReader::from_string(text, "run.toml");
    read(r);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(TomlReader, ReadsValuesAndDefaults) {
  TableReader r = TableReader::from_string(
      "name = \"x\"\n[material]\nE_kPa = 500\nnu = 0.4\nsizes = [512, 512]\n", "run.toml");
  TableReader m = r.table("material");
  EXPECT_DOUBLE_EQ(m.number("E_kPa", 1.0, 1.0, 1e5), 500.0);  // integer accepted as number
  EXPECT_DOUBLE_EQ(m.number("nu", 0.3, 0.0, 0.499), 0.4);
  EXPECT_DOUBLE_EQ(m.number("rho", 1.5, 0.0, 10.0), 1.5);      // absent -> default
  EXPECT_EQ(m.integers("sizes", {}, 1, 4096, 1, 8).size(), 2u);
  EXPECT_EQ(r.string("name", "", {"x", "y"}), "x");
  EXPECT_NO_THROW(m.finish());
  EXPECT_NO_THROW(r.finish());
}

TEST(TomlReader, AbsentTableGivesDefaults) {
  TableReader r = TableReader::from_string("", "run.toml");
  TableReader t = r.table("ppo");
  EXPECT_EQ(t.integer("n_steps", 50, 1, 100000), 50);
  EXPECT_FALSE(t.has("n_steps"));
}

TEST(TomlReader, OutOfRangeNamesFileKeyAndRange) {
  const std::string msg = error_of("[material]\nnu = 0.6\n", [](TableReader& r) {
    r.table("material").number("nu", 0.4, 0.0, 0.499);
  });
  EXPECT_EQ(msg, "run.toml: material.nu: value 0.6 is out of range; allowed [0, 0.499]");
}

TEST(TomlReader, WrongTypeIsReported) {
  const std::string msg = error_of("steps = \"ten\"\n", [](TableReader& r) {
    r.integer("steps", 1, 1, 10);
  });
  EXPECT_EQ(msg, "run.toml: steps: expected an integer in [1, 10], got a string");
  const std::string frac = error_of("steps = 2.5\n", [](TableReader& r) {
    r.integer("steps", 1, 1, 10);
  });
  EXPECT_EQ(frac, "run.toml: steps: expected an integer in [1, 10], got a number");
}

TEST(TomlReader, UnknownKeyIsRejectedWithAllowedList) {
  const std::string msg = error_of("[ppo]\nlearning_rat = 0.1\n", [](TableReader& r) {
    TableReader p = r.table("ppo");
    p.number("learning_rate", 3e-3, 0.0, 1.0);
    p.integer("n_steps", 50, 1, 100);
    p.finish();
  });
  EXPECT_EQ(msg,
            "run.toml: ppo.learning_rat: unknown key in [ppo]; allowed keys: learning_rate, n_steps");
}

TEST(TomlReader, UnknownTableIsRejected) {
  const std::string msg = error_of("[pp0]\nx = 1\n", [](TableReader& r) {
    r.table("ppo");
    r.finish();
  });
  EXPECT_EQ(msg, "run.toml: pp0: unknown key at the top level; allowed keys: ppo");
}

TEST(TomlReader, StringChoicesAreEnforced) {
  const std::string msg = error_of("env = \"cartpole\"\n", [](TableReader& r) {
    r.string("env", "pendulum", {"pendulum", "whisker"});
  });
  EXPECT_EQ(msg, "run.toml: env: value \"cartpole\" is not allowed; allowed: \"pendulum\", \"whisker\"");
}

TEST(TomlReader, ArrayLengthAndElementsAreChecked) {
  const std::string len = error_of("p = [1, 2, 3]\n", [](TableReader& r) {
    r.numbers("p", {}, 0.0, 20.0, 1, 2);
  });
  EXPECT_EQ(len, "run.toml: p: expected an array of 1 to 2 numbers in [0, 20], got 3 elements");
  const std::string el = error_of("p = [1, 25]\n", [](TableReader& r) {
    r.numbers("p", {}, 0.0, 20.0, 1, 2);
  });
  EXPECT_EQ(el, "run.toml: p: element 1 = 25 is out of range; allowed [0, 20]");
}

TEST(TomlReader, AGridIsAnArrayOrAFromToStepRange) {
  TableReader a = TableReader::from_string("w = [2, 2.5]\nl = {from = 20, to = 50, step = 2}\nt = {from = 0.1, to = 0.3, step = 0.1}\n", "run.toml");
  EXPECT_EQ(a.grid("w", {}, 0.1, 10.0, 1, 100), (std::vector<double>{2.0, 2.5}));
  const std::vector<double> l = a.grid("l", {}, 1.0, 100.0, 1, 100);
  ASSERT_EQ(l.size(), 16u);  // 20, 22, …, 50: the end is included
  EXPECT_EQ(l.front(), 20.0);
  EXPECT_EQ(l.back(), 50.0);
  // 0.3 lies on the grid though (0.3 − 0.1)/0.1 rounds below 2; each value is from + k·step.
  EXPECT_EQ(a.grid("t", {}, 0.0, 1.0, 1, 100), (std::vector<double>{0.1, 0.1 + 0.1, 0.1 + 2 * 0.1}));
  EXPECT_EQ(a.grid("absent", {4.0}, 0.0, 10.0, 1, 2), (std::vector<double>{4.0}));
  a.finish();  // every key read

  const auto grid_error = [](const std::string& text) {
    return error_of(text, [](TableReader& r) { r.grid("l", {}, 1.0, 100.0, 1, 20); });
  };
  EXPECT_EQ(grid_error("l = {from = 20, to = 50}\n"), "run.toml: l: missing \"step\" in {from, to, step}");
  EXPECT_EQ(grid_error("l = {from = 20, to = 50, step = 2, by = 1}\n"), "run.toml: l: unknown key \"by\" in {from, to, step}");
  EXPECT_EQ(grid_error("l = {from = 20, to = 50, step = 0}\n"), "run.toml: l: {from, to, step}: step must be > 0");
  EXPECT_EQ(grid_error("l = {from = 50, to = 20, step = 2}\n"), "run.toml: l: {from, to, step}: from must not exceed to");
  EXPECT_EQ(grid_error("l = {from = 20, to = \"50\", step = 2}\n"), "run.toml: l: to: expected a number, got a string");
  EXPECT_EQ(grid_error("l = {from = 2, to = 60, step = 2}\n"), "run.toml: l: {from, to, step} gives 30 values; allowed 1 to 20");
  EXPECT_EQ(grid_error("l = {from = 90, to = 110, step = 5}\n"), "run.toml: l: {from, to, step} gives 105, out of range; allowed [1, 100]");
  EXPECT_EQ(grid_error("l = [1, 200]\n"), "run.toml: l: element 1 = 200 is out of range; allowed [1, 100]");
}

TEST(TomlReader, RequiredKeyMissing) {
  const std::string msg = error_of("", [](TableReader& r) { r.required_number("dt", 1e-5, 1.0); });
  EXPECT_EQ(msg, "run.toml: dt: missing; a number in [1e-05, 1] is required");
}

TEST(TomlReader, SyntaxErrorHasLineAndColumn) {
  const std::string msg = error_of("a = 1\n[m\n", [](TableReader&) {});
  EXPECT_EQ(msg.rfind("run.toml:2:", 0), 0u) << msg;
}

TEST(TomlReader, MissingFileIsReported) {
  try {
    TableReader::from_file("/nonexistent/run.toml");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/run.toml: cannot open config file");
  }
}

TEST(TomlReader, NonFiniteNumbersAreRejected) {
  const std::string msg = error_of("x = nan\n", [](TableReader& r) { r.number("x", 0, -1, 1); });
  EXPECT_EQ(msg, "run.toml: x: value nan is out of range; allowed [-1, 1]");
}

// A scratch folder of its own per test (pid in the name: ctest may run tests in parallel).
std::filesystem::path fresh_dir(const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() /
                 ("codesign_toml_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

void write(const std::filesystem::path& p, const std::string& text) {
  std::filesystem::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

std::string error_of_file(const std::filesystem::path& p) {
  try {
    TableReader r = TableReader::from_file(p.string());
    TableReader t = r.table("task");
    t.string("observation", "paper", {"paper", "no_feedback"});
    t.number("kappa", 1.5, 0.0, 10.0);
    t.finish();
    r.finish();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(TomlReaderExtends, DerivedFileOverridesKeysAndKeepsTheRest) {
  const auto d = fresh_dir("override");
  write(d / "base.toml", "[task]\nobservation = \"paper\"\nkappa = 1.5\n[ppo]\nsizes = [512, 512]\n");
  write(d / "sub" / "derived.toml",
        "extends = \"../base.toml\"\n[task]\nobservation = \"no_feedback\"\n[ppo]\nsizes = [64]\n");
  TableReader r = TableReader::from_file((d / "sub" / "derived.toml").string());
  TableReader t = r.table("task");
  EXPECT_EQ(t.string("observation", ""), "no_feedback");       // overridden
  EXPECT_DOUBLE_EQ(t.number("kappa", 0.0, 0.0, 10.0), 1.5);     // from the base
  TableReader ppo = r.table("ppo");
  EXPECT_EQ(ppo.integers("sizes", {}, 1, 4096, 1, 8), std::vector<std::int64_t>{64});  // arrays replace
  EXPECT_NO_THROW(t.finish());
  EXPECT_NO_THROW(ppo.finish());
  EXPECT_NO_THROW(r.finish());  // `extends` itself is not an unknown key
  ASSERT_EQ(r.bases().size(), 1u);
  EXPECT_NE(TableReader::input_text((d / "sub" / "derived.toml").string()).find("no_feedback"),
            std::string::npos);
}

TEST(TomlReaderExtends, ChainsResolveNearestFirst) {
  const auto d = fresh_dir("chain");
  write(d / "a.toml", "[task]\nkappa = 1.0\nobservation = \"paper\"\n");
  write(d / "b.toml", "extends = \"a.toml\"\n[task]\nkappa = 2.0\n");
  write(d / "c.toml", "extends = \"b.toml\"\n[task]\nkappa = 3.0\n");
  TableReader r = TableReader::from_file((d / "c.toml").string());
  EXPECT_DOUBLE_EQ(r.table("task").number("kappa", 0.0, 0.0, 10.0), 3.0);
  EXPECT_EQ(r.bases().size(), 2u);
  TableReader rb = TableReader::from_file((d / "b.toml").string());
  EXPECT_DOUBLE_EQ(rb.table("task").number("kappa", 0.0, 0.0, 10.0), 2.0);
}

TEST(TomlReaderExtends, BadValueIsReportedAtTheFileThatStatesIt) {
  const auto d = fresh_dir("blame");
  write(d / "base.toml", "[task]\nkappa = 99.0\n");
  write(d / "derived.toml", "extends = \"base.toml\"\n[task]\nobservation = \"no_feedback\"\n");
  EXPECT_EQ(error_of_file(d / "derived.toml"),
            (d / "base.toml").string() + ": task.kappa: value 99 is out of range; allowed [0, 10]");
  write(d / "derived.toml", "extends = \"base.toml\"\n[task]\nkappa = 1.0\nobservaton = \"x\"\n");
  const std::string typo = error_of_file(d / "derived.toml");
  EXPECT_EQ(typo.rfind((d / "derived.toml").string() + ": task.observaton: unknown key", 0), 0u) << typo;
}

TEST(TomlReaderExtends, CyclesMissingBasesAndWrongTypesAreClearErrors) {
  const auto d = fresh_dir("bad");
  write(d / "x.toml", "extends = \"y.toml\"\n");
  write(d / "y.toml", "extends = \"x.toml\"\n");
  EXPECT_NE(error_of_file(d / "x.toml").find("leads back to a file already in the chain"), std::string::npos);
  write(d / "self.toml", "extends = \"self.toml\"\n");
  EXPECT_NE(error_of_file(d / "self.toml").find("leads back"), std::string::npos);
  write(d / "m.toml", "extends = \"missing.toml\"\n");
  EXPECT_EQ(error_of_file(d / "m.toml"), (d / "missing.toml").string() + ": cannot open config file");
  write(d / "n.toml", "extends = 3\n");
  EXPECT_EQ(error_of_file(d / "n.toml"),
            (d / "n.toml").string() +
                ": extends: expected the file name of a config to extend (a string), got an integer");
  EXPECT_NE(error_of("extends = \"a.toml\"\n", [](TableReader&) {}).find("only a config read from a file"),
            std::string::npos);
}

}  // namespace
}  // namespace codesign::io
