#pragma once
// Line-oriented CSV reading with file:line in every error. Lines starting with '#' and blank
// lines are skipped (EuRoC puts its header in a '#' line).
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

namespace hs {

struct CsvRow {
  long line = 0;                    // 1-based line number in the file
  std::vector<std::string> fields;  // trimmed
};

class CsvReader {
 public:
  // Throws InputError if the file cannot be opened. `separators` are the field separator
  // characters: "," for EuRoC, " \t" for TUM (runs of separators then count as one).
  explicit CsvReader(std::string path, std::string separators = ",");
  // Reads the next data row; false at end of file.
  bool next(CsvRow& row);
  const std::string& path() const { return path_; }

  // Field parsers that throw InputError naming file:line and the column.
  int64_t int64_at(const CsvRow& row, size_t i) const;
  double double_at(const CsvRow& row, size_t i) const;  // finite values only
  // Throws unless the row has at least n fields.
  void require_fields(const CsvRow& row, size_t n) const;

 private:
  std::string path_;
  std::string separators_;
  std::ifstream in_;
  long line_ = 0;
};

}  // namespace hs
