// A convex polyhedron cut by half-spaces, in coordinates relative to its seed (so round-off is
// relative to the cell's size, not the domain's).
//
// It is stored in its dual form, after geogram's ConvexCell and Ray et al. 2018 ("Meshless
// Voronoi on the GPU"): each vertex is a triangle of the three planes through it, with the three
// triangles across its edges. A cut only touches the vertices it removes and the ring around
// them, so its cost does not grow with the size of the cell, and a vertex's name (the generators
// of its planes) comes for free: that name is what makes neighbouring cells agree on shared
// vertices. Near-degenerate input is handled by snapping: a vertex within `eps` of a cutting plane
// lies on it; the new vertices on its edges are put exactly at its position and merged with it
// when the faces are read, so it joins the new face and its name gains the new generator.
#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "froth/geometry.hpp"

namespace froth {

class ConvexCell {
 public:
  static constexpr int kMaxGenerators = 8;
  static constexpr int kMaxPlanes = 255;  // plane ids are bytes
  // Generators of the six faces of the initial cube; a finished cell must have none left.
  static constexpr int32_t kCubeGenerator = std::numeric_limits<int32_t>::min();
  static bool is_cube_generator(int32_t g) { return g < kCubeGenerator + 6; }

  // The generators of the faces through a vertex.
  struct Names {
    uint8_t n = 0;
    int32_t gen[kMaxGenerators] = {};  // all set: readers may copy the whole array
    bool has(int32_t g) const {
      for (int i = 0; i < n; ++i)
        if (gen[i] == g) return true;
      return false;
    }
    // The same generators in the same order (names are compared sorted).
    bool same_as(const Names& o) const {
      if (n != o.n) return false;
      for (int i = 0; i < n; ++i)
        if (gen[i] != o.gen[i]) return false;
      return true;
    }
    uint64_t hash() const {
      uint64_t h = n;
      for (int i = 0; i < n; ++i) h = (h ^ uint32_t(gen[i])) * 0x9E3779B97F4A7C15ull;
      return h;
    }
  };

  enum class Clip { Unchanged, Cut, Empty, Failed };

  // Decides near ties between seeds exactly (voronoi/seed_ties.hpp): a vertex whose three planes
  // are seed bisectors, within band() of a seed's bisector, is cut or kept as conflict() says,
  // never snapped onto the plane, so every cell around it decides alike. Generators >= 0 are
  // seeds; the cell's own seed is `self` in clip().
  struct TieBreaker {
    virtual ~TieBreaker() = default;
    virtual double band() const = 0;
    // +1 / -1: seed e is / is not in conflict with the vertex of seeds a, b, c, d; 0: undecided.
    virtual int conflict(int32_t a, int32_t b, int32_t c, int32_t d, int32_t e) const = 0;
  };

  // The cube [-half, half]^3.
  void reset_cube(double half);
  // Keeps {p : dot(normal, p) <= offset}; `normal` should be of unit length so `eps` is a
  // distance.
  // With `ties`, a seed's bisector (generator >= 0) decides the near ties of seed vertices
  // exactly; `self` is the cell's seed.
  Clip clip(Vec3 normal, double offset, int32_t generator, double eps, const TieBreaker* ties = nullptr,
            int32_t self = -1);

  // The largest squared distance of a vertex from the origin (the seed).
  double max_radius2() const;
  // The largest squared distance from the origin of a vertex the last cut made (a vertex of its
  // new face): a lower bound on max_radius2() until the next cut.
  double new_face_radius2() const { return new_face_radius2_; }
  // The faces as polygons, built on first use after a cut: vertices that coincide (snapped
  // degenerate vertices) are one.
  size_t vertex_count() const { return final().points.size(); }
  size_t face_count() const { return final().face_gen.size(); }
  Vec3 vertex(size_t v) const { return final().points[v]; }
  int32_t face_generator(size_t f) const { return final().face_gen[f]; }
  // Vertex indices of face f, counter-clockwise seen from outside.
  const uint16_t* face_begin(size_t f) const { return final().face_vert.data() + final().face_start[f]; }
  size_t face_size(size_t f) const { return final().face_start[f + 1] - final().face_start[f]; }
  double volume() const;
  // Names of all vertices; false if a vertex lies on more than kMaxGenerators faces.
  bool vertex_names(std::vector<Names>& names) const;

 private:
  static constexpr uint16_t kNone = 0xFFFF;
  struct PlaneRec {
    Vec3 n;
    double d;
    int32_t gen;
  };
  // Planes p[0], p[1], p[2] around the vertex, counter-clockwise seen from outside; adj[k] is the
  // triangle across the edge opposite p[k], that is the edge (p[k+1], p[k+2]).
  struct Tri {
    uint8_t p[3];
    uint16_t adj[3];
  };
  struct Faces {
    std::vector<Vec3> points;
    std::vector<int32_t> face_gen;
    std::vector<uint32_t> face_start;
    std::vector<uint16_t> face_vert;
    std::vector<uint16_t> vertex_of_tri;  // merged vertex of each triangle
  };
  const Faces& final() const {
    if (!faces_valid_) build_faces();
    return faces_;
  }
  void build_faces() const;
  void merge_coincident() const;
  bool compact_planes();
  uint16_t find(uint16_t t) const;

  std::vector<PlaneRec> planes_;
  std::vector<Tri> tri_;
  std::vector<Vec3> pos_;

  // Scratch, kept to avoid allocation in the hot loop.
  std::vector<double> sd_;
  std::vector<uint8_t> out_;
  std::vector<uint8_t> exact_;  // per vertex, in a cut with ties: decided by the tie-breaker
  struct Border {  // an edge of the removed region: from plane u to plane v
    uint8_t u, v, outer_slot;
    uint16_t outer;
    Vec3 pos;
  };
  std::vector<Border> border_;
  std::vector<uint16_t> slots_;
  std::array<uint16_t, 256> border_from_;  // border edge leaving each plane, or kNone

  double new_face_radius2_ = 0;
  bool coincident_ = false;  // an edge of zero length was made since reset_cube (snapping)
  mutable bool faces_valid_ = false;
  mutable bool rmax_valid_ = false;
  mutable double rmax2_ = 0;
  mutable Faces faces_;
  mutable std::vector<uint16_t> parent_;
  mutable std::vector<uint16_t> plane_tri_;
};

}  // namespace froth
