// The domain to mesh. This foundation handles convex domains: the intersection of the inner
// half-spaces of the boundary's distinct facet planes.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "froth/geometry.hpp"

namespace froth {

struct TriangleSurface {
  std::vector<Vec3> vertices;                  // merged exactly (bit-equal coordinates)
  std::vector<std::array<int32_t, 3>> triangles;
};

// Reads binary or ASCII STL (ASCII may hold several `solid` blocks). Throws Error.
TriangleSurface read_stl(const std::filesystem::path& path);

// Reads OFF, OBJ or PLY (ASCII or binary); polygons are fanned into triangles. Throws Error.
TriangleSurface read_polygon_file(const std::filesystem::path& path);

// Counts of the input surface's features (see src/features).
struct FeatureSummary {
  double angle_degrees = 0;  // edges turning by more than this are features
  size_t flat_edges = 0, convex_edges = 0, reflex_edges = 0;
  size_t curves = 0, convex_curves = 0, reflex_curves = 0, corners = 0;
};

// The default feature angle: the facets of a curved surface tessellated finely enough to mesh
// at r turn by a few degrees at each edge (3.1 to 5.8 on the 1280-triangle icosphere, less on
// the torus), while machined edges turn by 45 to 90 degrees; 30 separates the two with room on
// both sides (the shared models' README counts sharp edges at the same 30).
inline constexpr double kDefaultFeatureAngle = 30;

struct ConvexDomain {
  std::string description;      // "box:..." or the file name
  FeatureSummary features;
  std::vector<Plane> planes;    // distinct facet planes, outward normals
  Box bounds;
  double volume = 0;
  double surface_area = 0;

  bool contains(Vec3 p) const {
    for (const Plane& pl : planes)
      if (pl.signed_distance(p) > 0) return false;
    return true;
  }
};

ConvexDomain make_box_domain(Vec3 lo, Vec3 hi);

// Parses "box:X0,Y0,Z0,X1,Y1,Z1". Throws Error(Usage) when malformed.
ConvexDomain parse_box_spec(const std::string& spec);

// Validates that the surface is closed, consistently oriented and convex (exact predicates),
// then returns its distinct facet planes. `name` is used in error messages.
ConvexDomain convex_domain_from_surface(const TriangleSurface& surface, const std::string& name);

// A box spec or a surface file, whichever `input` names; features at `feature_angle` degrees.
ConvexDomain load_domain(const std::string& input, double feature_angle = kDefaultFeatureAngle);

}  // namespace froth
