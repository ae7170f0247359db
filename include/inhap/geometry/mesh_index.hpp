// Spatial queries on a triangle mesh: first hit of a segment and closest point on the surface.
// Units: mm. Queries are const, thread-safe, allocation-free and exception-free (servo-ready).
// A query against a mesh translated by t is answered by querying with (point - t): the index
// never needs rebuilding for a rigid translation (TCA-MESH relies on this).
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "inhap/geometry/trimesh.hpp"

namespace inhap {

namespace detail {
/// Storage of the large index arrays: above 1 MiB, 2 MiB-aligned and (on Linux) advised for
/// transparent huge pages, since queries jump around 100 MB and would otherwise miss the TLB at
/// almost every node. Goes through the aligned global operator new; never less aligned than
/// `min_align` (the element type's alignment: the tree's records are 64- and 128-byte aligned).
void* index_alloc(std::size_t bytes, std::size_t min_align);
void index_free(void* p, std::size_t bytes, std::size_t min_align) noexcept;
template <class T>
struct IndexAllocator {
  using value_type = T;
  IndexAllocator() = default;
  template <class U>
  IndexAllocator(const IndexAllocator<U>&) {}
  T* allocate(std::size_t n) { return static_cast<T*>(index_alloc(n * sizeof(T), alignof(T))); }
  void deallocate(T* p, std::size_t n) noexcept { index_free(p, n * sizeof(T), alignof(T)); }
  friend bool operator==(const IndexAllocator&, const IndexAllocator&) { return true; }
};
template <class T>
using IndexVector = std::vector<T, IndexAllocator<T>>;
struct SeedGridBuilder;
}  // namespace detail

/// A point on the surface: triangle id and barycentric weights of its vertices t[0], t[1], t[2]
/// (bary sums to 1; point = sum bary[i] * positions[t[i]]).
struct SurfacePoint {
  std::int32_t triangle = -1;  ///< -1: none
  Vec3 bary = Vec3::Zero();
  Vec3 point = Vec3::Zero();
  bool valid() const { return triangle >= 0; }
};

struct SegmentHit : SurfacePoint {
  double t = 0;           ///< segment parameter in [0, 1] (point = a + t (b - a))
  bool entering = false;  ///< the segment goes against the face normal (from outside to inside)
};

struct ClosestPoint : SurfacePoint {
  double distance2 = std::numeric_limits<double>::infinity();  ///< squared distance, mm^2
};

/// Build options of MeshIndex (distances in mm).
struct MeshIndexOptions {
  /// Closest-point queries at most this far from the surface start from a seed grid: cubes near
  /// the surface that list the few clusters of triangles which can hold the answer, instead of a
  /// descent from the root (about half the latency of a cold query; docs/spatial-queries.md,
  /// "Seed grid"). Costs about the tree's memory again and several times its build time (1M
  /// triangles: +171 MB, 15 s on 2 cores against the tree's 1.3 s). 0: no grid.
  double seed_shell = 5.0;
  /// Meshes with fewer triangles get no grid (their tree is shallow and stays in cache).
  std::size_t seed_min_triangles = 4096;
};

/// Bounding-volume hierarchy over the triangles of a mesh (binned SAH build, flat node array,
/// triangle data stored in leaf order for cache locality), with a seed grid near the surface for
/// closest-point queries (MeshIndexOptions). Keeps its own copy of the geometry; the mesh may be
/// destroyed afterwards.
class MeshIndex {
 public:
  MeshIndex() = default;
  /// Builds the index (allocates, may use several threads; not for the servo loop). Throws Error
  /// on an out-of-range vertex index, a non-finite vertex used by a triangle or a seed_shell that
  /// is negative or not finite. Zero-area triangles are kept but never hit by segments.
  explicit MeshIndex(const TriMesh& mesh, const MeshIndexOptions& options = {});

  /// First intersection of the closed segment a->b with the surface (smallest t), any face
  /// orientation. Degenerate segments (a == b) return nullopt.
  std::optional<SegmentHit> first_hit(const Vec3& a, const Vec3& b) const;
  /// True if the segment intersects the surface anywhere.
  bool any_hit(const Vec3& a, const Vec3& b) const;
  /// Closest surface point to p; triangle == -1 when none lies within max_distance (mm).
  ClosestPoint closest_point(const Vec3& p,
                             double max_distance = std::numeric_limits<double>::infinity()) const;

  /// closest_point() warm-started from a triangle that is probably near the answer, typically
  /// the previous servo tick's (`ClosestPoint::triangle`): the hint's distance is the first
  /// bound, so the search prunes from the start. Same answer as without the hint (an equally near
  /// triangle may be reported instead); a hint that is -1, out of range or far away only costs
  /// one point-triangle test.
  ClosestPoint closest_point(const Vec3& p, double max_distance, std::int32_t hint_triangle) const;

  /// Work done by one query (diagnostics and benchmarks; not needed by callers).
  struct QueryStats {
    std::int64_t nodes = 0;      ///< inner nodes visited
    std::int64_t triangles = 0;  ///< triangles loaded from leaves
    std::int64_t exact = 0;      ///< triangles that needed the full point-triangle test
    std::int64_t seeded = 0;     ///< queries that started from the seed grid
  };
  /// closest_point() that also adds its work to `stats` (same result, a little slower).
  ClosestPoint closest_point_counted(const Vec3& p, double max_distance, QueryStats& stats,
                                     std::int32_t hint_triangle = -1) const;

