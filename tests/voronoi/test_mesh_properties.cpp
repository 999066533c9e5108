// The paper's guarantees on whole meshes (welding off), for several seeds and radii, on a box and
// on the icosphere: empty disk, maximality (Lemma 1), volume sum, closed cells, matched faces,
// the r/2 ball in interior cells (Lemma 2) and interior dihedral angles in [60, 150] (Lemma 6).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <tuple>

#include <fmt/format.h>

#include "common/closed_edges.hpp"
#include "common/test_support.hpp"

namespace froth {
namespace {

struct Case {
  std::string domain;
  double r;
  uint64_t seed;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.domain << " r=" << c.r << " seed=" << c.seed; }

class MeshProperties : public testing::TestWithParam<Case> {};

TEST_P(MeshProperties, PaperGuaranteesHold) {
  const Case& k = GetParam();
  Domain d = load_domain(k.domain == "sphere" ? test::model("unit_sphere.STL") : k.domain);
  RunReport run;
  PolyMesh m = test::mesh_of(d, k.r, k.seed, 2, &run);
  const double r = k.r;
  ASSERT_GT(m.cell_count(), 50u);

  EXPECT_GE(test::min_seed_distance(m.seeds, r), r);  // empty disk

  MeshCheck check = check_mesh(m);
  EXPECT_TRUE(check.ok()) << check.first_problem;

  double sum = 0;
  size_t interior = 0, border_faces = 0;
  double border_area = 0;
  for (size_t c = 0; c < m.cell_count(); ++c) {
    double v = cell_volume(m, c);
    EXPECT_GT(v, 0);
    EXPECT_NEAR(v, m.volumes[c], 1e-12 * r * r * r);
    sum += v;
    const Vec3 x = m.seeds[c];
    bool border = false;
    for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) {
      border |= m.face_generator[f] < 0;
      for (int64_t i = m.face_vertex_begin[f]; i < m.face_vertex_begin[f + 1]; ++i)
        EXPECT_LE(norm(m.points[m.face_vertices[i]] - x), r * (1 + 1e-6)) << "Lemma 1, cell " << c;
      if (m.face_generator[f] < 0) {
        ++border_faces;
        Vec3 a2;
        int64_t b = m.face_vertex_begin[f], e = m.face_vertex_begin[f + 1];
        for (int64_t i = b + 1; i + 1 < e; ++i)
          a2 = a2 + cross(m.points[m.face_vertices[i]] - m.points[m.face_vertices[b]],
                          m.points[m.face_vertices[i + 1]] - m.points[m.face_vertices[b]]);
        border_area += norm(a2) / 2;
      }
    }
    EXPECT_EQ(border, m.kinds[c] == CellKind::Fringe);
    if (border) continue;
    ++interior;
    // Lemma 2: the ball of radius r/2 at the seed lies inside the interior cell.
    for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) {
      double gap = dot(test::face_normal(m, f), test::face_centroid(m, f) - x);
      EXPECT_GE(gap, r / 2 * (1 - 1e-9)) << "Lemma 2, cell " << c;
    }
    // Lemma 6: interior dihedral angles in [60, 150] degrees.
    for (double a : test::dihedral_angles(m, c)) {
      EXPECT_GE(a, 60 - 1e-6) << "Lemma 6, cell " << c;
      EXPECT_LE(a, 150 + 1e-6) << "Lemma 6, cell " << c;
    }
  }
  EXPECT_GT(interior, 0u);
  EXPECT_NEAR(sum, d.volume, 1e-9 * d.volume);
  EXPECT_NEAR(run.volume_sum, d.volume, 1e-9 * d.volume);
  EXPECT_NEAR(border_area, d.surface_area, 1e-9 * d.surface_area);
  EXPECT_EQ(run.cells, m.cell_count());
}

