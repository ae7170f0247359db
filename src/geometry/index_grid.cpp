// MeshIndex's seed grid for closest-point queries: for every cube near the surface, the clusters
// of triangles that can hold the nearest point of any point of the cube; and the per-triangle
// prism bounds its queries use. Units: mm. See docs/spatial-queries.md, "Seed grid".
#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <system_error>
#include <thread>
#include <vector>

#include "bvh_closest.hpp"
#include "bvh_obb.hpp"
#include "inhap/geometry/mesh_index.hpp"

namespace inhap {

namespace {
constexpr int kSeedCluster = 16;  // clusters: maximal subtrees of at most this many triangles
// Cell side = factor * sqrt(kSeedCluster * mean triangle area): ~25 clusters per covered cell.
constexpr double kSeedCellFactor = 1.2;
constexpr int kMaxSeeds = detail::kSeedMaxClusters;  // see there
constexpr std::size_t kMaxBlockCandidates = 16 * kMaxSeeds;
}  // namespace

// ---------------------------------------------------------------------------------------------
void MeshIndex::build_tri_bounds() {
  tri_bounds_.assign(tris_.size(), TriBound{});
  plane_slack_ = 0;
  prism_scale_ = 0;
  for (std::size_t s = 0; s < tris_.size(); ++s) {
    const TriData& t = tris_[s];
    double slack = 0, scale = 0;
    if (!detail::make_prism_bound(t.v0, t.v1, t.v2, tri_bounds_[s], slack, scale)) continue;
    plane_slack_ = std::max(plane_slack_, slack);
    prism_scale_ = std::max(prism_scale_, scale);
  }
}

// ---------------------------------------------------------------------------------------------
namespace detail {

// Builds MeshIndex::grid_ (a friend: it reads the tree and the triangles).
//
// The certificate (docs/spatial-queries.md, "Seed grid"): let C be the cube of half-side h
// around c, q a point of the surface and a2 = |c - q|^2. For x in C, d(x) <= |x - q|, and
// |x - y|^2 - |x - q|^2 = |y - c|^2 - a2 - 2 (x - c).(y - q) >= |y - c|^2 - a2 - 2 h |y - q|_1.
// So if |y - c|^2 - 2 h |y - q|_1 - a2 > 0 for every point y of a triangle, that triangle is
// farther than q from every point of C: it is never the nearest there. Over one octant of C
// (x - c between 0 and h along each axis, on the octant's side) the last term shrinks to the
// parts of y - q that point to that side (OctantRests), with the same c, q and a2: a cell lists
// a cluster with the octants it can serve, and a query reads only its own octant's clusters.
struct SeedGridBuilder {
  using Cluster = MeshIndex::Cluster;
  using NodeChild = MeshIndex::NodeObb::Child;

  MeshIndex& ix;
  double shell = 0, cell = 0;
  Vec3 origin = Vec3::Zero();
  std::int64_t n[3] = {0, 0, 0};
  std::vector<std::int32_t> cluster_of;           // 2 * node + child -> cluster id, or -1
  std::vector<Cluster> leaves;                    // every leaf, each cluster's leaves contiguous
  std::vector<std::int32_t> leaf_start;           // cluster -> first leaf; clusters + 1 entries
  std::vector<Mat3> cluster_rows, leaf_rows;      // their oriented boxes' frames (obb_rows)
  std::vector<std::vector<std::uint32_t>> lists;  // per cell: seeds

  // The cube test for one cube: centre, half-side (widened by eps for the query's rounding),
  // the nearest surface point, and the rounding margins.
  struct Cube {
    Vec3 c, q;
    double h = 0, eps = 0, a2 = 0, margin = 0, eq_obb = 0, eq_prism = 0;
    std::int32_t nearest = -1;  // original triangle id of q
  };

  explicit SeedGridBuilder(MeshIndex& index) : ix(index) {}

