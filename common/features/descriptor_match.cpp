#include "common/features/descriptor_match.h"

#include <algorithm>
#include <climits>
#include <cstring>

namespace hs {

int hamming256(const uint8_t* a, const uint8_t* b) {
  int d = 0;
  for (int i = 0; i < 32; i += 8) {
    uint64_t x, y;
    std::memcpy(&x, a + i, 8);
    std::memcpy(&y, b + i, 8);
    d += __builtin_popcountll(x ^ y);
  }
  return d;
}

KeypointGrid::KeypointGrid(const std::vector<Eigen::Vector2f>& uv, int width, int height,
                           int cell_px)
    : uv_(uv),
      cell_px_(cell_px),
      cols_((width + cell_px - 1) / cell_px),
      rows_((height + cell_px - 1) / cell_px),
      cells_(static_cast<size_t>(cols_ * rows_)) {
  for (int i = 0; i < static_cast<int>(uv.size()); ++i) {
    const int cx = std::clamp(static_cast<int>(uv[i].x()) / cell_px, 0, cols_ - 1);
    const int cy = std::clamp(static_cast<int>(uv[i].y()) / cell_px, 0, rows_ - 1);
    cells_[cy * cols_ + cx].push_back(i);
  }
}

void KeypointGrid::query(const Eigen::Vector2d& centre, double radius,
                         std::vector<int>& out) const {
  out.clear();
  const int x0 = std::max(0, static_cast<int>((centre.x() - radius) / cell_px_));
  const int x1 = std::min(cols_ - 1, static_cast<int>((centre.x() + radius) / cell_px_));
  const int y0 = std::max(0, static_cast<int>((centre.y() - radius) / cell_px_));
  const int y1 = std::min(rows_ - 1, static_cast<int>((centre.y() + radius) / cell_px_));
  const float r2 = static_cast<float>(radius * radius);
  const Eigen::Vector2f c = centre.cast<float>();
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x)
      for (int i : cells_[y * cols_ + x])
        if ((uv_[i] - c).squaredNorm() <= r2) out.push_back(i);
}

namespace {

// Best and second-best distances of one query against candidate rows.
struct Best {
  int index = -1;
  int dist = INT_MAX;
  int second = INT_MAX;
  void offer(int i, int d) {
    if (d < dist) {
      second = dist;
      dist = d;
      index = i;
    } else if (d < second) {
      second = d;
    }
  }
  bool passes(const DescriptorMatchOptions& o) const {
    return index >= 0 && dist <= o.max_distance &&
           (second == INT_MAX || static_cast<float>(dist) < o.ratio * static_cast<float>(second));
  }
};

}  // namespace

std::vector<int> match_by_projection(const cv::Mat& query_descriptors,
                                     const std::vector<Eigen::Vector2d>& predicted_uv,
                                     const cv::Mat& train_descriptors, const KeypointGrid& grid,
                                     const DescriptorMatchOptions& options) {
  std::vector<int> match(predicted_uv.size(), -1);
  std::vector<int> owner_dist(static_cast<size_t>(train_descriptors.rows), INT_MAX);
  std::vector<int> owner(static_cast<size_t>(train_descriptors.rows), -1);
  std::vector<int> candidates;
  for (size_t q = 0; q < predicted_uv.size(); ++q) {
    grid.query(predicted_uv[q], options.search_radius_px, candidates);
    Best best;
    for (int t : candidates)
      best.offer(t, hamming256(query_descriptors.ptr<uint8_t>(static_cast<int>(q)),
                               train_descriptors.ptr<uint8_t>(t)));
    if (!best.passes(options) || best.dist >= owner_dist[best.index]) continue;
    if (owner[best.index] >= 0) match[owner[best.index]] = -1;
    owner[best.index] = static_cast<int>(q);
    owner_dist[best.index] = best.dist;
    match[q] = best.index;
  }
  return match;
}

std::vector<std::pair<int, int>> match_mutual(const cv::Mat& query_descriptors,
                                              const cv::Mat& train_descriptors,
                                              const DescriptorMatchOptions& options) {
  const int nq = query_descriptors.rows, nt = train_descriptors.rows;
  std::vector<Best> fwd(static_cast<size_t>(nq));
  std::vector<int> back_index(static_cast<size_t>(nt), -1),
      back_dist(static_cast<size_t>(nt), INT_MAX);
  for (int q = 0; q < nq; ++q) {
    for (int t = 0; t < nt; ++t) {
      const int d =
          hamming256(query_descriptors.ptr<uint8_t>(q), train_descriptors.ptr<uint8_t>(t));
      fwd[q].offer(t, d);
      if (d < back_dist[t]) {
        back_dist[t] = d;
        back_index[t] = q;
      }
    }
  }
  std::vector<std::pair<int, int>> pairs;
  for (int q = 0; q < nq; ++q)
    if (fwd[q].passes(options) && back_index[fwd[q].index] == q)
      pairs.emplace_back(q, fwd[q].index);
  return pairs;
}

}  // namespace hs
