#pragma once
// Which channels the logger records: a channel is kept when it fully matches one of the include
// patterns and none of the exclude patterns (POSIX extended regexes, anchored at both ends, as
// LCM's own subscriptions match whole channel names).
#include <regex.h>

#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

namespace hs {

class ChannelFilter {
 public:
  // Throws InputError naming a pattern that is not a valid regex.
  ChannelFilter(const std::vector<std::string>& include, const std::vector<std::string>& exclude);
  // Decisions are cached per channel name (a log sees few distinct channels).
  bool keep(const std::string& channel);

 private:
  struct Compiled {
    regex_t re{};
    bool ok = false;  // regcomp succeeded: re must be freed
    ~Compiled() {
      if (ok) regfree(&re);
    }
  };
  using Patterns = std::vector<std::unique_ptr<Compiled>>;
  static Patterns compile(const std::vector<std::string>& patterns, const char* what);
  static bool any_full_match(const Patterns& patterns, const std::string& s);

  Patterns include_, exclude_;
  std::unordered_map<std::string, bool> cache_;
};

}  // namespace hs
