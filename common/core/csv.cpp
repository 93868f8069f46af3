#include "common/core/csv.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "common/core/error.h"

namespace hs {
namespace {

std::string trim(const std::string& s) {
  const char* ws = " \t\r\n";
  const size_t b = s.find_first_not_of(ws);
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(ws) - b + 1);
}

}  // namespace

CsvReader::CsvReader(std::string path, std::string separators)
    : path_(std::move(path)), separators_(std::move(separators)), in_(path_) {
  if (!in_) throw InputError(path_, "cannot open file");
}

bool CsvReader::next(CsvRow& row) {
  std::string text;
  const bool collapse = separators_.find(' ') != std::string::npos;
  while (std::getline(in_, text)) {
    ++line_;
    text = trim(text);
    if (text.empty() || text[0] == '#') continue;
    row.line = line_;
    row.fields.clear();
    size_t start = 0;
    while (true) {
      const size_t end = text.find_first_of(separators_, start);
      const std::string field = trim(text.substr(start, end - start));
      if (!(collapse && field.empty())) row.fields.push_back(field);
      if (end == std::string::npos) break;
      start = end + 1;
    }
    return true;
  }
  if (in_.bad()) throw InputError(path_, line_, "read error");
  return false;
}

void CsvReader::require_fields(const CsvRow& row, size_t n) const {
  if (row.fields.size() < n)
    throw InputError(
        path_, row.line,
        "expected " + std::to_string(n) + " fields, found " + std::to_string(row.fields.size()));
}

int64_t CsvReader::int64_at(const CsvRow& row, size_t i) const {
  require_fields(row, i + 1);
  const std::string& f = row.fields[i];
  errno = 0;
  char* end = nullptr;
  const long long v = std::strtoll(f.c_str(), &end, 10);
  if (f.empty() || *end != '\0' || errno == ERANGE)
    throw InputError(path_, row.line,
                     "column " + std::to_string(i + 1) + ": not an integer: '" + f + "'");
  return static_cast<int64_t>(v);
}

double CsvReader::double_at(const CsvRow& row, size_t i) const {
  require_fields(row, i + 1);
  const std::string& f = row.fields[i];
  char* end = nullptr;
  const double v = std::strtod(f.c_str(), &end);
  if (f.empty() || *end != '\0' || !std::isfinite(v))
    throw InputError(path_, row.line,
                     "column " + std::to_string(i + 1) + ": not a finite number: '" + f + "'");
  return v;
}

}  // namespace hs
