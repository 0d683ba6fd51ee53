#pragma once
// Episodes ended by a numerical failure of the simulator: their reason (episodes.csv, the
// evaluation files) starts with "numerical:" (whisker_env.hpp). The run counts them into its
// progress line, its summary and result.toml [run] numerical_failures.
#include <string_view>

namespace codesign::core {

inline bool is_numerical_failure(std::string_view reason) { return reason.starts_with("numerical:"); }

}  // namespace codesign::core
