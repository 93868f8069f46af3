#pragma once
// Output files are never left half-written: content goes to a temporary file in the same
// directory, which is fsync'ed and renamed over the target only on commit().
#include <fstream>
#include <string>

namespace hs {

class AtomicFile {
 public:
  explicit AtomicFile(std::string path);  // throws InputError if the temp file cannot be made
  ~AtomicFile();                          // removes the temp file unless committed
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ofstream& stream() { return out_; }
  const std::string& temp_path() const { return temp_; }
  void commit();  // flush, fsync, rename; throws InputError on failure

 private:
  std::string path_;
  std::string temp_;
  std::ofstream out_;
  bool committed_ = false;
};

// Writes `content` to `path` atomically.
void write_file_atomically(const std::string& path, const std::string& content);

// Renames a finished temp file over `path` after fsync'ing it (for writers that are not
// ostreams, e.g. cv::imwrite or lcm::LogFile). Throws InputError on failure.
void commit_temp_file(const std::string& temp_path, const std::string& path);

// A unique temp path beside `path`.
std::string temp_path_for(const std::string& path);

}  // namespace hs