  /// The seed grid (all zero without one). A cell is covered when a surface point lies within
  /// seed_shell of it and at most 120 clusters can hold its points' nearest triangles.
  struct SeedGridInfo {
    Vec3 origin = Vec3::Zero();  ///< corner of cell (0, 0, 0), mm
    double cell = 0;             ///< side of a cell, mm
    std::int64_t cells = 0, covered = 0;
    std::int64_t clusters = 0;  ///< clusters of at most 16 triangles
    double seeds_per_cell = 0;  ///< mean number of clusters listed by a covered cell
    std::size_t bytes = 0;      ///< grid and prism bounds (included in memory_bytes())
  };
  SeedGridInfo seed_grid_info() const;

  std::size_t num_triangles() const { return tri_ids_.size(); }
  Box3 bounds() const;
  std::size_t memory_bytes() const;

 private:
  friend struct detail::SeedGridBuilder;
  template <class Stats>
  ClosestPoint closest_impl(const Vec3& p, double max_distance, std::int32_t hint,
                            Stats& stats) const;
  template <class Search, class Stats>
  void exact_test(const Vec3& p, std::int32_t slot, Search& search, Stats& stats) const;
  // The seeds of the cell holding p (SeedGrid::seeds from `first`, `count` entries; count 0
  // outside the grid or its shell) and the bit of p's octant in their masks.
  struct SeedCell {
    const std::uint32_t* first = nullptr;
    int count = 0;
    std::uint32_t octant = 0;
  };
  template <class Search, class Stats>
  void seed_search(const Vec3& p, const SeedCell& cell, double eq, Search& search,
                   Stats& stats) const;

  // Inner node with the bounds of both children: one 64-byte cache line per visited node.
  struct alignas(64) Node {
    float lo[3][2], hi[3][2];  // [axis][child], float, conservatively rounded outwards
    std::int32_t child[2];     // leaf child: first triangle slot; inner child: node index
    std::int32_t count[2];     // leaf child: number of triangles (1..4); inner child: 0
  };
  // Oriented boxes of both children of the same inner node, for distance pruning only (one more
  // cache line per visit). Frame: int16 quaternion, see src/geometry/bvh_obb.hpp.
  struct alignas(64) NodeObb {
    struct Child {
      std::int16_t q[4];   // frame quaternion (w, x, y, z)
      float lo[3], hi[3];  // extents along the frame axes, rounded outwards
    } child[2];
  };
  struct TriData {
    // Raw vertex positions (not v0 + edges): a vertex shared by several triangles must be
    // bit-identical in each of them for the watertight segment test.
    Vec3 v0, v1, v2;
  };
  // A node and its children's oriented boxes side by side: 128 bytes, one aligned pair of lines
  // (the hardware fetches a line's pair partner along with it).
  struct alignas(128) NodeRec {
    Node node;
    NodeObb obb;
  };
  // Per triangle, in leaf order: a cheap, nearly exact lower bound of the squared distance from
  // a point (the "prism bound", docs/spatial-queries.md): the plane's unit normal and offset,
  // and the outward unit normals and offsets of the three edges' half-planes, in float, offsets
  // rounded so that the bound never exceeds the true distance. All zero: bound 0.
  struct alignas(64) TriBound {
    float n[3], o;  // plane: |n.x - o| <= plane_slack_ for every point x of the triangle
    float m[3][4];  // edge j: m[j].x <= m[j][3] for every point x of the triangle
  };
  // A cluster of the seed grid: a subtree of at most kSeedCluster triangles flattened to its
  // slot range, with its boxes (one cache line).
  struct alignas(64) Cluster {
    float lo[3], hi[3];         // axis-aligned box, as in Node
    NodeObb::Child obb;         // oriented box, as in NodeObb
    std::int32_t first, count;  // triangle slots [first, first + count)
  };
  // Seed grid (docs/spatial-queries.md, "Seed grid"): cubes of side 1 / inv_cell from origin,
  // n[0] x n[1] x n[2], x fastest. A covered cell lists the slot of the triangle nearest its
  // centre, then the clusters that can hold the nearest triangle of some point of the cell, each
  // with the octants of the cell where they can (cluster id in the low detail::kSeedIdBits bits,
  // octant mask above: bit x + 2y + 4z for the upper half along the axes x, y, z).
  struct SeedGrid {
    Vec3 origin = Vec3::Zero();
    double inv_cell = 0;
    std::int64_t n[3] = {0, 0, 0};
    std::int64_t covered = 0;                  // cells with a list
    detail::IndexVector<std::uint32_t> start;  // cell -> offset in seeds; cells + 1 entries
    detail::IndexVector<std::uint32_t> seeds;  // per covered cell: slot, then cluster entries
    detail::IndexVector<Cluster> clusters;
  };
  void build_seed_grid(const MeshIndexOptions& options);
  void build_tri_bounds();
  SeedCell grid_seeds(const Vec3& p) const;

  detail::IndexVector<NodeRec> nodes_;  // root = nodes_[0]; empty when all triangles fit a leaf
  detail::IndexVector<TriData> tris_;   // leaf order
  detail::IndexVector<TriBound> tri_bounds_;  // leaf order; empty without a seed grid
  double plane_slack_ = 0;                    // mm, see TriBound
  double prism_scale_ = 0;  // largest |offset| of a TriBound (mm), for the rounding bound
  std::vector<std::int32_t> tri_ids_;  // leaf slot -> original triangle id
  std::vector<std::int32_t> slots_;    // original triangle id -> leaf slot (for hints)
  Box3 bounds_;                        // exact bounds of all vertices
  SeedGrid grid_;                      // empty: no seed grid
};

}  // namespace inhap
