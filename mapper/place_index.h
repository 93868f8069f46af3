#pragma once
// Place recognition without a trained vocabulary (issue 7): multi-index hashing of the keyframes'
// ORB descriptors. Each descriptor is filed under several of its 16-bit chunks, one hash table
// per chunk; two descriptors of the same scene point (30-60 of 256 bits apart) share some chunk
// exactly with good odds, two unrelated ones (about 128 bits apart) almost never. A query votes
// for every keyframe that shares a chunk with one of its descriptors (one vote per query
// descriptor and keyframe); the votes a keyframe would get by chance, in proportion to its
// descriptor count, are subtracted. Incremental: keyframes are added and removed at any time,
// nothing to train or ship, and the candidates still go through geometric verification.
#include <cstdint>
#include <functional>
#include <unordered_map>
#include <vector>

#include "mapper/mapper_keyframe.h"

namespace hs {

struct PlaceIndexOptions {
  int tables = 8;  // 16-bit chunks used, spread over the 16 of a descriptor (1..16)
  // Buckets holding more than this many times the mean per bucket are skipped at query time:
  // chunks of flat or repetitive texture that every keyframe has.
  double max_bucket_factor = 20.0;
};

struct PlaceCandidate {
  int64_t keyframe_id = -1;
  int votes = 0;       // query descriptors sharing a chunk with this keyframe's
  double score = 0.0;  // votes above chance
};

class PlaceIndex {
 public:
  explicit PlaceIndex(const PlaceIndexOptions& options = {});

  // A keyframe id already in the index is replaced.
  void add(int64_t keyframe_id, const std::vector<Descriptor>& descriptors);
  void remove(int64_t keyframe_id);
  // The best `max_candidates` keyframes by score (positive scores only, best first), skipping
  // those `exclude` names (e.g. the query's own neighbourhood).
  std::vector<PlaceCandidate> query(const std::vector<Descriptor>& descriptors,
                                    size_t max_candidates,
                                    const std::function<bool(int64_t)>& exclude = {}) const;

  size_t size() const { return slot_of_.size(); }
  size_t memory_bytes() const;

 private:
  uint16_t chunk(const Descriptor& d, int table) const;
  void compact();

  PlaceIndexOptions options_;
  std::vector<int> chunk_of_table_;
  // Per table, 65536 buckets of keyframe slots (one entry per descriptor).
  std::vector<std::vector<std::vector<uint32_t>>> buckets_;
  std::vector<int64_t> keyframe_of_slot_;  // -1 once removed (entries dropped at compaction)
  std::vector<uint32_t> descriptors_of_slot_;
  std::unordered_map<int64_t, uint32_t> slot_of_;
  size_t entries_ = 0;       // live descriptors (per table)
  size_t dead_entries_ = 0;  // of removed keyframes, still in the buckets
};

}  // namespace hs
