// Binned-SAH BVH build for MeshIndex. Units: mm. See docs/spatial-queries.md.
#include "bvh_build.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace inhap::detail {

float round_down_padded(double x) {
  constexpr float kFloatMax = std::numeric_limits<float>::max();
  constexpr float kFloatInf = std::numeric_limits<float>::infinity();
  if (x > static_cast<double>(kFloatMax)) return kFloatMax;
  if (x < -static_cast<double>(kFloatMax)) return -kFloatInf;
  float f = static_cast<float>(x);
  if (static_cast<double>(f) > x) f = std::nextafter(f, -kFloatInf);
  return std::nextafter(f, -kFloatInf);
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Top-down build over a permutation of the triangle ids; nodes in depth-first order.
class Builder {
 public:
  explicit Builder(std::vector<BvhBox> boxes) : boxes_(std::move(boxes)) {
    centroids_.resize(boxes_.size());
    out_.order.resize(boxes_.size());
    for (std::size_t i = 0; i < boxes_.size(); ++i) {
      centroids_[i] = 0.5 * (boxes_[i].lo + boxes_[i].hi);
      out_.order[i] = static_cast<std::int32_t>(i);
    }
    out_.nodes.reserve(2 * boxes_.size());
  }
  BvhBuild run() && {
    if (!boxes_.empty()) build(0, static_cast<std::int32_t>(boxes_.size()), 0);
    out_.nodes.shrink_to_fit();
    return std::move(out_);
  }

 private:
  struct Split {
    int axis = -1, bin = 0;
    double cost = kInf;
  };
  struct Bin {
    BvhBox box;
    std::int32_t count = 0;
  };
  // Maps a centre coordinate to its bin along one axis of the centroid box.
  struct Binning {
    double lo, scale;
    int operator()(double c) const {
      return std::clamp(static_cast<int>((c - lo) * scale), 0, kBvhBins - 1);
    }
  };
  static Binning binning(const BvhBox& cb, int axis) {
    return {cb.lo[axis], kBvhBins / (cb.hi[axis] - cb.lo[axis])};
  }

  Split best_sah_split(std::int32_t begin, std::int32_t end, const BvhBox& cb) const {
    std::array<std::array<Bin, kBvhBins>, 3> bins{};  // one pass bins all three axes
    bool usable[3];
    Binning bin_of[3];
    for (int axis = 0; axis < 3; ++axis) {
      usable[axis] = cb.hi[axis] > cb.lo[axis];
      bin_of[axis] = usable[axis] ? binning(cb, axis) : Binning{0, 0};
    }
    for (std::int32_t i = begin; i < end; ++i) {
      const std::int32_t t = out_.order[i];
      for (int axis = 0; axis < 3; ++axis) {
        Bin& b = bins[axis][bin_of[axis](centroids_[t][axis])];
        b.box.grow(boxes_[t]);
        ++b.count;
      }
    }
    Split best;
    for (int axis = 0; axis < 3; ++axis) {
      if (!usable[axis]) continue;
      // Cost of a split between bins b-1 and b: area(left) * n(left) + area(right) * n(right).
      std::array<double, kBvhBins> right_cost{};
      BvhBox acc;
      std::int32_t n = 0;
      for (int b = kBvhBins - 1; b > 0; --b) {
        acc.grow(bins[axis][b].box);
        n += bins[axis][b].count;
        right_cost[b] = n ? acc.half_area() * n : kInf;
      }
      acc = BvhBox{};
      n = 0;
      for (int b = 0; b < kBvhBins - 1; ++b) {
        acc.grow(bins[axis][b].box);
        n += bins[axis][b].count;
        if (n == 0) continue;
        const double cost = acc.half_area() * n + right_cost[b + 1];
        if (cost < best.cost) best = {axis, b + 1, cost};
      }
    }
    return best;
  }

  // Partitions [begin, end) and returns the first index of the right half.
  std::int32_t split(std::int32_t begin, std::int32_t end, const BvhBox& cb, int depth) {
    std::int32_t* first = out_.order.data() + begin;
    std::int32_t* last = out_.order.data() + end;
    if (depth < kBvhSahDepth) {
      const Split s = best_sah_split(begin, end, cb);
      if (s.axis >= 0) {
        const Binning bin_of = binning(cb, s.axis);
        std::int32_t* mid = std::partition(
            first, last, [&](std::int32_t t) { return bin_of(centroids_[t][s.axis]) < s.bin; });
        if (mid != first && mid != last) return static_cast<std::int32_t>(mid - out_.order.data());
      }
    }
    // Object median along the widest centroid axis (also handles identical centroids).
    int axis = 0;
    const Vec3 ext = cb.hi - cb.lo;
    if (ext.y() > ext[axis]) axis = 1;
    if (ext.z() > ext[axis]) axis = 2;
    const std::int32_t m = begin + (end - begin) / 2;
    std::nth_element(first, out_.order.data() + m, last, [&](std::int32_t a, std::int32_t b) {
      return centroids_[a][axis] < centroids_[b][axis];
    });
    return m;
  }

  void build(std::int32_t begin, std::int32_t end, int depth) {
    out_.max_depth = std::max(out_.max_depth, depth);
    BvhBox box, cb;
    for (std::int32_t i = begin; i < end; ++i) {
      box.grow(boxes_[out_.order[i]]);
      cb.grow(centroids_[out_.order[i]]);
    }
    BvhBuildNode node{};
    for (int k = 0; k < 3; ++k) {
      node.lo[k] = round_down_padded(box.lo[k]);
      node.hi[k] = round_up_padded(box.hi[k]);
    }
    const std::size_t self = out_.nodes.size();
    if (end - begin <= kBvhMaxLeaf) {
      node.first = begin;
      node.count = end - begin;
      out_.nodes.push_back(node);
      return;
    }
    node.count = 0;
    out_.nodes.push_back(node);
    const std::int32_t mid = split(begin, end, cb, depth);
    build(begin, mid, depth + 1);  // left child = self + 1
    out_.nodes[self].first = static_cast<std::int32_t>(out_.nodes.size());
    build(mid, end, depth + 1);
  }

  std::vector<BvhBox> boxes_;
  std::vector<Vec3> centroids_;
  BvhBuild out_;
};

}  // namespace

BvhBuild build_bvh(std::vector<BvhBox> boxes) {
  return Builder(std::move(boxes)).run();
}

}  // namespace inhap::detail