  void collect_clusters();
  bool choose_grid(const MeshIndexOptions& options);
  bool make_cube(const Vec3& c, double half, std::int32_t hint, Cube& cube) const;
  double box_lb(const float* lo, const float* hi, const NodeChild& obb, const Cube& k) const;
  std::uint32_t box_octants(const Cluster& b, const Mat3& rows, const Cube& k,
                            std::uint32_t want) const;
  std::uint32_t triangle_octants(std::int32_t slot, const Cube& k, std::uint32_t want) const;
  std::uint32_t cluster_octants(std::int32_t id, const Cube& k) const;
  bool block_candidates(const Cube& k, std::vector<std::int32_t>& out) const;
  void cell_seeds(const Cube& k, const std::vector<std::int32_t>& cand,
                  std::vector<std::uint32_t>& out) const;
  void run_blocks(std::int64_t first, std::int64_t step);
  void store();
};

// Clusters in depth-first order, each a maximal subtree of at most kSeedCluster triangles (its
// slots are contiguous: the tree was built by partitioning in place), with its leaves.
void SeedGridBuilder::collect_clusters() {
  const auto& nodes = ix.nodes_;
  std::vector<std::int32_t> size(nodes.size(), 0);  // triangles below each inner node
  for (std::size_t i = nodes.size(); i-- > 0;)      // children come after their parents
    for (int ch = 0; ch < 2; ++ch) {
      const auto& nd = nodes[i].node;
      size[i] += nd.count[ch] > 0 ? nd.count[ch] : size[nd.child[ch]];
    }
  auto child_box = [&](std::int32_t ni, int ch) {
    const auto& nd = nodes[ni].node;
    Cluster b{};
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = nd.lo[a][ch];
      b.hi[a] = nd.hi[a][ch];
    }
    b.obb = nodes[ni].obb.child[ch];
    b.first = nd.child[ch];
    b.count = nd.count[ch];
    return b;
  };
  cluster_of.assign(2 * nodes.size(), -1);
  std::vector<std::int32_t> st{0}, sub;
  while (!st.empty()) {
    const std::int32_t ni = st.back();
    st.pop_back();
    for (int ch = 0; ch < 2; ++ch) {
      const auto& nd = nodes[ni].node;
      if (nd.count[ch] == 0 && size[nd.child[ch]] > kSeedCluster) {
        st.push_back(nd.child[ch]);
        continue;
      }
      Cluster cl = child_box(ni, ch);
      leaf_start.push_back(static_cast<std::int32_t>(leaves.size()));
      if (nd.count[ch] > 0) {
        leaves.push_back(cl);
      } else {
        cl.first = std::numeric_limits<std::int32_t>::max();
        std::int32_t end = -1;
        for (sub.assign(1, nd.child[ch]); !sub.empty();) {
          const std::int32_t mi = sub.back();
          sub.pop_back();
          for (int cc = 0; cc < 2; ++cc) {
            if (nodes[mi].node.count[cc] == 0) {
              sub.push_back(nodes[mi].node.child[cc]);
              continue;
            }
            leaves.push_back(child_box(mi, cc));
            cl.first = std::min(cl.first, leaves.back().first);
            end = std::max(end, leaves.back().first + leaves.back().count);
          }
        }
        cl.count = end - cl.first;
      }
      cluster_of[2 * ni + ch] = static_cast<std::int32_t>(ix.grid_.clusters.size());
      ix.grid_.clusters.push_back(cl);
    }
  }
  leaf_start.push_back(static_cast<std::int32_t>(leaves.size()));
  for (const Cluster& cl : ix.grid_.clusters) cluster_rows.push_back(obb_rows(cl.obb.q));
  for (const Cluster& lf : leaves) leaf_rows.push_back(obb_rows(lf.obb.q));
}

// Cell side from the mean triangle area (so a cell needs ~25 clusters), widened until the grid
// has at most 4 cells per triangle (plus 64 Ki). False: no grid.
bool SeedGridBuilder::choose_grid(const MeshIndexOptions& options) {
  shell = options.seed_shell;
  double area = 0;
  for (const auto& t : ix.tris_) area += 0.5 * (t.v1 - t.v0).cross(t.v2 - t.v0).norm();
  const double mean = area / double(ix.tris_.size());
  cell = kSeedCellFactor * std::sqrt(kSeedCluster * mean);
  if (!(cell > 0) || !std::isfinite(cell)) return false;
  const auto max_cells = static_cast<double>(4 * ix.tris_.size() + 65536);
  for (;;) {
    origin = ix.bounds_.min - Vec3::Constant(shell + cell);
    const Vec3 ext = ix.bounds_.max - ix.bounds_.min + Vec3::Constant(2 * (shell + cell));
    double cells = 1;
    for (int k = 0; k < 3; ++k) cells *= std::max(1.0, std::ceil(ext[k] / cell));
    if (!std::isfinite(cells)) return false;
    if (cells <= max_cells) {
      for (int k = 0; k < 3; ++k)
        n[k] = static_cast<std::int64_t>(std::max(1.0, std::ceil(ext[k] / cell)));
      return true;
    }
    cell *= 1.1;
  }
}

// Fills the cube test for the cube of half-side `half` around c; false when no surface point
// lies within the shell of any point of the cube (the cube is not covered).
bool SeedGridBuilder::make_cube(const Vec3& c, double half, std::int32_t hint, Cube& k) const {
  const double X = c.cwiseAbs().maxCoeff();
  k.c = c;
  // A query point is placed in its cell, and in its octant, with a relative rounding of a few
  // ulps.
  k.eps = 1e-9 * (1 + X);
  k.h = half + k.eps;
  const ClosestPoint q = ix.closest_point(c, shell + std::sqrt(3.0) * k.h, hint);
  if (q.triangle < 0) return false;
  k.q = q.point;
  k.a2 = q.distance2;
  k.nearest = q.triangle;
  // Rounding of the squared distances and sums below (generous: ~1e-6 of the slack it guards).
  k.margin = 1e-10 * (1 + X) * (1 + std::sqrt(k.a2) + 4 * k.h);
  k.eq_obb = obb_project_error(c);
  k.eq_prism = prism_error(c, ix.prism_scale_);
  return true;
}

// Lower bound of the certificate over a box (axis-aligned lo/hi, oriented obb); > margin: no
// point of the box can be nearest anywhere in the cube.
double SeedGridBuilder::box_lb(const float* lo, const float* hi, const NodeChild& obb,
                               const Cube& k) const {
  double d2 = 0, m = 0;
  for (int a = 0; a < 3; ++a) {
    const double l = lo[a], u = hi[a];
    const double g = std::max(std::max(l - k.c[a], k.c[a] - u), 0.0);
    d2 += g * g;
    m += std::max(std::abs(l - k.q[a]), std::abs(u - k.q[a]));  // max of |y - q|_1 over the box
  }
  const double rest = 2 * k.h * m + k.a2;
  if (d2 - rest > k.margin) return d2 - rest;
  return std::max(d2, obb_distance2(obb, k.c, k.eq_obb)) - rest;
}

// The certificate per octant of a cell cube k (see the struct comment, with the octant's box
// for C): for x in the octant with signs s, x - c lies in [-eps, h] along an axis where s > 0
// and in [-h, eps] where s < 0, so for y with y - q in [-down, up] (componentwise, up, down >= 0)
// 2 (x - c).(y - q) <= 2 sum_a (h up_a + eps down_a) (s_a > 0), (h down_a + eps up_a) (s_a < 0).
// at(o): a2 + that + margin, which |y - c|^2 must exceed for y to be excluded from octant o (bit
// x + 2y + 4z, set for the upper half along x, y, z). The largest, top(), is at most the whole
// cube's (up_a and down_a both counted at h).
struct OctantRests {
  double side[3][2];  // [axis][upper half]
  double base;
  OctantRests(const double up[3], const double down[3], double h, double eps, double a2,
              double margin)
      : base(a2 + margin) {
    for (int a = 0; a < 3; ++a) {
      side[a][1] = 2 * (h * up[a] + eps * down[a]);
      side[a][0] = 2 * (h * down[a] + eps * up[a]);
    }
  }
  double at(int o) const { return base + side[0][o & 1] + side[1][(o >> 1) & 1] + side[2][o >> 2]; }
  double top() const {
    return base + std::max(side[0][0], side[0][1]) + std::max(side[1][0], side[1][1]) +
           std::max(side[2][0], side[2][1]);
  }
  // The octants among `want` where a squared distance d2 (or a lower bound of it) is not
  // excluded.
  std::uint32_t passing(double d2, std::uint32_t want) const {
    std::uint32_t m = 0;
    for (int o = 0; o < 8; ++o)
      if ((want >> o & 1) && d2 <= at(o)) m |= 1u << o;
    return m;
  }
};

// The octants among `want` for which a box (of a cluster or a leaf: axis-aligned and oriented)
// may hold the nearest point of some point of the octant.
std::uint32_t SeedGridBuilder::box_octants(const Cluster& b, const Mat3& rows, const Cube& k,
                                           std::uint32_t want) const {
  double d2 = 0, up[3], down[3];
  for (int a = 0; a < 3; ++a) {
    const double l = b.lo[a], u = b.hi[a];
    const double g = std::max(std::max(l - k.c[a], k.c[a] - u), 0.0);
    d2 += g * g;
    up[a] = std::max(u - k.q[a], 0.0);
    down[a] = std::max(k.q[a] - l, 0.0);
  }
  const OctantRests rest(up, down, k.h, k.eps, k.a2, k.margin);
  const double top = rest.top();
  if (!(d2 <= top)) return 0;
  d2 = std::max(d2, obb_distance2(b.obb, rows, k.c, k.eq_obb));
  return d2 <= top ? rest.passing(d2, want) : 0;
}

// The octants among `want` for which triangle `slot` may hold the nearest point: the prism
// bound of its distance from c first, the exact distance if needed.
std::uint32_t SeedGridBuilder::triangle_octants(std::int32_t slot, const Cube& k,
                                                std::uint32_t want) const {
  const auto& t = ix.tris_[slot];
  double up[3], down[3];
  for (int a = 0; a < 3; ++a) {
    const double u0 = t.v0[a] - k.q[a], u1 = t.v1[a] - k.q[a], u2 = t.v2[a] - k.q[a];
    up[a] = std::max({u0, u1, u2, 0.0});
    down[a] = std::max({-u0, -u1, -u2, 0.0});
  }
  const OctantRests rest(up, down, k.h, k.eps, k.a2, k.margin);
  const double top = rest.top();
  const double pb = prism_bound(ix.tri_bounds_[slot], k.c, k.eq_prism, ix.plane_slack_);
  if (!(pb <= top) || !rest.passing(pb, want)) return 0;
  const Vec3 w = closest_bary(k.c, t);
  return rest.passing((k.c - (w[0] * t.v0 + w[1] * t.v1 + w[2] * t.v2)).squaredNorm(), want);
}

// The octants of cell cube k where cluster id may hold the nearest point (0: nowhere in the
// cell): its box, its leaves' boxes, then their triangles, each only for the octants still open.
std::uint32_t SeedGridBuilder::cluster_octants(std::int32_t id, const Cube& k) const {
  const std::uint32_t open = box_octants(ix.grid_.clusters[id], cluster_rows[id], k, 0xFF);
  std::uint32_t mask = 0;
  for (std::int32_t l = leaf_start[id]; l < leaf_start[id + 1] && (open & ~mask); ++l) {
    const Cluster& lf = leaves[l];
    const std::uint32_t want = box_octants(lf, leaf_rows[l], k, open & ~mask);
    for (std::int32_t s = lf.first; s < lf.first + lf.count && (want & ~mask); ++s)
      mask |= triangle_octants(s, k, want & ~mask);
  }
  return mask;
}

// Clusters whose boxes pass the certificate for cube k (a tree descent). False when there are
// more than kMaxBlockCandidates: the block's cells would overflow anyway (a block sees about
// four times what a cell keeps), and the descent stops there, which bounds the build's time
// where every cluster is about equally near (a small, fine sphere in a wide shell).
bool SeedGridBuilder::block_candidates(const Cube& k, std::vector<std::int32_t>& out) const {
  out.clear();
  std::vector<std::int32_t> st{0, 1};  // 2 * node + child
  while (!st.empty()) {
    const std::int32_t code = st.back();
    st.pop_back();
    const auto& rec = ix.nodes_[code >> 1];
    const int ch = code & 1;
    const float lo[3] = {rec.node.lo[0][ch], rec.node.lo[1][ch], rec.node.lo[2][ch]};
    const float hi[3] = {rec.node.hi[0][ch], rec.node.hi[1][ch], rec.node.hi[2][ch]};
    if (box_lb(lo, hi, rec.obb.child[ch], k) > k.margin) continue;
    if (cluster_of[code] >= 0) {
      out.push_back(cluster_of[code]);
      if (out.size() > kMaxBlockCandidates) return false;
    } else {
      st.push_back(2 * rec.node.child[ch]);
      st.push_back(2 * rec.node.child[ch] + 1);
    }
  }
  return true;
}

// A cell's seeds: the slot of the triangle nearest its centre, then the clusters among `cand`
// (its block's) that pass the certificate in some octant, with their octant masks.
void SeedGridBuilder::cell_seeds(const Cube& k, const std::vector<std::int32_t>& cand,
                                 std::vector<std::uint32_t>& out) const {
  out.assign(1, static_cast<std::uint32_t>(ix.slots_[k.nearest]));
  for (const std::int32_t id : cand) {
    const std::uint32_t mask = cluster_octants(id, k);
    if (!mask) continue;
    out.push_back(static_cast<std::uint32_t>(id) | mask << kSeedIdBits);
    if (out.size() > kMaxSeeds + 1) {  // too many: the cell stays uncovered
      out.clear();
      return;
    }
  }
}

// Blocks of 2 x 2 x 2 cells: what passes the certificate for the block's cube is a superset of
// what passes it for any of its cells, so the tree is descended once per block.
// Blocks first, first + step, ... (threads interleave, so empty regions are shared out).
void SeedGridBuilder::run_blocks(std::int64_t first, std::int64_t step) {
  const std::int64_t nb[3] = {(n[0] + 1) / 2, (n[1] + 1) / 2, (n[2] + 1) / 2};
  std::vector<std::int32_t> cand;
  Cube block, k;
  for (std::int64_t b = first; b < nb[0] * nb[1] * nb[2]; b += step) {
    const std::int64_t bi[3] = {b % nb[0], (b / nb[0]) % nb[1], b / (nb[0] * nb[1])};
    const Vec3 bc = origin + cell * Vec3(2.0 * double(bi[0]) + 1, 2.0 * double(bi[1]) + 1,
                                         2.0 * double(bi[2]) + 1);
    if (!make_cube(bc, cell, -1, block) || !block_candidates(block, cand)) continue;
    for (int d = 0; d < 8; ++d) {
      const std::int64_t i = 2 * bi[0] + (d & 1), j = 2 * bi[1] + ((d >> 1) & 1),
                         l = 2 * bi[2] + (d >> 2);
      if (i >= n[0] || j >= n[1] || l >= n[2]) continue;
      const Vec3 c = origin + cell * Vec3(double(i) + 0.5, double(j) + 0.5, double(l) + 0.5);
      if (make_cube(c, 0.5 * cell, block.nearest, k))
        cell_seeds(k, cand, lists[i + n[0] * (j + n[1] * l)]);
    }
  }
}

// Concatenates the cells' lists (offsets must fit 32 bits, else no grid).
void SeedGridBuilder::store() {
  MeshIndex::SeedGrid& g = ix.grid_;
  std::size_t total = 0;
  for (const auto& l : lists) total += l.size();
  if (total >= std::numeric_limits<std::uint32_t>::max()) {
    g = MeshIndex::SeedGrid{};
    return;
  }
  g.start.resize(lists.size() + 1);
  g.seeds.resize(total);
  std::size_t at = 0;
  for (std::size_t id = 0; id < lists.size(); ++id) {
    g.start[id] = static_cast<std::uint32_t>(at);
    g.covered += !lists[id].empty();
    std::copy(lists[id].begin(), lists[id].end(),
              g.seeds.begin() + static_cast<std::ptrdiff_t>(at));
    at += lists[id].size();
  }
  g.start[lists.size()] = static_cast<std::uint32_t>(at);
  g.origin = origin;
  g.inv_cell = 1.0 / cell;
  for (int k = 0; k < 3; ++k) g.n[k] = n[k];
}

}  // namespace detail

