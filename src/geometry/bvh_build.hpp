// Internal to MeshIndex: top-down binned-SAH build of a binary bounding-volume hierarchy over
// triangle boxes. Units: mm. Not a public header (lives beside its sources).
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "inhap/core/types.hpp"

namespace inhap::detail {

inline constexpr int kBvhBins = 16;      ///< SAH candidate planes per axis: kBvhBins - 1
inline constexpr int kBvhMaxLeaf = 4;    ///< leaves hold 1..4 triangles
inline constexpr int kBvhSahDepth = 40;  ///< deeper: object-median splits (halve the count)
/// Depth bound: SAH levels plus at most 31 halvings of a count below 2^31.
inline constexpr int kBvhMaxDepth = kBvhSahDepth + 32;
/// Seed grid: a cell lists at most this many clusters (a fuller cell is left uncovered, its
/// queries descend the tree); a seeded closest-point search holds no more on its stack.
inline constexpr int kSeedMaxClusters = 120;
/// Seed grid list entries: cluster id in the low kSeedIdBits bits, the mask of the cell's eight
/// octants where the cluster can hold the nearest triangle above them (a mesh with more clusters
/// gets no grid).
inline constexpr int kSeedIdBits = 24;
inline constexpr std::uint32_t kSeedIdMask = (1u << kSeedIdBits) - 1;

struct BvhBox {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = Vec3::Constant(-std::numeric_limits<double>::infinity());
  void grow(const Vec3& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  void grow(const BvhBox& b) {
    lo = lo.cwiseMin(b.lo);
    hi = hi.cwiseMax(b.hi);
  }
  /// Half the surface area (the SAH only compares areas).
  double half_area() const {
    if (lo.x() > hi.x()) return 0;
    const Vec3 d = hi - lo;
    return d.x() * d.y() + d.y() * d.z() + d.z() * d.x();
  }
};

/// Depth-first binary node: left child = this + 1; bounds in float rounded outwards (plus one
/// ulp of padding, so no vertex lies exactly on a face).
struct BvhBuildNode {
  float lo[3], hi[3];
  std::int32_t first;  ///< leaf: first slot in `order`; inner: index of the right child
  std::int32_t count;  ///< leaf: number of triangles (> 0); inner: 0
};

struct BvhBuild {
  std::vector<BvhBuildNode> nodes;  ///< empty for no triangles
  std::vector<std::int32_t> order;  ///< leaf slot -> triangle id
  int max_depth = 0;                ///< root = 0; never above kBvhMaxDepth
};

/// Builds the hierarchy over one box per triangle (binned SAH on box centres).
BvhBuild build_bvh(std::vector<BvhBox> boxes);

/// Nearest float <= x minus one ulp (and the mirror image): conservative, padded bounds.
float round_down_padded(double x);
inline float round_up_padded(double x) {
  return -round_down_padded(-x);
}

}  // namespace inhap::detail
