// Per-cell quality metrics and their summary (paper §3, Theorem 1 and Lemma 6).
#include <CGAL/Min_sphere_of_points_d_traits_3.h>
#include <CGAL/Min_sphere_of_spheres_d.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <bit>
#include <cmath>

#include <nlohmann/json.hpp>

#include "common/cell_points.hpp"
#include "common/face_plane.hpp"
#include "froth/quality.hpp"
#include "quality/inscribed_ball.hpp"

namespace froth {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
// Welzl-type exact algorithm (Fischer & Gärtner's Min_sphere_of_spheres_d), radius in doubles.
using MinSphere = CGAL::Min_sphere_of_spheres_d<CGAL::Min_sphere_of_points_d_traits_3<Kernel, double, CGAL::Tag_true>>;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegree = 180 / kPi;
// Bounds of the paper, with room for round-off only.
constexpr double kTheorem1Aspect = 2 * (1 + 1e-9);
constexpr double kAngleSlack = 1e-7;  // degrees

struct CellScratch {
  std::vector<int32_t> ids;
  std::vector<Kernel::Point_3> points;
  std::vector<Vec3> normals;
  std::vector<double> offsets;
  std::vector<bool> border;
  // An edge's use by a face: its ends a < b (ids below 2^31) as one integer, the face's index in
  // the cell and whether the face runs the edge from a to b.
  struct EdgeUse {
    uint64_t ends, use;
    EdgeUse(int32_t a, int32_t b, uint32_t face, bool forward)
        : ends(uint64_t(a) << 32 | uint32_t(b)), use(uint64_t(face) << 1 | forward) {}
    int32_t a() const { return int32_t(ends >> 32); }
    int32_t b() const { return int32_t(uint32_t(ends)); }
    uint32_t face() const { return uint32_t(use >> 1); }
    bool forward() const { return use & 1; }
  };
  std::vector<EdgeUse> edges;
  // The edges' pairs of uses (indices into `edges`), and the open-addressing table that finds
  // them: an edge's ends, and its use waiting for the other (kNone once paired).
  static constexpr uint64_t kEmpty = ~uint64_t(0);
  static constexpr uint32_t kNone = ~uint32_t(0);
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  struct Slot {
    uint64_t ends = kEmpty;
    uint32_t open = kNone;
  };
  std::vector<Slot> table;
  std::vector<uint32_t> filled;
  // Pairs each use with the next use of its edge, in the order of `edges` (the faces'): a sort of
  // the uses was a tenth of the quality stage.
  void pair_uses() {
    pairs.clear();
    if (table.size() < 2 * edges.size()) table.assign(std::bit_ceil(2 * edges.size()), Slot{});
    const size_t mask = table.size() - 1;
    auto home = [mask](uint64_t e) { return size_t((e * 0x9E3779B97F4A7C15ull) >> 40) & mask; };
    for (uint32_t k = 0; k < uint32_t(edges.size()); ++k) {
      size_t s = home(edges[k].ends);
      while (table[s].ends != kEmpty && table[s].ends != edges[k].ends) s = (s + 1) & mask;
      Slot& slot = table[s];
      if (slot.ends == kEmpty) slot = {edges[k].ends, k}, filled.push_back(uint32_t(s));
      else if (slot.open == kNone) slot.open = k;
      else pairs.emplace_back(slot.open, k), slot.open = kNone;
    }
    for (uint32_t s : filled) table[s] = Slot{};  // empty again for the next cell
    filled.clear();
  }
};

// Lemma 6's half-angle where protection seeds r_e = r/sqrt(2) apart make it: sin(theta) >= sqrt(2)/4
// (paper §3.2), 20.7 degrees, instead of 30.
const double kProtectedTheta = std::asin(std::sqrt(2.0) / 4) * 180 / M_PI;

struct Dihedral {
  double degrees;
  DihedralClass cls;
  bool relaxed;  // its faces come from protection seeds r_e apart (see judge)
};

bool is_protection_seed(const PolyMesh& m, int32_t generator) {
  if (generator == kOtherPieceProtected) return true;
  return generator >= 0 && size_t(generator) < m.kinds.size() && m.kinds[generator] >= CellKind::Edge;
}

// Fills everything but the summary; `angles` receives each edge's dihedral.
CellQuality measure(const PolyMesh& m, size_t c, CellScratch& w, std::vector<Dihedral>* angles) {
  CellQuality q;
  const Vec3 o = m.seeds[c];
  const int64_t f0 = m.cell_face_begin[c], f1 = m.cell_face_begin[c + 1];
  w.ids.clear();
  w.normals.clear();
  w.offsets.clear();
  w.border.clear();
  w.edges.clear();
  for (int64_t f = f0; f < f1; ++f) {
    const int64_t b = m.face_vertex_begin[f], e = m.face_vertex_begin[f + 1];
    for (int64_t k = b; k < e; ++k) {
      const int32_t a = m.face_vertices[k], bb = m.face_vertices[k + 1 < e ? k + 1 : b];
      w.edges.emplace_back(std::min(a, bb), std::max(a, bb), uint32_t(f - f0), a < bb);
    }
    // The best-fit plane of a (possibly welded) face, relative to the seed.
    const FacePlane plane =
        best_fit_plane(size_t(e - b), [&](size_t k) { return m.points[m.face_vertices[b + int64_t(k)]] - o; });
    w.normals.push_back(plane.normal);
    w.offsets.push_back(dot(plane.normal, plane.centroid));
    w.border.push_back(is_border_generator(m.face_generator[f]));
  }
  cell_points(m, c, w.ids);
  q.faces = uint32_t(f1 - f0);
  q.vertices = uint32_t(w.ids.size());

  w.points.clear();
  for (int32_t v : w.ids) {
    const Vec3 p = m.points[v] - o;
    w.points.emplace_back(p.x, p.y, p.z);
  }
  MinSphere sphere(w.points.begin(), w.points.end());
  q.outradius = sphere.radius();
  const InscribedBall ball = largest_inscribed_ball(w.normals, w.offsets);
  // No ball (an empty kernel: the program's optimum is negative) is an inradius of 0, and a ball
  // far below the cell's size (a kernel of one point, 1e-19 where the cell is 1) no ball either:
  // its aspect ratio, 1e18, would otherwise enter the spread's mean as a finite figure.
  q.inradius = ball.ok && ball.radius > 1e-12 * q.outradius ? ball.radius : 0;
  q.aspect = q.inradius > 0 ? q.outradius / q.inradius : INFINITY;

  // Each edge is used by two faces of a closed cell: pair them up.
  w.pair_uses();
  q.min_dihedral = INFINITY, q.max_dihedral = -INFINITY, q.min_edge = INFINITY;
  for (const auto& [first, second] : w.pairs) {
    const auto& x = w.edges[first];
    const auto& y = w.edges[second];
    q.min_edge = std::min(q.min_edge, norm(m.points[x.a()] - m.points[x.b()]));
    // Two coplanar faces meet along a line in a plane, not an edge of the cell's shape: where a
    // face with holes was cut into triangles (assembly/holed_faces), or a face split where a
    // neighbour was cut in convex pieces (--convex).
    const int32_t gx = m.face_generator[f0 + x.face()], gy = m.face_generator[f0 + y.face()];
    if (dot(w.normals[x.face()], w.normals[y.face()]) > 1 - 1e-9) continue;
    // The angle inside the cell between two faces is pi minus the angle of their outward normals
    // at a convex edge, pi plus it at a reflex one (star-shaped cells of non-convex domains):
    // convex when the normals turn along the edge as the first face runs it.
    const double cosine = std::clamp(dot(w.normals[x.face()], w.normals[y.face()]), -1.0, 1.0);
    const Vec3 run = x.forward() ? m.points[x.b()] - m.points[x.a()] : m.points[x.a()] - m.points[x.b()];
    const bool reflex = dot(cross(w.normals[x.face()], w.normals[y.face()]), run) < 0;
    const double angle = reflex ? 180 + std::acos(cosine) * kDegree : 180 - std::acos(cosine) * kDegree;
    q.min_dihedral = std::min(q.min_dihedral, angle);
    q.max_dihedral = std::max(q.max_dihedral, angle);
    if (angles) {
      const int borders = int(w.border[x.face()]) + int(w.border[y.face()]);
      const bool relaxed = borders == 0 ? is_protection_seed(m, gx) && is_protection_seed(m, gy)
                                        : m.kinds[c] >= CellKind::Edge &&
                                              (is_protection_seed(m, gx) || is_protection_seed(m, gy));
      angles->push_back({angle, DihedralClass(borders), relaxed});
    }
  }
  return q;
}

// The paper's bounds for one cell: Theorem 1 and Lemma 6 speak of interior cells, Lemma 6's
// border-interior bound of every cell. Lemma 6 takes sin(theta) >= 1/2 from seeds r apart; where
// the seeds that make the angle are protection seeds r_e = r/sqrt(2) apart it has
// sin(theta) >= sqrt(2)/4 instead (paper §3.2), so theta >= 20.7 degrees.
CellVerdict judge(CellKind kind, const CellQuality& q, const std::vector<Dihedral>& angles, bool graded) {
  CellVerdict v;
  v.q = q;
  v.graded = graded;
  const bool interior = kind == CellKind::Interior;
  v.theorem1 = interior && !(q.aspect <= kTheorem1Aspect);
  for (const Dihedral& d : angles) {
    const double theta = d.relaxed ? kProtectedTheta : 30;
    if (d.cls == DihedralClass::InteriorInterior && interior)
      v.lemma6_interior |= d.degrees < 60 - kAngleSlack || d.degrees > 180 - theta + kAngleSlack;
    if (d.cls == DihedralClass::BorderInterior)
      v.lemma6_border |= d.degrees < theta - kAngleSlack || d.degrees > 180 - theta + kAngleSlack;
  }
  return v;
}

constexpr int kAspectBins = 60;
constexpr double kAspectLo = 1, kAspectHi = 4;
constexpr int kDihedralBins = 180;

}  // namespace