// ---------------------------------------------------------------------------------------------
void MeshIndex::build_seed_grid(const MeshIndexOptions& options) {
  grid_ = SeedGrid{};
  if (nodes_.empty() || options.seed_shell == 0 || tris_.size() < options.seed_min_triangles)
    return;
  detail::SeedGridBuilder b(*this);
  b.collect_clusters();
  // Cluster ids share a list entry with the octant mask; choose_grid fails e.g. when all
  // triangles have zero area.
  if (grid_.clusters.size() > detail::kSeedIdMask + std::size_t{1} || !b.choose_grid(options)) {
    grid_ = SeedGrid{};
    return;
  }
  build_tri_bounds();
  b.lists.resize(static_cast<std::size_t>(b.n[0] * b.n[1] * b.n[2]));
  const std::int64_t blocks = ((b.n[0] + 1) / 2) * ((b.n[1] + 1) / 2) * ((b.n[2] + 1) / 2);
  const int threads =
      blocks < 4096 ? 1 : static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 8u));
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(threads));
  auto share = [&](int t) {  // blocks t, t + threads, ...
    try {
      b.run_blocks(t, threads);
    } catch (...) {
      errors[static_cast<std::size_t>(t)] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) {
    try {
      pool.emplace_back(share, t);
    } catch (const std::system_error&) {  // no thread: do its share here
      share(t);
    }
  }
  share(0);
  for (auto& th : pool) th.join();
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
  b.store();
  if (grid_.start.empty()) tri_bounds_ = {};
}

MeshIndex::SeedGridInfo MeshIndex::seed_grid_info() const {
  SeedGridInfo info;
  if (grid_.start.empty()) return info;
  info.origin = grid_.origin;
  info.cell = 1.0 / grid_.inv_cell;
  info.cells = static_cast<std::int64_t>(grid_.start.size()) - 1;
  info.covered = grid_.covered;
  info.clusters = static_cast<std::int64_t>(grid_.clusters.size());
  if (info.covered > 0)
    info.seeds_per_cell = double(grid_.seeds.size() - info.covered) / double(info.covered);
  info.bytes = tri_bounds_.capacity() * sizeof(TriBound) +
               grid_.clusters.capacity() * sizeof(Cluster) +
               (grid_.start.capacity() + grid_.seeds.capacity()) * sizeof(std::int32_t);
  return info;
}

}  // namespace inhap
