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

// Reads binary or ASCII STL (ASCII may hold several `solid` blocks). The file may take a quarter
// of `max_memory_bytes` (0: the memory available); a binary STL is read no further than its
// triangle count says. Throws Error.
TriangleSurface read_stl(const std::filesystem::path& path, double max_memory_bytes = 0);

// Reads OFF, OBJ or PLY (ASCII or binary); polygons are fanned into triangles. Memory as for
// read_stl; a text file (or PLY header) holding a NUL byte is refused from its first bytes.
// Throws Error.
TriangleSurface read_polygon_file(const std::filesystem::path& path, double max_memory_bytes = 0);

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
struct RegionSet;
struct CrackSet;

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
  // The input's coordinates are the stored ones plus `origin`: a part far from the origin (beyond
  // 8 times its size) is stored relative to a corner of it, exactly (load_domain), so that its
  // cells are computed in coordinates of its own size; the mesh is moved back when it is made.
  Vec3 origin{};
  double volume = 0;
  double surface_area = 0;
  std::shared_ptr<const SurfaceLocator> locator;  // inside tests and nearby triangles
  // Several regions (a multi-region solid, paper §2.2 "Non-manifold geometry"): this domain is
  // their union, and the regions' solids and interfaces are here. Null: one region.
  std::shared_ptr<const RegionSet> regions;
  // Crack sheets this domain is cut open along (src/input/cracked_domain.hpp): its surface then
  // holds each sheet twice, one copy facing each side. Null: no cracks.
  std::shared_ptr<const CrackSet> cracks;

  bool contains(Vec3 p) const;
};

// The regions of a multi-region solid: the parts of space its closed surfaces bound, each
// cell of the mesh in exactly one, with interfaces where two touch.
//
// Facets number the planes of all regions alike: a facet is an edge-connected group of coplanar
// triangles with the same region on each side, so one facet is one interface (or one piece of
// the outer boundary) and the vertices that cells name by it agree on both of its sides.
struct RegionSet {
  std::vector<std::string> names;
  // Region k as a domain of its own: its surface oriented out of it, on the shared vertices,
  // `planes` indexed by facet and oriented out of region k (facets it does not touch: as
  // facet_planes), `triangle_plane` its triangles' facets.
  std::vector<Domain> solids;
  std::vector<Plane> facet_planes;                   // normal from facet_sides[f][0] to [1]
  std::vector<std::array<int32_t, 2>> facet_sides;   // region behind the normal, in front (-1: outside)
  // The union with its border triangles on facets (as the mesh's border faces name them).
  Domain boundary;
  // Every edge of every region's surface as (smaller vertex, larger), sorted: the ids that
  // vertices on an input edge are named by, the same in every region.
  std::vector<std::pair<int32_t, int32_t>> edges;
  struct Interface {
    int32_t a = 0, b = 0;  // a < b
    double area = 0;
  };
  std::vector<Interface> interfaces;
  size_t interface_triangles = 0;

  size_t size() const { return names.size(); }
  bool is_interface(int32_t facet) const { return facet_sides[size_t(facet)][1] >= 0; }
  // The region on the other side of facet f from region k.
  int32_t across(int32_t facet, int32_t k) const {
    const auto& s = facet_sides[size_t(facet)];
    return s[0] == k ? s[1] : s[0];
  }
};

struct DomainOptions {
  double feature_angle = kDefaultFeatureAngle;  // degrees
  bool repair = false;  // reorient shells whose triangles are inconsistently wound
  double max_memory_bytes = 0;  // what reading may take: a quarter of it for the file (0: the memory available)
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

// domain_from_surface's domain, stored relative to the part where it lies far from the origin
// (Domain::origin), as load_domain stores a file's.
Domain domain_anywhere(const TriangleSurface& surface, const std::string& name, const DomainOptions& options = {});

// A box spec or a surface file, whichever `input` names. A file whose shells share triangles
// (listed twice, opposite ways: two solids touching along a face) is a multi-region solid, one
// region per solid (Domain::regions).
Domain load_domain(const std::string& input, const DomainOptions& options = {});

// Several closed surfaces, one region each, named `names` (file stems): solids that share
// triangles touch there (an interface), a solid inside another is an inclusion (the outer
// region is the part outside it). Vertices with bit-equal coordinates are one. Returns their
// union with Domain::regions set. Throws Error(InvalidInput) where regions overlap or cross,
// naming the regions and a point.
Domain domain_from_regions(const std::vector<TriangleSurface>& surfaces, const std::vector<std::string>& names,
                           const DomainOptions& options = {});

// Reads every input (files only) and makes them one multi-region domain (one input: load_domain).
Domain load_regions(const std::vector<std::string>& inputs, const DomainOptions& options = {});

// `solid` (as load_domain or load_regions makes it) cut open along the crack sheets in `sheets` (STL,
// OFF, OBJ or PLY files, in the solid's coordinates, each named by its file's stem): each sheet
// is clipped to the solid (reported), and the mesh of the returned domain has each sheet's
// faces twice, on patches crack_NAME_a and crack_NAME_b, sharing vertices only along the front.
// A sheet may reach the solid's surface (a through or edge crack), be closed (a lens) or end
// inside the solid (a penny: the cells at its front are split there when the mesh is made, at
// its r). Sheets may cross each other, and in a multi-region solid cross interfaces (not end
// at one, nor have a front within 2r of one: Usage, not supported yet). Throws Error:
// InvalidInput naming the defect and a point (see input/cracks.hpp), Usage for what is not
// supported.
Domain load_cracks(const Domain& solid, const std::vector<std::string>& sheets, const DomainOptions& options = {});

}  // namespace froth
