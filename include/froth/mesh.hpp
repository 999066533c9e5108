// The conforming polyhedral mesh froth produces, the options that make it and the run report.
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <utility>
#include <string>
#include <vector>

#include "froth/buffer.hpp"
#include "froth/communicator.hpp"
#include "froth/domain.hpp"
#include "froth/geometry.hpp"

namespace froth {

// InterfaceFace and InterfaceEdge: a multi-region solid's cells of seeds on an interface facet, or on
// an interface curve or corner (src/sampling/protect_interfaces.hpp).
enum class CellKind : uint8_t { Interior = 0, Fringe = 1, Edge = 2, Vertex = 3, InterfaceFace = 4, InterfaceEdge = 5 };
inline constexpr int kCellKinds = 6;

// A face's generator: >= 0 is the seed on the other side (an interior face);
// < 0 encodes domain plane p as -(p + 1) (a border face).
inline bool is_border_generator(int32_t g) { return g < 0; }
inline int32_t plane_generator(int32_t plane) { return -(plane + 1); }
inline int32_t generator_plane(int32_t g) { return -g - 1; }
// A piece of a partitioned mesh (froth/partition.hpp): an interior face toward a cell of another
// piece, whose seed is a free one or a protection seed (Lemma 6's relaxation needs to know).
constexpr int32_t kOtherPiece = INT32_MAX;
constexpr int32_t kOtherPieceProtected = INT32_MAX - 1;
inline bool is_other_piece_generator(int32_t g) { return g >= kOtherPieceProtected; }

struct FaceScratch;

// Quality metrics of one cell (see froth/quality.hpp).
struct CellQuality {
  double outradius = 0;     // radius of the smallest sphere enclosing the cell's vertices
  double inradius = 0;      // radius of the largest ball inside the cell (convex cells)
  double aspect = 0;        // outradius / inradius
  double min_dihedral = 0;  // degrees, over the cell's edges
  double max_dihedral = 0;
  double min_edge = 0;
  uint32_t faces = 0, vertices = 0;
};

// Cells, faces and points in compressed-row form. Cell c owns faces
// [cell_face_begin[c], cell_face_begin[c+1]); face f has vertices
// face_vertices[face_vertex_begin[f] .. face_vertex_begin[f+1]), counter-clockwise seen from
// outside the cell. Shared vertices have one id: the mesh is conforming.
struct PolyMesh {
  Buffer<Vec3> points;
  std::vector<Vec3> seeds;            // one per cell, cell c belongs to seeds[c]
  std::vector<CellKind> kinds;
  std::vector<double> volumes;
  std::vector<int64_t> cell_face_begin{0};
  Buffer<int32_t> face_generator;
  Buffer<int64_t> face_vertex_begin{0};
  Buffer<int32_t> face_vertices;
  std::vector<CellQuality> quality;   // per cell when the quality stage ran, else empty
  // Where a seed's part of the domain falls in several pieces (a wall thinner than its cell),
  // each piece is a cell: piece 0 holds the seed, pieces 1, 2, ... follow it with the same seed.
  // Empty when no cell was split.
  std::vector<uint32_t> piece;
  // A point each cell is star-shaped from (validate.hpp's fan_centers), NaN for a cell that has
  // none (an empty kernel); empty: the seeds, as in a convex domain, where every cell holds its
  // seed and is convex.
  std::vector<Vec3> centers;
  // Each cell's exclusion radius, h at its seed; empty: r for every cell.
  std::vector<double> radii;
  double r = 0;  // the sampling radius; 0 if unknown (a VTU without froth's field data)
  std::optional<uint64_t> random_seed;  // the seed it was made with, where known
  bool border_planes_known = true;  // border faces name their domain facet plane (not read from a VTU)
  // The input's surface patches (froth/domain.hpp's TriangleSurface) and each face's patch,
  // -1 for interior faces; empty face_patch: every border face on patch 0.
  std::vector<std::string> patch_names;
  std::vector<int32_t> face_patch;
  int32_t patch_of(size_t f) const { return face_patch.empty() ? 0 : face_patch[f]; }
  // Per cell: h < r at its seed or at a face neighbour's (quality.hpp's graded cells), worked
  // out where every neighbour is known (a partitioned run's cells with their ghost ring);
  // empty: from the radii.
  std::vector<uint8_t> near_graded;
  // --convex: the cell each cell was split from (MeshOptions::convex); empty: none was split.
  std::vector<uint32_t> parent;
  // A multi-region solid's (froth/domain.hpp's RegionSet): each cell's region, an index into
  // region_names. Empty: one region. Faces between cells of two regions are interface faces.
  std::vector<int32_t> region;
  std::vector<std::string> region_names;
  // A solid cut along cracks (froth/domain.hpp's load_cracks): their names, NAME of the patches
  // crack_NAME_a and crack_NAME_b. Empty: no cracks.
  std::vector<std::string> crack_names;
  // The stages' per-face data while the mesh is built (src/common/face_scratch.hpp); null in a
  // finished mesh.
  std::shared_ptr<FaceScratch> scratch;

