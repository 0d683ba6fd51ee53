#include "run/folder_lock.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>

namespace codesign::run {

namespace fs = std::filesystem;

std::unique_ptr<io::RunLock> lock_run_folder(const std::string& dir, bool only_if_exists) {
  std::error_code ec;
  if (only_if_exists && !fs::is_directory(dir, ec)) return nullptr;
  auto lock = std::make_unique<io::RunLock>(dir);
  if (!lock->stale_holder().empty())
    std::fprintf(stderr, "codesign: %s was left by %s, which no longer runs (killed); taking the run folder over\n",
                 lock->path().c_str(), lock->stale_holder().c_str());
  return lock;
}

std::unique_ptr<io::RunLock> lock_run_folder_for_output(const std::string& dir, const std::string& out) {
  std::error_code ec;
  auto normal = [&ec](const std::string& p) {
    fs::path n = fs::weakly_canonical(p, ec).lexically_normal();
    return n.has_filename() ? n : n.parent_path();  // "runs/q/" as "runs/q"
  };
  const fs::path d = normal(dir), o = normal(out);
  if (ec) return nullptr;
  const auto [end, _] = std::mismatch(d.begin(), d.end(), o.begin(), o.end());
  if (end != d.end()) return nullptr;
  return lock_run_folder(dir, /*only_if_exists=*/true);
}

}  // namespace codesign::run
