#include "logger/channel_filter.h"

#include "common/core/error.h"

namespace hs {

namespace {

std::vector<std::regex> compile(const std::vector<std::string>& patterns, const char* what) {
  std::vector<std::regex> out;
  for (const std::string& p : patterns) {
    try {
      out.emplace_back(p, std::regex::ECMAScript | std::regex::optimize);
    } catch (const std::regex_error& e) {
      throw InputError(std::string(what) + " channel pattern '" + p +
                       "' is not a valid regex: " + e.what());
    }
  }
  return out;
}

bool any_full_match(const std::vector<std::regex>& patterns, const std::string& s) {
  for (const std::regex& r : patterns)
    if (std::regex_match(s, r)) return true;
  return false;
}

}  // namespace

ChannelFilter::ChannelFilter(const std::vector<std::string>& include,
                             const std::vector<std::string>& exclude)
    : include_(compile(include, "include")), exclude_(compile(exclude, "exclude")) {}

bool ChannelFilter::keep(const std::string& channel) {
  const auto it = cache_.find(channel);
  if (it != cache_.end()) return it->second;
  const bool k = any_full_match(include_, channel) && !any_full_match(exclude_, channel);
  cache_.emplace(channel, k);
  return k;
}

}  // namespace hs
