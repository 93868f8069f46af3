#include "logger/channel_filter.h"

#include "common/core/error.h"

namespace hs {

ChannelFilter::Patterns ChannelFilter::compile(const std::vector<std::string>& patterns,
                                               const char* what) {
  Patterns out;
  for (const std::string& p : patterns) {
    auto c = std::make_unique<Compiled>();
    const int err = regcomp(&c->re, ("^(" + p + ")$").c_str(), REG_EXTENDED | REG_NOSUB);
    if (err != 0) {
      char msg[256];
      regerror(err, &c->re, msg, sizeof msg);
      throw InputError(std::string(what) + " channel pattern '" + p +
                       "' is not a valid regex: " + msg);
    }
    c->ok = true;
    out.push_back(std::move(c));
  }
  return out;
}

bool ChannelFilter::any_full_match(const Patterns& patterns, const std::string& s) {
  for (const auto& c : patterns)
    if (regexec(&c->re, s.c_str(), 0, nullptr, 0) == 0) return true;
  return false;
}

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
