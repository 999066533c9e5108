// OFF, OBJ and PLY (ASCII or binary) through CGAL's polygon-soup reader. Polygons are fanned
// into triangles; vertices with bit-equal coordinates are merged, as for STL, so the same
// validation applies whatever the format.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/polygon_soup_io.h>

#include <cmath>
#include <fstream>

#include <fmt/format.h>

#include "froth/domain.hpp"
#include "froth/error.hpp"
#include "input/vertex_merger.hpp"

namespace froth {

TriangleSurface read_polygon_file(const std::filesystem::path& path) {
  if (!std::ifstream(path)) fail(ErrorKind::Io, fmt::format("cannot open {}", path.string()));
  using Point = CGAL::Exact_predicates_inexact_constructions_kernel::Point_3;
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> polygons;
  bool ok = false;
  try {
    ok = CGAL::IO::read_polygon_soup(path.string(), points, polygons, CGAL::parameters::verbose(false));
  } catch (const std::exception& e) {
    fail(ErrorKind::InvalidInput, fmt::format("{}: cannot be read: {}", path.string(), e.what()));
  }
  if (!ok || polygons.empty())
    fail(ErrorKind::InvalidInput, fmt::format("{}: not a readable {} surface (or no faces in it)", path.string(),
                                              path.extension().string()));
  TriangleSurface s;
  VertexMerger merge(s);
  std::vector<int32_t> id(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const Vec3 p{points[i].x(), points[i].y(), points[i].z()};
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      fail(ErrorKind::InvalidInput,
           fmt::format("{}: vertex {} has a coordinate that is not a finite number ({}, {}, {})", path.string(), i,
                       p.x, p.y, p.z));
    id[i] = merge.add(p);
  }
  for (size_t f = 0; f < polygons.size(); ++f) {
    const auto& poly = polygons[f];
    if (poly.size() < 3)
      fail(ErrorKind::InvalidInput, fmt::format("{}: face {} has {} vertices", path.string(), f, poly.size()));
    for (std::size_t v : poly)
      if (v >= points.size())
        fail(ErrorKind::InvalidInput, fmt::format("{}: face {} uses vertex {}, but there are only {}", path.string(),
                                                  f, v, points.size()));
    for (size_t k = 1; k + 1 < poly.size(); ++k) s.triangles.push_back({id[poly[0]], id[poly[k]], id[poly[k + 1]]});
  }
  return s;
}

}  // namespace froth
