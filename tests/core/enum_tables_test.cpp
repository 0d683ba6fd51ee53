// The one string table of each enum of the co-design core (base/enum_names.hpp): every value has
// its name, to_string gives it, and the *_from_name parsers read every name back and refuse
// anything else with a message that lists the table, in its order.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "core/design_distribution.hpp"
#include "core/design_sweep.hpp"
#include "core/nlopt_search.hpp"
#include "core/pid_controller.hpp"
#include "core/task_config.hpp"

namespace codesign::core {
namespace {

// Each enum's values in declaration order: a value left out of its table would be named "?".
template <class E, std::size_t N>
void expect_named(const EnumNames<E, N>& names, int count) {
  ASSERT_EQ(static_cast<int>(N), count);
  for (int i = 0; i < count; ++i) {
    const E v = static_cast<E>(i);
    EXPECT_NE(name_of(names, v), "?") << i;
    EXPECT_EQ(std::string(to_string(v)), std::string(name_of(names, v)));
  }
}

template <class F>
std::string refusal(F&& parse) {
  try {
    parse();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(EnumTables, EveryValueIsNamedOnce) {
  expect_named(kLocalMethodNames, 4);
  expect_named(kPhaseNames, 3);
  expect_named(kSweepControllerNames, 4);
  expect_named(kPidSignalNames, 3);
  expect_named(kFaultNames, 3);
}

TEST(EnumTables, ParsersReadEveryNameAndListTheTableOtherwise) {
  for (const auto& n : kLocalMethodNames) EXPECT_EQ(local_method_from_name(std::string(n.name)), n.value);
  for (const auto& n : kSweepControllerNames) EXPECT_EQ(sweep_controller_from_name(std::string(n.name)), n.value);
  for (const auto& n : kPidSignalNames) EXPECT_EQ(pid_signal_from_name(std::string(n.name)), n.value);
  EXPECT_EQ(refusal([] { local_method_from_name("newton"); }),
            "unknown local search method 'newton'; allowed: bobyqa, cobyla, neldermead, sbplx");
  EXPECT_EQ(refusal([] { sweep_controller_from_name("pid_oracle"); }),
            "unknown sweep controller 'pid_oracle'; allowed: fixed_theta, pid_force, pid_strain, pid_estimate");
  EXPECT_EQ(refusal([] { pid_signal_from_name("Force"); }),
            "unknown PID signal 'Force'; allowed: force, strain, estimate");
}

}  // namespace
}  // namespace codesign::core
