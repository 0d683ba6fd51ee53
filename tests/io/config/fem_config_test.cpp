// The [solver] reader's fast_stop key: its default, its values, the message for a bad one, and
// that the config writer leaves the default out (resolved configs of older runs keep their text).
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "base/errors.hpp"
#include "io/config/config_writer.hpp"
#include "io/config/fem_config.hpp"
#include "io/config/toml_reader.hpp"

namespace codesign::io {
namespace {

fem::SolverConfig parse_solver(const std::string& text) {
  TableReader root = TableReader::from_string(text, "run.toml");
  const fem::SolverConfig c = read_solver(root);
  root.finish();
  return c;
}

std::string solver_error(const std::string& text) {
  try {
    parse_solver(text);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error for:\n" << text;
  return {};
}

std::string written(const fem::SolverConfig& solver) {
  std::ostringstream out;
  write_fem_tables(out, fem::WhiskerModelSpec{}, fem::SceneConfig{}, solver);
  return out.str();
}

TEST(FemConfig, FastStopDefaultsToTheRelativeRule) {
  EXPECT_EQ(fem::SolverConfig{}.fast_stop, fem::FastStop::Relative);
  EXPECT_EQ(parse_solver("").fast_stop, fem::FastStop::Relative);
  EXPECT_EQ(parse_solver("[solver]\nfast_tolerance = 1e-4\n").fast_stop, fem::FastStop::Relative);
  EXPECT_EQ(parse_solver("[solver]\nfast_stop = \"relative\"\n").fast_stop, fem::FastStop::Relative);
}

TEST(FemConfig, FastStopForceIsRead) {
  const fem::SolverConfig c = parse_solver("[solver]\nfast_stop = \"force\"\nfast_tolerance = 4e-3\n");
  EXPECT_EQ(c.fast_stop, fem::FastStop::Force);
  EXPECT_EQ(c.fast_tolerance, 4e-3);
}

TEST(FemConfig, BadFastStopNamesFileKeyAndAllowedValues) {
  const std::string m = solver_error("[solver]\nfast_stop = \"absolute\"\n");
  EXPECT_NE(m.find("run.toml"), std::string::npos) << m;
  EXPECT_NE(m.find("solver.fast_stop"), std::string::npos) << m;
  EXPECT_NE(m.find("absolute"), std::string::npos) << m;
  for (const char* allowed : {"\"relative\"", "\"force\""})
    EXPECT_NE(m.find(allowed), std::string::npos) << allowed << " missing from: " << m;
  const std::string n = solver_error("[solver]\nfast_stop = 1\n");  // not a string
  EXPECT_NE(n.find("solver.fast_stop"), std::string::npos) << n;
}

TEST(FemConfig, WriterStatesFastStopOnlyWhenNotTheDefault) {
  const std::string d = written(fem::SolverConfig{});
  EXPECT_EQ(d.find("fast_stop"), std::string::npos) << d;
  fem::SolverConfig f;
  f.fast_stop = fem::FastStop::Force;
  const std::string t = written(f);
  EXPECT_NE(t.find("fast_stop = \"force\"\n"), std::string::npos) << t;
  // Apart from that line the text is the default one.
  std::string without = t;
  without.erase(without.find("fast_stop = \"force\"\n"), std::string("fast_stop = \"force\"\n").size());
  EXPECT_EQ(without, d);
}

}  // namespace
}  // namespace codesign::io
