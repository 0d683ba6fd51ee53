// DIR/.lock (io/formats/run_lock.hpp): taken and removed again, refused while held (naming the holder,
// leaving the file as it was), and taken over when its holder is gone.
#include "io/formats/run_lock.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include <unistd.h>

#include "base/errors.hpp"

namespace {

namespace fs = std::filesystem;
using codesign::io::RunLock;

fs::path fresh(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("codesign_runlock_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(RunLock, CreatesTheFolderWritesPidAndHostAndRemovesTheFileAfter) {
  const fs::path d = fresh("take");
  {
    const RunLock lock(d.string());
    EXPECT_EQ(lock.path(), (d / ".lock").string());
    const std::string text = slurp(d / ".lock");
    EXPECT_EQ(text.rfind("pid " + std::to_string(::getpid()) + "\nhost ", 0), 0u) << text;
    EXPECT_TRUE(lock.stale_holder().empty());
  }
  EXPECT_FALSE(fs::exists(d / ".lock"));
  EXPECT_TRUE(fs::is_directory(d));
  fs::remove_all(d);
}

TEST(RunLock, HeldLockIsRefusedWithTheHolderAndTheFileUnchanged) {
  const fs::path d = fresh("held");
  const RunLock first(d.string());
  const std::string text = slurp(d / ".lock");
  // flock locks belong to an open file: a second open of the file conflicts even in this process.
  try {
    const RunLock second(d.string());
    ADD_FAILURE() << "took a lock that is held";
  } catch (const codesign::InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind(d.string() + ": another codesign process (pid " + std::to_string(::getpid()) + " on host ", 0),
              0u)
        << m;
    EXPECT_NE(m.find((d / ".lock").string()), std::string::npos) << m;
  }
  EXPECT_EQ(slurp(d / ".lock"), text);
  fs::remove_all(d);
}

TEST(RunLock, StaleLockFileIsTakenOverAndNamed) {
  const fs::path d = fresh("stale");
  fs::create_directories(d);
  std::ofstream(d / ".lock") << "pid 4242\nhost elsewhere\n";  // no process holds it
  {
    const RunLock lock(d.string());
    EXPECT_EQ(lock.stale_holder(), "pid 4242 on host elsewhere");
    EXPECT_EQ(slurp(d / ".lock").rfind("pid " + std::to_string(::getpid()), 0), 0u);
  }
  EXPECT_FALSE(fs::exists(d / ".lock"));
  fs::remove_all(d);
}

TEST(RunLock, ReleasedLockCanBeTakenAgain) {
  const fs::path d = fresh("again");
  std::optional<RunLock> a(std::in_place, d.string());
  a.reset();
  EXPECT_NO_THROW(RunLock(d.string()));
  fs::remove_all(d);
}

}  // namespace