INSTANTIATE_TEST_SUITE_P(
    BoxAndSphere, MeshProperties,
    testing::Values(Case{"box:0,0,0,1,1,1", 0.1, 1}, Case{"box:0,0,0,1,1,1", 0.1, 2},
                    Case{"box:-1,0,2,1.5,0.7,2.9", 0.07, 3}, Case{"box:0,0,0,1,1,1", 0.05, 4},
                    Case{"sphere", 0.2, 1}, Case{"sphere", 0.1, 2}, Case{"sphere", 0.1, 3},
                    Case{"sphere", 0.06, 4}),
    [](const testing::TestParamInfo<Case>& i) {
      return fmt::format("{}_r{}_seed{}", i.param.domain == "sphere" ? "sphere" : "box" + std::to_string(i.index),
                         int(std::round(i.param.r * 1000)), i.param.seed);
    });

TEST(MeshDeterminism, SameSeedSameMeshForOneAndTwoThreads) {
  Domain d = load_domain(test::model("unit_sphere.STL"));
  PolyMesh a = test::mesh_of(d, 0.12, 5, 1), b = test::mesh_of(d, 0.12, 5, 2);
  EXPECT_EQ(a.face_vertices, b.face_vertices);
  EXPECT_EQ(a.face_generator, b.face_generator);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (size_t i = 0; i < a.points.size(); ++i) EXPECT_EQ(norm2(a.points[i] - b.points[i]), 0.0);
}

TEST(MeshErrors, BadParametersAreUsageErrors) {
  Domain d = make_box_domain({0, 0, 0}, {1, 1, 1});
  for (double r : {0.0, -1.0, double(NAN)}) {
    try {
      test::mesh_of(d, r, 1, 1);
      ADD_FAILURE() << "r = " << r << " accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::Usage);
    }
  }
}

}  // namespace
}  // namespace froth