  size_t cell_count() const { return seeds.size(); }
  uint32_t piece_of(size_t c) const { return piece.empty() ? 0 : piece[c]; }
  uint32_t parent_of(size_t c) const { return parent.empty() ? uint32_t(c) : parent[c]; }
  int32_t region_of(size_t c) const { return region.empty() ? 0 : region[c]; }
  Vec3 center_of(size_t c) const { return centers.empty() ? seeds[c] : centers[c]; }
  // Is cell c star-shaped from center_of(c)? (Not where its kernel is empty.)
  bool has_kernel(size_t c) const { return centers.empty() || !std::isnan(centers[c].x); }
  // A point to sum a cell's signed volumes from: its center, or its seed where it has none.
  Vec3 fan_origin(size_t c) const { return has_kernel(c) ? center_of(c) : seeds[c]; }
  double radius_of(size_t c, double r) const { return radii.empty() ? r : radii[c]; }
  size_t face_count() const { return face_generator.size(); }
};

inline constexpr int kMaxThreads = 4096;  // MeshOptions::threads at most

// What a mesh is made with. The library owns every default: a field left as it is gives the
// mesh `froth mesh` gives without that option (generate_mesh resolves them, resolve_options).
struct MeshOptions {
  double r = 0;      // sampling radius; 0: chosen for `cells`
  double cells = 0;  // with r = 0: about this many cells (radius_for_cells; 1 to 1e10)
  uint64_t seed = 0; // random seed: the mesh is a pure function of (domain, r, seed)
  // Weld tolerance w in [0, r): vertices closer than w merge; 0 = off. Unset: the default,
  // default_weld_tolerance (1e-4 min(r, the domain's diagonal); 0 with `convex`).
  std::optional<double> weld;
  int threads = 0;           // 0 = all cores; never changes the result
  bool quality = true;       // measure every cell (mesh.quality, report.quality)
  // Told when a stage starts (fraction 0) and, for sampling and cells, as it goes (fraction of
  // the domain covered, of the cells built), from one thread.
  std::function<void(const std::string& stage, double fraction)> progress;
  // Asked as each stage starts and as sampling and cells go (from the calling thread); true stops
  // the run with Error(Interrupted). Python asks it whether Ctrl-C was pressed.
  std::function<bool()> interrupted;
  // A radius graded to the input's thin walls and gaps (sampling/sizing.hpp): h(x) <= r, at
  // least min_r (0: the default, r/4 or above: sampling/sizing.hpp), with slope `grading` along
  // the sizing grid. Off: h = r everywhere.
  bool grade = false;
  double min_r = 0, grading = 0.2;
  // A run whose estimated memory is above this is refused before it starts; 0: the machine's
  // available memory.
  double max_memory_bytes = 0;
  // Split every non-convex cell into convex pieces that conform with their neighbours
  // (src/convex). Welding makes faces non-planar, so it cannot be combined with weld > 0.
  bool convex = false;
};

struct StageTiming {
  std::string stage;
  double seconds = 0;
  size_t peak_rss_bytes = 0;  // process peak resident memory when the stage ended
};

// The process's peak resident memory so far (Linux VmHWM), in bytes; 0 where unknown. Each
// stage's StageTiming records it; a program that adds stages of its own (writing) does too.
size_t peak_rss_bytes();

// The memory a run may take where no limit is given: MemAvailable from /proc/meminfo, else the
// physical memory; 0 if neither is known.
double available_memory();

struct SamplingLevel {
  size_t active_cubes = 0;  // at the start of the level
  size_t darts = 0;
  size_t accepted = 0;
};

struct SamplingStats {
  size_t seeds = 0;              // all seeds, protection seeds included
  size_t edge_seeds = 0, vertex_seeds = 0;  // protection of reflex features (paper §2.2)
  // A multi-region solid's interface seeds (sampling/protect_interfaces.hpp); sub-triangles of
  // the interfaces that no disk covers at the finest level (0: maximal on the interfaces).
  size_t interface_edge_seeds = 0, interface_face_seeds = 0, interface_uncovered = 0;
  // Crack sheets' seeds (sampling/protect_cracks.hpp): on their curves and on the sheets.
  size_t crack_edge_seeds = 0, crack_face_seeds = 0;
  // Their disks' radii over h: 1/2 on curves and 1/sqrt(2) on facets, less where h is graded.
  double interface_curve_factor = 0, interface_facet_factor = 0;
  size_t darts = 0;              // darts thrown in all rounds
  // Candidates decided in arrival order (a partitioned run counts the neighbours' it reads), and
  // the decisions looked up doing so: the work of the acceptance, which stays a small multiple
  // of the candidates.
  size_t candidates = 0, decision_lookups = 0;
  size_t levels = 0;             // refinement levels used
  size_t uncovered_cubes = 0;    // active cubes left at the finest level (0 = maximal)
  // Protection seeds closer to another than their spacing h / sqrt(2) allows (reflex corners
  // and short curves' ends that cluster), whose stated radius is reduced to what holds, and the
  // smallest such radius over h (1: none).
  size_t protection_radius_reduced = 0;
  double smallest_protection_radius = 1;
  double base_cube_side = 0;
  // Base grid cubes per axis, the empty margins (BackgroundGrid::kMargin per side) included.
  std::array<size_t, 3> grid{};
  std::vector<SamplingLevel> per_level;
};

// The input's local feature size up to a cap (src/features/feature_size.hpp): how thick the
// solid is and how wide its gaps are, measured at the triangles' centroids, by area.
struct FeatureSizeReport {
  struct Measure {
    double min = INFINITY;       // INFINITY: nothing below the cap
    Vec3 where;                  // the centroid where it is smallest
    double area_below_cap = 0;   // fraction of the surface area measured below the cap
    double quantile_1 = INFINITY, quantile_10 = INFINITY, quantile_50 = INFINITY;  // of the surface area
  };
  bool measured = false;
  double cap = 0;
  Measure thickness, gap;
};

struct QualityReport;  // froth/quality.hpp
struct WeldStats;      // froth/weld.hpp

struct RunReport {
  std::string domain;
  double r = 0;
  double cells_requested = 0;      // --cells: r was chosen for about this many cells (0: r given)
  uint64_t seed = 0;
  double weld = 0;
  int threads = 0;
  bool grade = false;              // the options that shape h (MeshOptions)
  double min_r = 0, grading = 0;
  FeatureSummary features;  // of the input surface
  FeatureSizeReport feature_size;  // thin walls and narrow gaps, up to r (2r when grading)
  struct Sizing {
    bool graded = false;  // h < r somewhere: the graded sampler ran
    double min_r = 0, grading = 0, lipschitz = 0, smallest = 0;
    // Estimated by sizing node: the fraction of the domain's volume where h < r, and the cells
    // over a uniform mesh's; floor_raised: the default floor went above r/4 to keep that ratio
    // within the budget (sampling/sizing.hpp), up to r, where nothing is graded.
    double graded_fraction = 0, cell_ratio = 1;
    bool floor_raised = false;
  } sizing;
  struct Input {
    bool convex = true;
    size_t triangles = 0, shells = 0, cavities = 0;
    size_t reoriented_triangles = 0;  // by --repair
  } input;
  SamplingStats sampling;
  size_t cells = 0, interior_cells = 0, fringe_cells = 0, edge_cells = 0, vertex_cells = 0;
  size_t interface_cells = 0;  // kinds InterfaceFace and InterfaceEdge (a multi-region solid's)
  // A multi-region solid's regions (cells, their volume against the region's enclosed volume)
  // and interfaces (their input area, and the area of the faces between them from each side).
  struct Region {
    std::string name;
    size_t cells = 0;
    double volume = 0, enclosed = 0;
  };
  std::vector<Region> regions;
  struct Interface {
    int32_t a = 0, b = 0;
    double area = 0, from_a = 0, from_b = 0;
  };
  std::vector<Interface> interfaces;
  // A solid cut along cracks (froth/domain.hpp's load_cracks), per sheet: its area as given and
  // inside the solid (clipped: a part lay outside), its front's length inside the solid, the
  // mesh's crack faces on each side (patches crack_NAME_a and _b: each sums to the area inside)
  // and how many.
  struct Crack {
    std::string name;
    double input_area = 0, area = 0, front_length = 0, from_a = 0, from_b = 0;
    size_t faces_a = 0, faces_b = 0;
    bool clipped = false;
    // Side-a faces all of whose points are on the front (shared with side b): a sheet narrower
    // than the cells there. A reader that pairs faces by their points takes such a face and its
    // twin for one shared face.
    size_t faces_on_front = 0;
  };
  std::vector<Crack> cracks;
  double border_area = 0;  // area of the border faces, to compare with the surface's
  // Cells not star-shaped from their seed (a face plane beyond it by over 1e-6 r), before
  // welding, and the worst distance / r; of those, cells not star-shaped from any point (their
  // kernel holds no ball of radius 1e-6 r). Always 0 for convex domains.
  size_t not_star_shaped = 0, without_kernel = 0;
  // Cells given no center (NaN, cell data kernel 0) in the final mesh: no point they fan from.
  size_t without_center = 0;
  double star_violation = 0;
  size_t faces = 0, points = 0;
  // Seeds whose part of the domain fell in several pieces, and the cells those added (mesh.piece).
  size_t split_seeds = 0, extra_pieces = 0;
  // Cells cut again by seeds beyond 2r: their part of the domain came back into their cube
  // beyond r (assembly/cell_builder.cpp).
  size_t recut_cells = 0;
  // --convex: the cells split, the convex cells they became, the most pieces of one cell, the
  // cells left non-convex (every face plane's cut would pinch a face, leave a face with a hole or
  // a sliver piece) and the smallest piece's volume / r^3.
  struct ConvexSplit {
    bool requested = false;
    size_t cells_split = 0, pieces = 0, max_pieces = 0, left_nonconvex = 0;
    double smallest_piece_volume = 0;
    double left_violation = 0;  // the farthest a vertex of those left lies beyond a face plane, / r
    // The pieces' quality (when measured): aspect ratio mean and largest, smallest dihedral,
    // over the pieces with an inscribed ball; those whose linear program found none apart.
    double piece_aspect_mean = 0, piece_aspect_max = 0, piece_min_dihedral = 0;
    size_t pieces_without_ball = 0;
  } convex_split;
  double domain_volume = 0, volume_sum = 0;
  double surface_area = 0;  // of the domain
  std::vector<StageTiming> stages;
  std::shared_ptr<const QualityReport> quality;  // when MeshOptions::quality
  // When also welding: the quality report's bound counts (only those) before welding.
  std::shared_ptr<const QualityReport> bounds_before_weld;
  std::shared_ptr<const WeldStats> welding;      // when MeshOptions::weld > 0
  double weld_aspect_shift = 0, weld_dihedral_shift = 0;  // largest per-cell change by welding
  double total_seconds = 0;
  size_t peak_rss_bytes = 0;