bool graded_near(const PolyMesh& m, size_t c) {
  if (!m.near_graded.empty()) return m.near_graded[c] != 0;
  if (m.radii.empty() || !(m.r > 0)) return false;
  const double below = m.r * (1 - 1e-9);
  if (m.radii[c] < below) return true;
  for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) {
    const int32_t g = m.face_generator[f];
    if (g >= 0 && size_t(g) < m.radii.size() && m.radii[size_t(g)] < below) return true;
  }
  return false;
}

namespace {

// Adds a cell's verdict to the bound counts, or to the graded cells' apart.
void count_verdict(QualityReport& r, const CellVerdict& v) {
  if (v.graded) {
    ++r.graded_cells;
    r.graded_outside.theorem1 += v.theorem1;
    r.graded_outside.lemma6_interior += v.lemma6_interior;
    r.graded_outside.lemma6_border += v.lemma6_border;
    return;
  }
  r.theorem1_violations += v.theorem1;
  r.lemma6_interior_violations += v.lemma6_interior;
  r.lemma6_border_violations += v.lemma6_border;
}

QualityReport empty_report() {
  QualityReport r;
  for (auto& h : r.aspect_histogram) h = {kAspectLo, kAspectHi, std::vector<uint64_t>(kAspectBins, 0)};
  // Dihedrals of non-convex cells (along reflex edges) go up to 360 degrees.
  for (auto& h : r.dihedral_histogram) h = {0, 360, std::vector<uint64_t>(kDihedralBins, 0)};
  return r;
}

}  // namespace

