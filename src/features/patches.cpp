#include "features/patches.hpp"

#include <algorithm>
#include <utility>

#include "common/union_find.hpp"

namespace froth {

std::vector<int32_t> smooth_regions(const TriangleSurface& s, const SurfaceFeatures& features, size_t& count) {
  auto key = [](int32_t a, int32_t b) { return std::pair{std::min(a, b), std::max(a, b)}; };
  std::vector<std::pair<int32_t, int32_t>> feature_edges;
  for (const FeatureCurve& c : features.curves)
    for (size_t k = 0; k + 1 < c.vertices.size(); ++k) feature_edges.push_back(key(c.vertices[k], c.vertices[k + 1]));
  std::sort(feature_edges.begin(), feature_edges.end());
  // Each edge with the triangles on it: sorted, the two uses of an edge are neighbours.
  std::vector<std::pair<std::pair<int32_t, int32_t>, int32_t>> uses;
  uses.reserve(3 * s.triangles.size());
  for (size_t t = 0; t < s.triangles.size(); ++t)
    for (int e = 0; e < 3; ++e) uses.push_back({key(s.triangles[t][e], s.triangles[t][(e + 1) % 3]), int32_t(t)});
  std::sort(uses.begin(), uses.end());
  UnionFind sets(s.triangles.size());
  for (size_t k = 0; k + 1 < uses.size(); ++k)
    if (uses[k].first == uses[k + 1].first &&
        !std::binary_search(feature_edges.begin(), feature_edges.end(), uses[k].first))
      sets.unite(uses[k].second, uses[k + 1].second);
  std::vector<int32_t> region(s.triangles.size()), number(s.triangles.size(), -1);
  count = 0;
  for (size_t t = 0; t < s.triangles.size(); ++t) {
    const int32_t root = sets.find(int32_t(t));
    if (number[root] < 0) number[root] = int32_t(count++);
    region[t] = number[root];
  }
  return region;
}

}  // namespace froth
