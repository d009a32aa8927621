#pragma once
// The tangential springs of DEM contacts (tangential_spring.hpp), one per contacting point pair,
// kept by the pair's first end in (body, point) order. Two buffers, by the parity of the
// evaluation: a step reads the springs of the last one while it writes its own, so the two ends
// of a pair, on any threads, read the same old spring. A list is valid only for the evaluation
// stamped on it: a pair that was not written in the last evaluation (it separated) has no spring.
#include <cstdint>
#include <limits>
#include <vector>

#include "bodies/vec.hpp"

namespace ckpd {

// One pair's spring, for checkpoints. A point against a mesh wall has partner_point kWallPartner
// and partner_body the wall.
struct ContactHistoryRow {
  std::uint32_t body = 0, point = 0, partner_body = 0, partner_point = 0;
  Vec3 spring = Vec3::Zero();
};
inline constexpr std::uint32_t kWallPartner = std::numeric_limits<std::uint32_t>::max();

class PairHistory {
 public:
  struct Entry {
    std::uint32_t body, point;  // the partner
    Vec3 spring;                // in the owner's sense
  };

  void resize(const std::vector<std::size_t>& points_per_body) {
    for (int k = 0; k < 2; ++k) {
      lists_[k].assign(points_per_body.size(), {});
      stamp_[k].assign(points_per_body.size(), {});
      for (std::size_t b = 0; b < points_per_body.size(); ++b) {
        lists_[k][b].resize(points_per_body[b]);
        stamp_[k][b].assign(points_per_body[b], kNever);
      }
    }
  }

  // The spring of the pair (owner body/point, partner) written at evaluation `e`; zero if none.
  Vec3 find(std::uint64_t e, std::uint32_t body, std::uint32_t point, std::uint32_t partner_body,
            std::uint32_t partner_point) const {
    const int k = static_cast<int>(e % 2);
    if (stamp_[k][body][point] != e) return Vec3::Zero();
    for (const Entry& entry : lists_[k][body][point])
      if (entry.body == partner_body && entry.point == partner_point) return entry.spring;
    return Vec3::Zero();
  }

  // The owner's list for evaluation e, emptied.
  std::vector<Entry>& start(std::uint64_t e, std::uint32_t body, std::uint32_t point) {
    const int k = static_cast<int>(e % 2);
    stamp_[k][body][point] = e;
    lists_[k][body][point].clear();
    return lists_[k][body][point];
  }

  std::vector<ContactHistoryRow> rows(std::uint64_t e) const {
    std::vector<ContactHistoryRow> rows;
    const int k = static_cast<int>(e % 2);
    for (std::uint32_t b = 0; b < lists_[k].size(); ++b)
      for (std::uint32_t i = 0; i < lists_[k][b].size(); ++i)
        if (stamp_[k][b][i] == e)
          for (const Entry& entry : lists_[k][b][i])
            rows.push_back({b, i, entry.body, entry.point, entry.spring});
    return rows;
  }

  // Forgets everything, then holds `rows` as written at evaluation e.
  void restore(std::uint64_t e, const std::vector<ContactHistoryRow>& rows) {
    for (int k = 0; k < 2; ++k)
      for (auto& stamps : stamp_[k]) std::fill(stamps.begin(), stamps.end(), kNever);
    const int k = static_cast<int>(e % 2);
    for (const ContactHistoryRow& r : rows) {
      if (stamp_[k].at(r.body).at(r.point) != e) start(e, r.body, r.point);
      lists_[k][r.body][r.point].push_back({r.partner_body, r.partner_point, r.spring});
    }
  }

 private:
  static constexpr std::uint64_t kNever = std::numeric_limits<std::uint64_t>::max();
  std::vector<std::vector<std::vector<Entry>>> lists_[2];  // [parity][body][point]
  std::vector<std::vector<std::uint64_t>> stamp_[2];
};

}  // namespace ckpd
