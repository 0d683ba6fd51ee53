#pragma once
// Episodes ended by a numerical failure of the simulator: their reason (episodes.csv, the
// evaluation files) starts with "numerical:" (whisker_env.hpp). The run counts them into its
// progress line, its summary and result.toml [run] numerical_failures.
#include <cstdint>
#include <string>
#include <string_view>

namespace codesign::core {

inline bool is_numerical_failure(std::string_view reason) { return reason.starts_with("numerical:"); }

// Rows of a run's episodes.csv (header first, reason the last column) whose reason is a
// numerical failure; 0 if the file does not exist.
std::int64_t count_numerical_failures(const std::string& episodes_csv);

}  // namespace codesign::core