namespace froth {
namespace {

// The hashed edge count agrees with sorting on prisms over n-gons, small and large enough to
// grow the table, closed or with a face missing, reversed or given twice, reused after clear().
TEST(EdgeUses, TellsClosedSurfacesLikeSorting) {
  EdgeUses uses;
  for (uint32_t n : {3u, 40u, 300u})
    for (int defect = 0; defect < 4; ++defect) {
      std::vector<std::vector<uint32_t>> faces;  // bottom 0..n-1, top n..2n-1
      std::vector<uint32_t> bottom, top;
      for (uint32_t k = 0; k < n; ++k) bottom.push_back(n - 1 - k), top.push_back(n + k);
      faces.push_back(bottom), faces.push_back(top);
      for (uint32_t k = 0; k < n; ++k) faces.push_back({k, (k + 1) % n, n + (k + 1) % n, n + k});
      if (defect == 1) faces.pop_back();
      if (defect == 2) std::reverse(faces[2].begin(), faces[2].end());
      if (defect == 3) faces.push_back(faces[2]);
      uses.clear();
      std::vector<uint64_t> keys;
      for (const auto& f : faces)
        for (size_t k = 0; k < f.size(); ++k) {
          uses.add(f[k], f[(k + 1) % f.size()]);
          keys.push_back(directed_edge_key(f[k], f[(k + 1) % f.size()]));
        }
      EXPECT_EQ(uses.each_once_each_way(), defect == 0) << n << "-gon prism, defect " << defect;
      EXPECT_EQ(each_edge_once_each_way(keys), defect == 0) << n << "-gon prism, defect " << defect;
    }
}

// The final check must catch what it promises to catch.
TEST(MeshCheckDetects, UnmatchedFaceOpenCellAndNegativeVolume) {
  Domain d = make_box_domain({0, 0, 0}, {1, 1, 1});
  PolyMesh good = test::mesh_of(d, 0.2, 4, 1);
  ASSERT_TRUE(check_mesh(good).ok());
  // An interior face of cell 0 and the cell behind it.
  int64_t f = good.cell_face_begin[0];
  while (good.face_generator[f] < 0) ++f;

  PolyMesh m = good;  // one vertex of the face replaced: its twin no longer matches, cell 0 opens
  m.face_vertices[m.face_vertex_begin[f]] = m.face_vertices[m.face_vertex_begin[f] + 1];
  MeshCheck c = check_mesh(m);
  EXPECT_FALSE(c.ok());
  EXPECT_GE(c.unmatched_faces, 1u);
  EXPECT_GE(c.open_cells, 1u);
  EXPECT_NE(c.first_problem.find("cell"), std::string::npos);

  m = good;  // a face given twice: its edges run twice each way
  {
    const int64_t fb = m.face_vertex_begin[f], fe = m.face_vertex_begin[f + 1];
    m.face_vertices.insert(m.face_vertices.begin() + fe, m.face_vertices.begin() + fb, m.face_vertices.begin() + fe);
    m.face_vertex_begin.insert(m.face_vertex_begin.begin() + f + 1, fe);
    for (size_t k = size_t(f) + 2; k < m.face_vertex_begin.size(); ++k) m.face_vertex_begin[k] += fe - fb;
    m.face_generator.insert(m.face_generator.begin() + f + 1, m.face_generator[f]);
    for (size_t c = 1; c < m.cell_face_begin.size(); ++c) ++m.cell_face_begin[c];
    EXPECT_GE(check_mesh(m).open_cells, 1u);
  }

  m = good;  // one triangle of cell 0's first face cut off as a face of its own: an edge used
             // three times
  {
    const int64_t g = m.cell_face_begin[0], fb = m.face_vertex_begin[g];
    const std::vector<int32_t> tri = {m.face_vertices[fb], m.face_vertices[fb + 1], m.face_vertices[fb + 2]};
    m.face_vertices.insert(m.face_vertices.begin() + m.face_vertex_begin[g + 1], tri.begin(), tri.end());
    m.face_vertex_begin.insert(m.face_vertex_begin.begin() + g + 1, m.face_vertex_begin[g + 1]);
    for (size_t k = size_t(g) + 2; k < m.face_vertex_begin.size(); ++k) m.face_vertex_begin[k] += 3;
    m.face_generator.insert(m.face_generator.begin() + g + 1, m.face_generator[g]);
    for (size_t c = 1; c < m.cell_face_begin.size(); ++c) ++m.cell_face_begin[c];
    EXPECT_GE(check_mesh(m).open_cells, 1u);
  }

  m = good;  // a face of cell g toward a later cell X said to face an earlier neighbour c
  {           // instead: g now has two faces toward c, and X's face toward g no twin
    bool done = false;
    for (size_t g = 1; g < m.cell_count() && !done; ++g) {
      int32_t earlier = -1;
      int64_t later_face = -1;
      for (int64_t h = m.cell_face_begin[g]; h < m.cell_face_begin[g + 1]; ++h) {
        const int32_t x = m.face_generator[h];
        if (x >= 0 && size_t(x) < g) earlier = x;
        if (x >= 0 && size_t(x) > g) later_face = h;
      }
      if (earlier >= 0 && later_face >= 0) m.face_generator[later_face] = earlier, done = true;
    }
    ASSERT_TRUE(done);
    const MeshCheck c = check_mesh(m);
    EXPECT_GE(c.unmatched_faces, 1u);
    EXPECT_EQ(c.open_cells, 0u);
  }

  m = good;  // the face reversed: still closed, but not the twin of the neighbour's face
  std::reverse(m.face_vertices.begin() + m.face_vertex_begin[f], m.face_vertices.begin() + m.face_vertex_begin[f + 1]);
  EXPECT_GE(check_mesh(m).unmatched_faces, 1u);

  m = good;  // every face of cell 0 reversed: closed, matched nowhere, negative volume
  for (int64_t g = m.cell_face_begin[0]; g < m.cell_face_begin[1]; ++g)
    std::reverse(m.face_vertices.begin() + m.face_vertex_begin[g], m.face_vertices.begin() + m.face_vertex_begin[g + 1]);
  m.volumes.clear();  // recomputed by the check
  c = check_mesh(m);
  EXPECT_GE(c.nonpositive_cells, 1u);
  EXPECT_GE(c.unmatched_faces, 1u);
}

}  // namespace
}  // namespace froth
