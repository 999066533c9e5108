// Cell quality (paper §3): outradius, inradius, aspect ratio, dihedral angles by class, shortest
// edge; summaries per cell kind with histograms, and the count of cells outside the paper's
// bounds (Theorem 1: interior aspect ratio at most 2; Lemma 6: interior dihedrals in [60°, 150°],
// border-interior dihedrals in [30°, 150°]).
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "froth/mesh.hpp"

namespace froth {

// Per-cell metrics of cell c. The inradius is the largest ball on the inner side of every
// face's plane (a linear program): exact for convex cells, which froth's cells are before
// welding; after welding faces are slightly non-planar and their best-fit planes are used.
CellQuality cell_quality(const PolyMesh& mesh, size_t c);

// A cell's metrics and whether it is beyond the paper's bounds (see QualityReport).
struct CellVerdict {
  CellQuality q;
  bool theorem1 = false, lemma6_interior = false, lemma6_border = false;
  // h < r at the cell's seed or a face neighbour's: the bounds, which are the paper's for a
  // uniform r, are not judged there (the counts go to QualityReport::graded_outside).
  bool graded = false;
};
CellVerdict cell_verdict(const PolyMesh& mesh, size_t c);
// Is h below r at cell c's seed or at a face neighbour's (PolyMesh::near_graded, else radii; r
// unknown: no)?
bool graded_near(const PolyMesh& mesh, size_t c);

// Edges between two faces, by the faces' kinds.
enum class DihedralClass : uint8_t { InteriorInterior = 0, BorderInterior = 1, BorderBorder = 2 };

struct Histogram {
  double lo = 0, hi = 0;         // range
  std::vector<uint64_t> counts;  // equal-width bins over [lo, hi)
  uint64_t below = 0, above = 0;  // values below lo; at or above hi, or not finite
  void add(double v);
  void merge(const Histogram& o);
};

// Min, mean and max of the finite values; values that are not (the infinite aspect ratio of a
// cell with an empty kernel) are counted apart, as JSON has no infinity.
struct Summary {
  uint64_t count = 0;
  uint64_t not_finite = 0;
  double min = 0, max = 0, sum = 0;
  double mean() const { return count ? sum / double(count) : 0; }
  void add(double v);
  void merge(const Summary& o);
};

struct QualityReport {
  static constexpr int kKinds = kCellKinds;  // CellKind
  static constexpr int kClasses = 3;  // DihedralClass
  std::array<uint64_t, kKinds> cells{};
  std::array<Summary, kKinds> aspect, outradius, inradius, min_edge, faces;
  std::array<Histogram, kKinds> aspect_histogram;
  std::array<Summary, kClasses> dihedral;
  std::array<Histogram, kClasses> dihedral_histogram;
  // Bounds from the paper, checked when r > 0 and the mesh is not welded: interior cells with
  // aspect ratio above 2 (Theorem 1), interior cells with an interior-interior dihedral outside
  // [60°, 150°] (Lemma 6), cells with a border-interior dihedral outside [30°, 150°] (Lemma 6).
  uint64_t theorem1_violations = 0, lemma6_interior_violations = 0, lemma6_border_violations = 0;
  // Cells with h < r at their seed or a face neighbour's (--grade): outside the bounds' scope,
  // counted apart, with how many of them lie beyond each bound.
  uint64_t graded_cells = 0;
  struct { uint64_t theorem1 = 0, lemma6_interior = 0, lemma6_border = 0; } graded_outside;
  double shortest_edge = 0;
};

// Metrics of every cell (into per_cell if given) and their summary. Uses all threads; the
// result does not depend on their number.
QualityReport assess_quality(const PolyMesh& mesh, std::vector<CellQuality>* per_cell = nullptr);

// Adds `from` (another set of cells: a chunk, or another rank's piece) to `into`.
void merge_quality(QualityReport& into, const QualityReport& from);

// The report as JSON text (schema: docs/quality-report.schema.json).
std::string quality_json_text(const QualityReport& q);

}  // namespace froth
