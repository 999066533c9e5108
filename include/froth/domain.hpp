// The domain to mesh: a box, or the solid a closed triangle surface encloses (several shells,
// cavities found by nesting). A convex domain is the intersection of the inner half-spaces of its
// facet planes, and its cells are cut by those planes alone; any other domain is clipped against
// its surface (src/clip).
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "froth/geometry.hpp"

namespace froth {

struct TriangleSurface {
  std::vector<Vec3> vertices;                  // merged exactly (bit-equal coordinates)
  std::vector<std::array<int32_t, 3>> triangles;
  // Named surface patches (boundary conditions go on them): each triangle's patch, an index
  // into patch_names. From an ASCII STL's `solid` blocks or an OBJ's `g`/`o` groups; empty when
  // the file names none (load_domain then splits the surface at its feature curves).
  std::vector<int32_t> triangle_patch;
  std::vector<std::string> patch_names;
};

// Reads binary or ASCII STL (ASCII may hold several `solid` blocks). Throws Error.
TriangleSurface read_stl(const std::filesystem::path& path);

// Reads OFF, OBJ or PLY (ASCII or binary); polygons are fanned into triangles. Throws Error.
TriangleSurface read_polygon_file(const std::filesystem::path& path);

// Counts of the input surface's features (see src/features).
struct FeatureSummary {
  double angle_degrees = 0;  // edges turning by more than this are features
  size_t flat_edges = 0, convex_edges = 0, reflex_edges = 0;
  // Flat edges that turn the reflex way (a concave curved surface's facets): not protected, so
  // the cells along such a surface are star-shaped only up to its curvature.
  size_t flat_reflex_edges = 0;
  size_t curves = 0, convex_curves = 0, reflex_curves = 0, corners = 0;
};

// The default feature angle: the facets of a curved surface tessellated finely enough to mesh
// at r turn by a few degrees at each edge (3.1 to 5.8 on the 1280-triangle icosphere, less on
// the torus), while machined edges turn by 45 to 90 degrees; 30 separates the two with room on
// both sides (the shared models' README counts sharp edges at the same 30).
inline constexpr double kDefaultFeatureAngle = 30;


class SurfaceLocator;

struct Domain {
  std::string description;      // "box:..." or the file name
  FeatureSummary features;
  bool convex = true;           // one convex shell
  std::vector<Plane> planes;    // facet planes (edge-connected coplanar triangles share one), outward
  TriangleSurface surface;      // oriented out of the solid: a cavity's shell faces into the cavity
  std::vector<int32_t> triangle_plane;  // each triangle's facet plane
  // Reflex feature curves (paper §2.2), the ones protection seeds, as chains of surface
  // vertices; a closed one repeats its first vertex at the end. Reflex edges below the feature
  // angle (the facets of a concave curved surface) are flat and not protected.
  std::vector<std::vector<int32_t>> reflex_curves;
  size_t shells = 1, cavities = 0;
  size_t reoriented_triangles = 0;      // flipped by --repair
  Box bounds;
  double volume = 0;
  double surface_area = 0;
  std::shared_ptr<const SurfaceLocator> locator;  // inside tests and nearby triangles

  bool contains(Vec3 p) const;
};

struct DomainOptions {
  double feature_angle = kDefaultFeatureAngle;  // degrees
  bool repair = false;  // reorient shells whose triangles are inconsistently wound
};

Domain make_box_domain(Vec3 lo, Vec3 hi);

// Parses "box:X0,Y0,Z0,X1,Y1,Z1". Throws Error(Usage) when malformed.
Domain parse_box_spec(const std::string& spec);

// A surface built in memory, made a domain as load_domain makes a file's: validates it (finite,
// no degenerate triangle, closed, edge-manifold, consistently oriented, no self-intersection;
// exact predicates), finds its shells and their nesting, orients them, groups facet planes,
// decides whether the solid is convex, and finds its feature edges and the reflex curves that
// get protection seeds. Throws Error(InvalidInput) naming the first defect and where it is, or
// Error(Usage) for a feature angle outside (0, 180). `name` is used in error messages.
Domain domain_from_surface(const TriangleSurface& surface, const std::string& name, const DomainOptions& options = {});

// A box spec or a surface file, whichever `input` names.
Domain load_domain(const std::string& input, const DomainOptions& options = {});

}  // namespace froth
