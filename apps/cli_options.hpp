#pragma once
// Command-line options several sub-commands share, stated once so that their names, allowed
// ranges and error messages agree from one command to the next.
#include <string>
#include <utility>

#include <CLI/CLI.hpp>

namespace codesign::app {

// --threads N, 0 ≤ N ≤ 1024; 0 means all cores. `help` says what the threads do.
CLI::Option* add_threads_option(CLI::App& cmd, int& threads, const std::string& help = "threads (0: all cores)");

// --designs J or --designs A-B: the design indices a command covers (0..109). Read the value
// with parse_design_range; `default_text` says what the command does without the option.
CLI::Option* add_designs_option(CLI::App& cmd, std::string& designs, const std::string& default_text);

// "J" -> {J, J}; "A-B" -> {A, B} with 0 ≤ A ≤ B ≤ 109. Anything else throws InputError naming
// --designs and the allowed range.
std::pair<int, int> parse_design_range(const std::string& text);

}  // namespace codesign::app
