// Files that cannot be written: the error names the file and the system's reason, and the
// earlier file stays as it was. A full disk is /dev/full (every write fails with ENOSPC): the
// writers' temporary file PATH.tmp, or a log itself, is made a symbolic link to it. That works
// without root and as root (a read-only folder does not stop root).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include "base/errors.hpp"
#include "io/formats/atomic_file.hpp"
#include "io/formats/csv_log.hpp"
#include "io/formats/png_file.hpp"

namespace {

namespace fs = std::filesystem;

class WriteError : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
    dir_ = fs::temp_directory_path() / ("codesign_write_error_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  // PATH.tmp -> /dev/full, and PATH with the text "earlier".
  fs::path full_target(const std::string& name) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << "earlier";
    fs::create_symlink("/dev/full", dir_ / (name + ".tmp"));
    return p;
  }
  static std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  fs::path dir_;
};

TEST_F(WriteError, AtomicFileNamesTheFileAndTheCauseAndKeepsTheEarlierFile) {
  const fs::path p = full_target("checkpoint.bin");
  try {
    codesign::io::write_file_atomically(p.string(), [](std::ostream& out) { out << std::string(100000, 'x'); }, true);
    ADD_FAILURE() << "wrote into /dev/full";
  } catch (const codesign::FileError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(p.string() + ".tmp: cannot write: No space left on device"), std::string::npos) << m;
    EXPECT_NE(m.find(p.string() + " left as it was"), std::string::npos) << m;
  }
  EXPECT_EQ(slurp(p), "earlier");
  EXPECT_FALSE(fs::is_symlink(p.string() + ".tmp"));  // the temporary file is removed
}

TEST_F(WriteError, PngNamesTheFileAndTheCauseInsteadOfLibpngsWriteError) {
  const fs::path p = full_target("frame_0000.png");
  codesign::io::RgbImage image(64, 48);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = static_cast<unsigned char>(i * 7);
  testing::internal::CaptureStderr();
  try {
    codesign::io::write_png(p.string(), image);
    ADD_FAILURE() << "wrote into /dev/full";
  } catch (const codesign::FileError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(p.string() + ".tmp: cannot write: No space left on device"), std::string::npos) << m;
  }
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(err.find("libpng"), std::string::npos) << err;  // libpng printed nothing itself
  EXPECT_EQ(slurp(p), "earlier");
  EXPECT_FALSE(fs::is_symlink(p.string() + ".tmp"));
}

TEST_F(WriteError, CsvLogNamesTheFileAndTheCause) {
  const fs::path p = dir_ / "episodes.csv";
  fs::create_symlink("/dev/full", p);
  codesign::io::CsvLog log(p.string(), {"t", "k"});
  log.row({"1", "2"});
  try {
    log.flush();
    ADD_FAILURE() << "flushed into /dev/full";
  } catch (const codesign::FileError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m, p.string() + ": cannot write: No space left on device") << m;
  }
}

}  // namespace
