// The place index on random descriptors: a keyframe's descriptors seen again with 40 of 256 bits
// flipped find it among 200 others; removal, replacement, exclusion and compaction.
#include "mapper/place_index.h"

#include <gtest/gtest.h>

#include <random>

namespace hs {
namespace {

std::vector<Descriptor> random_descriptors(std::mt19937& rng, size_t n) {
  std::vector<Descriptor> out(n);
  for (Descriptor& d : out)
    for (uint8_t& b : d) b = static_cast<uint8_t>(rng());
  return out;
}

// Each descriptor with `bits` distinct bits flipped, the first `keep` of them only.
std::vector<Descriptor> seen_again(const std::vector<Descriptor>& in, size_t keep, int bits,
                                   std::mt19937& rng) {
  std::vector<Descriptor> out(in.begin(), in.begin() + static_cast<ptrdiff_t>(keep));
  for (Descriptor& d : out) {
    std::vector<int> order(256);
    for (int i = 0; i < 256; ++i) order[static_cast<size_t>(i)] = i;
    std::shuffle(order.begin(), order.end(), rng);
    for (int k = 0; k < bits; ++k)
      d[static_cast<size_t>(order[static_cast<size_t>(k)] / 8)] ^=
          static_cast<uint8_t>(1 << (order[static_cast<size_t>(k)] % 8));
  }
  return out;
}

class PlaceIndexTest : public ::testing::Test {
 protected:
  void SetUp() override {
    for (int64_t id = 0; id < 200; ++id) {
      keyframes_.push_back(random_descriptors(rng_, 500));
      index_.add(id, keyframes_.back());
    }
  }
  std::mt19937 rng_{11};
  std::vector<std::vector<Descriptor>> keyframes_;
  PlaceIndex index_;
};

TEST_F(PlaceIndexTest, FindsTheKeyframeWhoseDescriptorsReappear) {
  // Half the points seen again, 40 bits off each, plus as many new ones.
  std::vector<Descriptor> query = seen_again(keyframes_[57], 250, 40, rng_);
  const std::vector<Descriptor> fresh = random_descriptors(rng_, 250);
  query.insert(query.end(), fresh.begin(), fresh.end());
  const auto found = index_.query(query, 5);
  ASSERT_FALSE(found.empty());
  EXPECT_EQ(found.front().keyframe_id, 57);
  EXPECT_GT(found.front().votes, 100);  // 1 - (1 - (216/256)^16)^8 of 250: about 0.73
  if (found.size() > 1) {
    EXPECT_LT(found[1].score, 0.2 * found.front().score);
  }
  // Nothing in common: no candidate stands out of chance (about 30 votes each here).
  const auto none = index_.query(random_descriptors(rng_, 500), 5);
  for (const PlaceCandidate& c : none) EXPECT_LT(c.score, 25.0);
}

TEST_F(PlaceIndexTest, ExcludedRemovedAndReplacedKeyframesAreNotReturned) {
  const std::vector<Descriptor> query = seen_again(keyframes_[3], 300, 30, rng_);
  auto found = index_.query(query, 1, [](int64_t id) { return id == 3; });
  ASSERT_TRUE(found.empty() || found.front().keyframe_id != 3);
  index_.remove(3);
  found = index_.query(query, 1);
  EXPECT_TRUE(found.empty() || found.front().keyframe_id != 3);
  index_.add(3, keyframes_[3]);
  ASSERT_FALSE(index_.query(query, 1).empty());
  EXPECT_EQ(index_.query(query, 1).front().keyframe_id, 3);
  index_.add(3, random_descriptors(rng_, 500));  // replaced: the old descriptors are gone
  found = index_.query(query, 1);
  EXPECT_TRUE(found.empty() || found.front().keyframe_id != 3);
  EXPECT_EQ(index_.size(), 200u);
}

TEST_F(PlaceIndexTest, CompactionAfterManyRemovalsKeepsTheAnswers) {
  const size_t before = index_.memory_bytes();
  for (int64_t id = 0; id < 200; ++id)
    if (id != 120) index_.remove(id);
  EXPECT_EQ(index_.size(), 1u);
  EXPECT_LT(index_.memory_bytes(), before);
  const auto found = index_.query(seen_again(keyframes_[120], 200, 40, rng_), 3);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found.front().keyframe_id, 120);
  index_.remove(12345);  // unknown: nothing happens
  EXPECT_EQ(index_.size(), 1u);
}

TEST(PlaceIndex, RejectsATableCountOutsideTheDescriptor) {
  EXPECT_THROW(PlaceIndex({0, 20.0}), std::invalid_argument);
  EXPECT_THROW(PlaceIndex({17, 20.0}), std::invalid_argument);
}

}  // namespace
}  // namespace hs
