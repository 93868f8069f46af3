#include "common/core/csv.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "common/core/error.h"

namespace hs {
namespace {

std::string write_temp(const std::string& content) {
  char name[] = "/tmp/hs_csv_XXXXXX";
  const int fd = mkstemp(name);
  EXPECT_GE(fd, 0);
  std::ofstream(name) << content;
  return name;
}

TEST(Csv, SkipsCommentsAndParsesFields) {
  const std::string p = write_temp("#t,x\n\n1, 2.5\n3,4\n");
  CsvReader r(p);
  CsvRow row;
  ASSERT_TRUE(r.next(row));
  EXPECT_EQ(row.line, 3);
  EXPECT_EQ(r.int64_at(row, 0), 1);
  EXPECT_DOUBLE_EQ(r.double_at(row, 1), 2.5);
  ASSERT_TRUE(r.next(row));
  EXPECT_EQ(row.line, 4);
  EXPECT_FALSE(r.next(row));
  std::remove(p.c_str());
}

TEST(Csv, WhitespaceSeparatorsCollapse) {
  const std::string p = write_temp("1.0  2.0\t3.0\n");
  CsvReader r(p, " \t");
  CsvRow row;
  ASSERT_TRUE(r.next(row));
  ASSERT_EQ(row.fields.size(), 3u);
  EXPECT_DOUBLE_EQ(r.double_at(row, 2), 3.0);
  std::remove(p.c_str());
}

TEST(Csv, MalformedFieldNamesFileAndLine) {
  const std::string p = write_temp("1,2\n3,abc\n4,nan\n");
  CsvReader r(p);
  CsvRow row;
  ASSERT_TRUE(r.next(row));
  ASSERT_TRUE(r.next(row));
  try {
    r.double_at(row, 1);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(p + ":2: column 2"), std::string::npos) << e.what();
  }
  ASSERT_TRUE(r.next(row));
  EXPECT_THROW(r.double_at(row, 1), InputError);  // NaN is not accepted
  EXPECT_THROW(r.int64_at(row, 5), InputError);   // too few fields
  std::remove(p.c_str());
}

TEST(Csv, MissingFileIsAnInputError) {
  EXPECT_THROW(CsvReader("/nonexistent/x.csv"), InputError);
}

}  // namespace
}  // namespace hs