void merge_quality(QualityReport& into, const QualityReport& from) {
  for (int k = 0; k < QualityReport::kKinds; ++k) {
    into.cells[k] += from.cells[k];
    into.aspect[k].merge(from.aspect[k]);
    into.outradius[k].merge(from.outradius[k]);
    into.inradius[k].merge(from.inradius[k]);
    into.min_edge[k].merge(from.min_edge[k]);
    into.faces[k].merge(from.faces[k]);
    into.aspect_histogram[k].merge(from.aspect_histogram[k]);
  }
  for (int k = 0; k < QualityReport::kClasses; ++k) {
    into.dihedral[k].merge(from.dihedral[k]);
    into.dihedral_histogram[k].merge(from.dihedral_histogram[k]);
  }
  into.theorem1_violations += from.theorem1_violations;
  into.lemma6_interior_violations += from.lemma6_interior_violations;
  into.lemma6_border_violations += from.lemma6_border_violations;
  into.graded_cells += from.graded_cells;
  into.graded_outside.theorem1 += from.graded_outside.theorem1;
  into.graded_outside.lemma6_interior += from.graded_outside.lemma6_interior;
  into.graded_outside.lemma6_border += from.graded_outside.lemma6_border;
  if (from.shortest_edge > 0 && (into.shortest_edge == 0 || from.shortest_edge < into.shortest_edge))
    into.shortest_edge = from.shortest_edge;
}

