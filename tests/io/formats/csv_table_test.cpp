// io::read_csv: values, columns, an unterminated last line, and every defect named.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "base/errors.hpp"
#include "io/formats/csv_table.hpp"

using namespace codesign;
namespace fs = std::filesystem;

namespace {

class CsvTableTest : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(testing::TempDir()) / ("codesign_csv_table_" + std::to_string(::getpid()) + "_" +
                                           testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& text) {
    const fs::path p = dir_ / "t.csv";
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
  std::string error_of(const std::string& text) {
    try {
      const io::CsvTable t = io::read_csv(write(text));
      for (std::size_t r = 0; r < t.rows(); ++r)
        for (std::size_t c = 0; c + 1 < t.columns().size(); ++c) (void)t.number(r, c);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  }
  fs::path dir_;
};

}  // namespace

TEST_F(CsvTableTest, ReadsNumbersIntegersAndText) {
  const io::CsvTable t = io::read_csv(write("k,t,return,reason\n0,400,-0.25,lost_contact\n1,800,1e-3,time_limit\r\n"));
  ASSERT_EQ(t.rows(), 2u);
  EXPECT_EQ(t.columns(), (std::vector<std::string>{"k", "t", "return", "reason"}));
  EXPECT_EQ(t.column("return"), 2u);
  EXPECT_TRUE(t.has_column("reason"));
  EXPECT_FALSE(t.has_column("Return"));
  EXPECT_EQ(t.integer(1, 1), 800);
  EXPECT_EQ(t.number(0, 2), -0.25);
  EXPECT_EQ(t.number(1, 2), 1e-3);
  EXPECT_EQ(t.cell(1, 3), "time_limit");  // the \r of a CRLF line is dropped
  EXPECT_EQ(t.numbers("k"), (std::vector<double>{0.0, 1.0}));
  // 17 significant digits read back bit-identical.
  const io::CsvTable u = io::read_csv(write("x\n0.10000000000000001\n"));
  EXPECT_EQ(u.number(0, 0), 0.1);
}

TEST_F(CsvTableTest, UnterminatedLastLineIsIgnored) {
  const io::CsvTable t = io::read_csv(write("a,b\n1,2\n3,"));
  EXPECT_EQ(t.rows(), 1u);
  EXPECT_EQ(t.number(0, 1), 2.0);
}

TEST_F(CsvTableTest, DefectsNameFileLineAndColumn) {
  const std::string path = (dir_ / "t.csv").string();
  EXPECT_EQ(error_of(""), path + ": no header row (empty file?)");
  EXPECT_EQ(error_of("a,,b\n"), path + ": line 1: empty column name in the header");
  EXPECT_EQ(error_of("a,b,a\n"), path + ": line 1: column 'a' appears twice");
  EXPECT_EQ(error_of("a,b\n1,2\n1,2,3\n"), path + ": line 3: 3 cells, the header has 2");
  EXPECT_EQ(error_of("a,b,c\n1,x,0\n"), path + ": line 2, column 'b': 'x' is not a finite number");
  EXPECT_EQ(error_of("a,b,c\n1,nan,0\n"), path + ": line 2, column 'b': 'nan' is not a finite number");
  EXPECT_EQ(error_of("a,b,c\n1,,0\n"), path + ": line 2, column 'b': '' is not a finite number");
  EXPECT_EQ(error_of("a,b,c\n1,2.5x,0\n"), path + ": line 2, column 'b': '2.5x' is not a finite number");

  const io::CsvTable t = io::read_csv(write("a,b\n1.5,2\n"));
  try {
    (void)t.integer(0, 0);
    ADD_FAILURE() << "1.5 accepted as an integer";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": line 2, column 'a': '1.5' is not an integer");
  }
  try {
    (void)t.column("return");
    ADD_FAILURE() << "missing column accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": no column 'return' (columns: a, b)");
  }
  try {
    (void)io::read_csv((dir_ / "absent.csv").string());
    ADD_FAILURE() << "missing file accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("absent.csv: cannot open"), std::string::npos);
  }
}
