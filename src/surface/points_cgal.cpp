// k-nearest-neighbour search with CGAL's kd-tree. One of the three CGAL translation units of
// the surface module.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/property_map.h>
#include <CGAL/boost/iterator/counting_iterator.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "inhap/surface/points.hpp"

namespace inhap {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using PointMap = CGAL::Pointer_property_map<Point>::type;
using Traits = CGAL::Search_traits_adapter<std::size_t, PointMap, CGAL::Search_traits_3<K>>;
using Search = CGAL::Orthogonal_k_neighbor_search<Traits>;
using Tree = Search::Tree;
using Distance = Search::Distance;

}  // namespace

KnnTable knn_table(std::span<const Vec3> points, std::size_t k) {
  KnnTable table;
  const std::size_t n = points.size();
  if (n < 2 || k == 0) return table;
  k = std::min(k, n - 1);
  table.k = k;
  table.index.assign(n * k, -1);
  table.distance.assign(n * k, 0.0);
  std::vector<Point> pts;
  pts.reserve(n);
  for (const Vec3& p : points) pts.emplace_back(p.x(), p.y(), p.z());
  PointMap pmap = CGAL::make_property_map(pts);
  Tree tree(boost::counting_iterator<std::size_t>(0), boost::counting_iterator<std::size_t>(n),
            Tree::Splitter(), Traits(pmap));
  tree.build();
  Distance dist(pmap);
  for (std::size_t i = 0; i < n; ++i) {
    Search search(tree, pts[i], static_cast<unsigned>(k + 1), 0, true, dist);
    std::size_t count = 0;
    for (const auto& [j, d2] : search) {
      if (j == i || count == k) continue;
      table.index[i * k + count] = static_cast<std::int32_t>(j);
      table.distance[i * k + count] = std::sqrt(d2);
      ++count;
    }
    // i was not among its k+1 nearest (more than k exact duplicates): fill with the last.
    for (; count < k && count > 0; ++count) {
      table.index[i * k + count] = table.index[i * k + count - 1];
      table.distance[i * k + count] = table.distance[i * k + count - 1];
    }
  }
  return table;
}

KnnTable knn_query(std::span<const Vec3> sites, std::span<const Vec3> queries, std::size_t k) {
  KnnTable table;
  if (sites.empty() || k == 0) return table;
  k = std::min(k, sites.size());
  table.k = k;
  table.index.assign(queries.size() * k, -1);
  table.distance.assign(queries.size() * k, 0.0);
  std::vector<Point> pts;
  pts.reserve(sites.size());
  for (const Vec3& p : sites) pts.emplace_back(p.x(), p.y(), p.z());
  PointMap pmap = CGAL::make_property_map(pts);
  Tree tree(boost::counting_iterator<std::size_t>(0),
            boost::counting_iterator<std::size_t>(pts.size()), Tree::Splitter(), Traits(pmap));
  tree.build();
  Distance dist(pmap);
  for (std::size_t i = 0; i < queries.size(); ++i) {
    Search search(tree, Point(queries[i].x(), queries[i].y(), queries[i].z()),
                  static_cast<unsigned>(k), 0, true, dist);
    std::size_t count = 0;
    for (const auto& [j, d2] : search) {
      if (count == k) break;
      table.index[i * k + count] = static_cast<std::int32_t>(j);
      table.distance[i * k + count] = std::sqrt(d2);
      ++count;
    }
  }
  return table;
}

NearestSites nearest_sites(std::span<const Vec3> sites, std::span<const Vec3> queries) {
  NearestSites out;
  out.index.assign(queries.size(), -1);
  out.distance.assign(queries.size(), std::numeric_limits<double>::infinity());
  if (sites.empty()) return out;
  const KnnTable t = knn_query(sites, queries, 1);  // the same k-d tree search with k = 1
  for (std::size_t i = 0; i < queries.size(); ++i) {
    if (t.index[i] < 0) continue;
    out.index[i] = t.index[i];
    out.distance[i] = t.distance[i];
  }
  return out;
}

}  // namespace inhap