  double volume_relative_error() const {
    return domain_volume > 0 ? std::abs(volume_sum - domain_volume) / domain_volume : 0;
  }
};

// What a run of `options` on `domain` needs, estimated before it starts: the cells of a
// saturated sample (paper §3.3's density, with the surface's fringe) and the bytes they take.
struct RunEstimate {
  double cells = 0, bytes = 0;
};
RunEstimate estimate_run(const Domain& domain, const MeshOptions& options);

// The r whose uniform mesh of the domain has about `cells` cells (issue 22's --cells): from the
// saturated density first, then corrected by the seeds of one sample at that r (a pure function
// of the domain, the count and the seed, so a run can be repeated with -r). With grading the
// count is the uniform mesh's; grading adds cells where walls are thin (sampling/sizing.hpp).
// `sample` false: the density's estimate alone (a dry run). With `comm` (a partitioned run's
// ranks, all calling together) each rank draws its slab of that sample, and the r is the same.
double radius_for_cells(const Domain& domain, double cells, uint64_t seed, bool sample = true,
                        Communicator* comm = nullptr);

// Throws Error(Usage) for options that cannot give a mesh of the domain: r or the weld out of
// range, a domain or r outside the scales froth computes in, a domain thinner than 1e-6 r, a
// grid of more than 2e9 cubes, or more memory than max_memory_bytes (with the estimate and an r
// that fits) for the `share` of the mesh this process holds. generate_mesh calls it; froth
// ensemble before it creates its folder.
void check_mesh_options(const Domain& domain, const MeshOptions& options, double share = 1);

// The options with the library's defaults filled in: r from `cells` where r is 0 (`sample`
// false: the density's estimate alone, as for a dry run) and the weld tolerance where unset.
// Throws Error(Usage) where neither r nor cells is given, or both.
MeshOptions resolve_options(const Domain& domain, const MeshOptions& options, bool sample = true,
                            Communicator* comm = nullptr);

// The whole pipeline: sample, build cells, assemble the conforming mesh. Throws Error.
PolyMesh generate_mesh(const Domain& domain, const MeshOptions& options, RunReport* report);

}  // namespace froth
