// Point-set preprocessing before surface reconstruction (thesis sec. 3.3.1). Units: mm.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "inhap/core/types.hpp"

namespace inhap {

/// The k nearest neighbours of every point (itself excluded; exact duplicates count), as a
/// row-major n x k' table with k' = min(k, n - 1), nearest first (CGAL kd-tree).
struct KnnTable {
  std::size_t k = 0;
  std::vector<std::int32_t> index;  ///< n * k neighbour indices
  std::vector<double> distance;     ///< n * k distances, mm
};
KnnTable knn_table(std::span<const Vec3> points, std::size_t k);

/// The k nearest `sites` of each query (row-major queries x k', k' = min(k, sites), nearest
/// first).
KnnTable knn_query(std::span<const Vec3> sites, std::span<const Vec3> queries, std::size_t k);

/// Nearest of `sites` to each query: index (-1 when sites is empty) and distance (mm, +inf).
struct NearestSites {
  std::vector<std::int32_t> index;
  std::vector<double> distance;
};
NearestSites nearest_sites(std::span<const Vec3> sites, std::span<const Vec3> queries);
inline std::vector<double> nearest_distances(std::span<const Vec3> sites,
                                             std::span<const Vec3> queries) {
  return nearest_sites(sites, queries).distance;
}

/// Mean distance from each point to its k nearest neighbours, mm.
std::vector<double> knn_mean_distances(std::span<const Vec3> points, std::size_t k);

/// k-NN mean-distance outlier removal: a point whose mean distance to its k nearest neighbours
/// exceeds median + `sigmas` * 1.4826 * MAD of all such distances (a robust z-score) is
/// "abnormally far" and dropped. Returns the indices kept, in input order.
std::vector<std::size_t> remove_knn_outliers(std::span<const Vec3> points, std::size_t k,
                                             double sigmas);

/// Jet smoothing: fits a second-order height function z = c0 + c1 x + c2 y + c3 x^2 + c4 xy +
/// c5 y^2 over the local PCA frame of the point and its k nearest neighbours (an osculating
/// jet, Cazals & Pouget 2005, as CGAL's jet_smooth_point_set with degree 2) and moves the point
/// onto it along the frame normal. Points whose fit is singular are kept as they are.
std::vector<Vec3> jet_smooth(std::span<const Vec3> points, std::size_t k);
/// The same with outward directions known per point (e.g. contact force directions): only
/// neighbours whose direction is within 90 deg of the point's count (of its 3k nearest, the
/// first k such), so the two sides of a thin part (an ear tapped front and back) are not
/// averaged into its middle. Empty `directions`: jet_smooth(points, k).
std::vector<Vec3> jet_smooth(std::span<const Vec3> points, std::size_t k,
                             std::span<const Vec3> directions, double min_cos = 0.0,
                             double feature_factor = 0.0);

/// Moves each query onto the second-order jet (as jet_smooth) fitted to its k nearest
/// `points` alone, along the jet frame's normal: puts the vertices of a mesh built from the
/// points back onto the sampled surface (subdivision and smoothing pull a coarse mesh inward on
/// convex parts by about e^2 / (8 R) for edges e on radius R). Queries whose fit is singular,
/// or that would move farther than `max_move` mm, stay where they are.
std::vector<Vec3> project_onto_jets(std::span<const Vec3> points, std::span<const Vec3> queries,
                                    std::size_t k, double max_move,
                                    std::span<const Vec3> directions = {}, double min_cos = 0.0);

/// Unit normals by PCA of each point and its k nearest neighbours (smallest-variance axis),
/// unoriented (sign arbitrary).
std::vector<Vec3> pca_normals(std::span<const Vec3> points, std::size_t k);

/// Deterministic jitter of at most `amplitude` mm per coordinate (uniform, seeded).
std::vector<Vec3> jitter(std::span<const Vec3> points, double amplitude, std::uint64_t seed);

}  // namespace inhap
