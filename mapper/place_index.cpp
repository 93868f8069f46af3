#include "mapper/place_index.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace hs {
namespace {
constexpr size_t kBuckets = 65536;
constexpr int kChunks = 16;
}  // namespace

PlaceIndex::PlaceIndex(const PlaceIndexOptions& options) : options_(options) {
  if (options_.tables < 1 || options_.tables > kChunks)
    throw std::invalid_argument("place index: tables must be 1..16, not " +
                                std::to_string(options_.tables));
  for (int t = 0; t < options_.tables; ++t)
    chunk_of_table_.push_back(t * kChunks / options_.tables);
  buckets_.assign(static_cast<size_t>(options_.tables),
                  std::vector<std::vector<uint32_t>>(kBuckets));
}

uint16_t PlaceIndex::chunk(const Descriptor& d, int table) const {
  const size_t c = static_cast<size_t>(chunk_of_table_[static_cast<size_t>(table)]);
  return static_cast<uint16_t>(d[2 * c] | (d[2 * c + 1] << 8));
}

void PlaceIndex::add(int64_t keyframe_id, const std::vector<Descriptor>& descriptors) {
  remove(keyframe_id);
  const auto slot = static_cast<uint32_t>(keyframe_of_slot_.size());
  keyframe_of_slot_.push_back(keyframe_id);
  descriptors_of_slot_.push_back(static_cast<uint32_t>(descriptors.size()));
  slot_of_[keyframe_id] = slot;
  for (const Descriptor& d : descriptors)
    for (int t = 0; t < options_.tables; ++t)
      buckets_[static_cast<size_t>(t)][chunk(d, t)].push_back(slot);
  entries_ += descriptors.size();
}

void PlaceIndex::remove(int64_t keyframe_id) {
  const auto it = slot_of_.find(keyframe_id);
  if (it == slot_of_.end()) return;
  keyframe_of_slot_[it->second] = -1;
  entries_ -= descriptors_of_slot_[it->second];
  dead_entries_ += descriptors_of_slot_[it->second];
  slot_of_.erase(it);
  if (dead_entries_ > entries_ + 1000) compact();
}

void PlaceIndex::compact() {
  std::vector<uint32_t> new_slot(keyframe_of_slot_.size(), UINT32_MAX);
  std::vector<int64_t> keyframes;
  std::vector<uint32_t> counts;
  for (size_t s = 0; s < keyframe_of_slot_.size(); ++s) {
    if (keyframe_of_slot_[s] < 0) continue;
    new_slot[s] = static_cast<uint32_t>(keyframes.size());
    slot_of_[keyframe_of_slot_[s]] = new_slot[s];
    keyframes.push_back(keyframe_of_slot_[s]);
    counts.push_back(descriptors_of_slot_[s]);
  }
  for (auto& table : buckets_)
    for (std::vector<uint32_t>& bucket : table) {
      size_t kept = 0;
      for (uint32_t s : bucket)
        if (new_slot[s] != UINT32_MAX) bucket[kept++] = new_slot[s];
      bucket.resize(kept);
      bucket.shrink_to_fit();
    }
  keyframe_of_slot_ = std::move(keyframes);
  descriptors_of_slot_ = std::move(counts);
  dead_entries_ = 0;
}

std::vector<PlaceCandidate> PlaceIndex::query(const std::vector<Descriptor>& descriptors,
                                              size_t max_candidates,
                                              const std::function<bool(int64_t)>& exclude) const {
  const double mean_bucket = static_cast<double>(entries_ + dead_entries_) / kBuckets;
  const size_t cap = static_cast<size_t>(std::max(8.0, options_.max_bucket_factor * mean_bucket));
  std::vector<int> votes(keyframe_of_slot_.size(), 0);
  std::vector<uint32_t> hit;
  for (const Descriptor& d : descriptors) {
    hit.clear();
    for (int t = 0; t < options_.tables; ++t) {
      const std::vector<uint32_t>& bucket = buckets_[static_cast<size_t>(t)][chunk(d, t)];
      if (bucket.size() <= cap) hit.insert(hit.end(), bucket.begin(), bucket.end());
    }
    std::sort(hit.begin(), hit.end());
    hit.erase(std::unique(hit.begin(), hit.end()), hit.end());
    for (uint32_t s : hit) ++votes[s];
  }
  // A query descriptor meets a given keyframe descriptor by chance in a table with odds 2^-16.
  const double chance =
      static_cast<double>(descriptors.size()) * options_.tables / static_cast<double>(kBuckets);
  std::vector<PlaceCandidate> out;
  for (size_t s = 0; s < votes.size(); ++s) {
    const int64_t id = keyframe_of_slot_[s];
    if (id < 0 || votes[s] == 0 || (exclude && exclude(id))) continue;
    const double score = votes[s] - chance * descriptors_of_slot_[s];
    if (score > 0) out.push_back({id, votes[s], score});
  }
  std::sort(out.begin(), out.end(), [](const PlaceCandidate& a, const PlaceCandidate& b) {
    return a.score != b.score ? a.score > b.score : a.keyframe_id < b.keyframe_id;
  });
  if (out.size() > max_candidates) out.resize(max_candidates);
  return out;
}

size_t PlaceIndex::memory_bytes() const {
  size_t bytes = keyframe_of_slot_.capacity() * sizeof(int64_t) +
                 descriptors_of_slot_.capacity() * sizeof(uint32_t) +
                 slot_of_.size() * (sizeof(int64_t) + sizeof(uint32_t) + 2 * sizeof(void*));
  for (const auto& table : buckets_)
    for (const std::vector<uint32_t>& bucket : table)
      bytes += sizeof(bucket) + bucket.capacity() * sizeof(uint32_t);
  return bytes;
}

}  // namespace hs
