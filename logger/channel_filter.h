#pragma once
// Which channels the logger records: a channel is kept when it fully matches one of the include
// patterns and none of the exclude patterns (ECMAScript regexes, as LCM's own subscriptions
// match whole channel names).
#include <regex>
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
  std::vector<std::regex> include_, exclude_;
  std::unordered_map<std::string, bool> cache_;
};

}  // namespace hs
