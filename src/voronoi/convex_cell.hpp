// A convex polyhedron cut by half-spaces, in coordinates relative to its seed (so round-off is
// relative to the cell's size, not the domain's). Every face remembers the generator of its
// plane, so a vertex is named by the generators of the faces through it: that name is what makes
// neighbouring cells agree on shared vertices. Near-degenerate input is handled by snapping: a
// vertex within `eps` of a cutting plane lies on it (no new vertex is made next to it, and it
// joins the new face).
#pragma once
#include <cstdint>
#include <limits>
#include <vector>

#include "froth/geometry.hpp"

namespace froth {

class ConvexCell {
 public:
  static constexpr int kMaxGenerators = 8;
  // Generators of the six faces of the initial cube; a finished cell must have none left.
  static constexpr int32_t kCubeGenerator = std::numeric_limits<int32_t>::min();
  static bool is_cube_generator(int32_t g) { return g < kCubeGenerator + 6; }

  // The generators of the faces through a vertex.
  struct Names {
    uint8_t n = 0;
    int32_t gen[kMaxGenerators];
    bool has(int32_t g) const {
      for (int i = 0; i < n; ++i)
        if (gen[i] == g) return true;
      return false;
    }
  };

  enum class Clip { Unchanged, Cut, Empty, Failed };

  // The cube [-half, half]^3.
  void reset_cube(double half);
  // Keeps {p : dot(normal, p) <= offset}; `normal` should be of unit length so `eps` is a
  // distance.
  Clip clip(Vec3 normal, double offset, int32_t generator, double eps);

  size_t vertex_count() const { return verts_.size(); }
  size_t face_count() const { return face_gen_.size(); }
  Vec3 vertex(size_t v) const { return verts_[v]; }
  int32_t face_generator(size_t f) const { return face_gen_[f]; }
  // Vertex indices of face f, counter-clockwise seen from outside.
  const uint16_t* face_begin(size_t f) const { return face_vert_.data() + face_start_[f]; }
  size_t face_size(size_t f) const { return face_start_[f + 1] - face_start_[f]; }

  double max_radius2() const;
  double volume() const;
  // Names of all vertices; false if a vertex lies on more than kMaxGenerators faces.
  bool vertex_names(std::vector<Names>& names) const;

 private:
  enum Side : uint8_t { In, On, Out };
  uint16_t cut_vertex(uint16_t a, uint16_t b);

  std::vector<Vec3> verts_;
  std::vector<int32_t> face_gen_;
  std::vector<uint32_t> face_start_;
  std::vector<uint16_t> face_vert_;

  // Scratch, kept to avoid allocation in the hot loop.
  std::vector<double> dist_;
  std::vector<Side> side_;
  std::vector<int32_t> new_gen_;
  std::vector<uint32_t> new_start_;
  std::vector<uint16_t> new_vert_;
  struct CutEdge { uint16_t a, b, v; };
  std::vector<CutEdge> cuts_;
  struct CapEdge { uint16_t from, to; };
  std::vector<CapEdge> cap_;
  std::vector<int32_t> remap_;
};

}  // namespace froth