void Histogram::add(double v) {
  if (counts.empty()) return;
  if (v < lo) {
    ++below;
    return;
  }
  const double x = (v - lo) / (hi - lo) * double(counts.size());
  if (!(x < double(counts.size()))) {  // at or beyond hi, or NaN
    ++above;
    return;
  }
  ++counts[size_t(x)];
}

void Histogram::merge(const Histogram& o) {
  for (size_t b = 0; b < counts.size(); ++b) counts[b] += o.counts[b];
  below += o.below, above += o.above;
}

void Summary::add(double v) {
  if (!std::isfinite(v)) {
    ++not_finite;
    return;
  }
  if (count == 0) min = max = v;
  min = std::min(min, v), max = std::max(max, v);
  sum += v;
  ++count;
}

void Summary::merge(const Summary& o) {
  not_finite += o.not_finite;
  if (o.count == 0) return;
  if (count == 0) {
    const uint64_t keep = not_finite;
    *this = o;
    not_finite = keep;
    return;
  }
  min = std::min(min, o.min), max = std::max(max, o.max);
  sum += o.sum;
  count += o.count;
}

CellQuality cell_quality(const PolyMesh& mesh, size_t c) {
  CellScratch w;
  return measure(mesh, c, w, nullptr);
}

CellVerdict cell_verdict(const PolyMesh& mesh, size_t c) {
  CellScratch w;
  std::vector<Dihedral> angles;
  const CellQuality q = measure(mesh, c, w, &angles);
  return judge(mesh.kinds[c], q, angles, graded_near(mesh, c));
}

QualityReport assess_quality(const PolyMesh& m, std::vector<CellQuality>* per_cell) {
  constexpr size_t kChunk = 4096;  // fixed, so sums add up in one order for any thread count
  const size_t n = m.cell_count(), chunks = (n + kChunk - 1) / kChunk;
  std::vector<QualityReport> parts(chunks, empty_report());
  if (per_cell) per_cell->resize(n);
#pragma omp parallel
  {
    CellScratch w;
    std::vector<Dihedral> angles;
#pragma omp for schedule(dynamic, 1)
    for (size_t ch = 0; ch < chunks; ++ch) {
      QualityReport& r = parts[ch];
      for (size_t c = ch * kChunk; c < std::min(n, (ch + 1) * kChunk); ++c) {
        angles.clear();
        const CellQuality q = measure(m, c, w, &angles);
        if (per_cell) (*per_cell)[c] = q;
        const int kind = int(m.kinds[c]);
        ++r.cells[kind];
        r.aspect[kind].add(q.aspect);
        r.aspect_histogram[kind].add(q.aspect);
        r.outradius[kind].add(q.outradius);
        r.inradius[kind].add(q.inradius);
        r.min_edge[kind].add(q.min_edge);
        r.faces[kind].add(q.faces);
        for (const Dihedral& d : angles) {
          r.dihedral[int(d.cls)].add(d.degrees);
          r.dihedral_histogram[int(d.cls)].add(d.degrees);
        }
        count_verdict(r, judge(m.kinds[c], q, angles, graded_near(m, c)));
      }
    }
  }
  QualityReport all = empty_report();
  for (const auto& p : parts) merge_quality(all, p);
  double shortest = INFINITY;
  for (const auto& s : all.min_edge)
    if (s.count) shortest = std::min(shortest, s.min);
  all.shortest_edge = std::isfinite(shortest) ? shortest : 0;
  return all;
}

std::string quality_json_text(const QualityReport& q) {
  static const char* kinds[] = {"interior", "fringe", "edge", "vertex", "interface_face", "interface_edge"};
  static const char* classes[] = {"interior_interior", "border_interior", "border_border"};
  // Over the finite values (null if there are none); "not_finite" counts the others.
  auto summary = [](const Summary& s) {
    nlohmann::ordered_json j;
    if (s.count) j = {{"min", s.min}, {"mean", s.mean()}, {"max", s.max}};
    else j = {{"min", nullptr}, {"mean", nullptr}, {"max", nullptr}};
    if (s.not_finite) j["not_finite"] = s.not_finite;
    return j;
  };
  auto histogram = [](const Histogram& h) {
    return nlohmann::ordered_json{{"lo", h.lo}, {"hi", h.hi}, {"counts", h.counts}, {"below", h.below}, {"above", h.above}};
  };
  nlohmann::ordered_json j;
  for (int k = 0; k < QualityReport::kKinds; ++k) {
    if (q.cells[k] == 0) continue;
    j["cells"][kinds[k]] = {{"count", q.cells[k]},
                            {"aspect", summary(q.aspect[k])},
                            {"outradius", summary(q.outradius[k])},
                            {"inradius", summary(q.inradius[k])},
                            {"min_edge", summary(q.min_edge[k])},
                            {"faces", summary(q.faces[k])},
                            {"aspect_histogram", histogram(q.aspect_histogram[k])}};
  }
  for (int k = 0; k < QualityReport::kClasses; ++k) {
    if (q.dihedral[k].count == 0) continue;
    j["dihedral_degrees"][classes[k]] = {{"edges", q.dihedral[k].count},
                                         {"summary", summary(q.dihedral[k])},
                                         {"histogram", histogram(q.dihedral_histogram[k])}};
  }
  j["shortest_edge"] = q.shortest_edge;
  j["bounds"] = {{"theorem1_interior_aspect_max", 2.0},
                 {"lemma6_interior_dihedral_degrees", {60.0, 150.0}},
                 {"lemma6_border_interior_dihedral_degrees", {30.0, 150.0}},
                 {"lemma6_protected_theta_degrees", kProtectedTheta},
                 {"theorem1_violations", q.theorem1_violations},
                 {"lemma6_interior_violations", q.lemma6_interior_violations},
                 {"lemma6_border_violations", q.lemma6_border_violations}};
  if (q.graded_cells > 0)
    j["bounds"]["graded_cells"] = {{"cells", q.graded_cells},
                                   {"beyond_theorem1", q.graded_outside.theorem1},
                                   {"beyond_lemma6_interior", q.graded_outside.lemma6_interior},
                                   {"beyond_lemma6_border", q.graded_outside.lemma6_border}};
  return j.dump(2) + "\n";
}

}  // namespace froth
