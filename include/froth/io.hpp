// Writers. Every output is written to a temporary name and renamed on success.
#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "froth/mesh.hpp"

namespace froth {

// VTK XML UnstructuredGrid of VTK_POLYHEDRON cells, appended raw binary (zlib-compressed in
// VTK's own layout when `compress`). Cell data: seed, kind, volume; field data: r, random_seed,
// weld, version.
void write_vtu(const PolyMesh& mesh, const RunReport& run, const std::filesystem::path& path,
               const std::function<void(double)>& progress = {}, bool compress = false);

// OpenFOAM polyMesh in the folder `dir` (points, faces, owner, neighbour, boundary, cellZones by
// cell kind; ASCII): interior faces once, owner < neighbour, normals out of the owner, in
// upper-triangular order; the border faces in one wall patch per input patch (mesh.patch_names,
// made OpenFOAM words).
void write_openfoam(const PolyMesh& mesh, const std::filesystem::path& dir);

// The facet graph, a NumPy .npz archive (numpy.load reads it): per cell its seed, centroid,
// volume, kind, region and piece; per interior face (once) its two cells, area, centroid, unit
// normal from the first cell to the second and the point where the segment between the two
// seeds meets the face's plane; per border face its cell, area, centroid, outward normal, patch
// and domain facet plane. docs/design.md lists the arrays; format_version is 1.
void write_facet_graph(const PolyMesh& mesh, const std::filesystem::path& path);

// Peridynamic nodes, Peridigm's text discretization ("x y z block_id volume" per cell, at the
// cell's centroid, block 1), which PeriLab reads too.
void write_peridynamic_nodes(const PolyMesh& mesh, const std::filesystem::path& path);

// Exodus II (.exo, .e): an NSIDED face block with every face once, NFACED element blocks by
// cell kind (ids 1-4: interior, fringe, edge, vertex), the cell data as element variables at
// t = 0, side set 1 "walls" of the border faces, double-precision coordinates (see
// docs/design.md). Usage error if froth was built without libexodusii.
void write_exodus(const PolyMesh& mesh, const RunReport& run, const std::filesystem::path& path);

// What write_mesh writes for an output path: NAME.vtu, NAME.exo or NAME.e (Exodus II), a folder
// named polyMesh (OpenFOAM), NAME.npz (facet graph) or NAME.nodes (peridynamic nodes).
enum class MeshFormat { Vtu, OpenFoam, FacetGraph, PeridynamicNodes, Exodus, Unknown };
MeshFormat mesh_format_of(const std::filesystem::path& path);

// The mesh in the format its path names (mesh_format_of); Usage error for an unknown one.
// `compress`: a zlib-compressed VTU (the other formats ignore it).
void write_mesh(const PolyMesh& mesh, const RunReport& run, const std::filesystem::path& path,
                const std::function<void(double)>& progress = {}, bool compress = false);

// The border faces as a surface VTU (VTK_POLYGON cells) with cell data `patch` (into the field
// data `patch_names`) and `cell` (the mesh cell each belongs to): a VTU holds no face data.
void write_boundary_vtu(const PolyMesh& mesh, const std::filesystem::path& path);

// The parallel VTU (.pvtu) that gathers the pieces of a partitioned run (froth/partition.hpp),
// each written by write_vtu; `pieces` are their paths relative to the .pvtu's folder. The pieces
// must all have the per-cell quality arrays or none, and the `region` array (a multi-region
// solid's) or none.
void write_pvtu(const std::vector<std::string>& pieces, bool with_quality, bool with_regions,
                const std::filesystem::path& path);

// A polyhedral VTU (any VTK writer: ascii, base64 or appended raw data, zlib-compressed or not)
// as a mesh: cells must be VTK_POLYHEDRON. Faces shared by two cells become interior faces;
// seeds come from the "seed" cell data, else each cell's vertex mean; kinds from "kind", else
// fringe where a cell has a border face; froth's other cell arrays (quality measures, parents,
// regions, centres, radii) where present. `recorded`, if given, gets the run's figures the field
// data keep (r, seed, weld, the grading options). Throws Error (Io, InvalidInput).
PolyMesh read_vtu(const std::filesystem::path& path, RunReport* recorded = nullptr);

// Writes `path` through a temporary name beside it (PATH.tmpPID, with `extension` appended if
// given), for a writer that opens files by name (Exodus II, a script): `write` is given the
// temporary path to create; it is renamed into place (or deferred, in an OutputGroup) when
// `write` returns, and removed when it throws. A symbolic link keeps pointing at its (replaced)
// target; temporaries of PATH left by processes that no longer run are removed first.
void write_atomically_by_name(const std::filesystem::path& path,
                              const std::function<void(const std::filesystem::path& tmp)>& write,
                              const std::string& extension = "");

// While one is alive (on this thread), the writers leave each finished file under its temporary
// name; commit() renames them all into place, and a group destroyed before then removes them and
// the folders made for them: outputs that belong together (a mesh and its report, an OpenFOAM
// case's files) appear together or not at all. A group within a group commits into the outer.
class OutputGroup {
 public:
  OutputGroup();
  ~OutputGroup();
  OutputGroup(const OutputGroup&) = delete;
  OutputGroup& operator=(const OutputGroup&) = delete;
  void commit();
  void defer(const std::filesystem::path& tmp, const std::filesystem::path& target);  // (the writers' part)
  void made_folder(const std::filesystem::path& folder);                              // (the writers' part)

 private:
  std::vector<std::pair<std::filesystem::path, std::filesystem::path>> pending_;
  std::vector<std::filesystem::path> folders_;
  OutputGroup* outer_;
};

// SIGINT, SIGTERM and SIGHUP remove the temporary files being written and end the process with
// 128 + the signal's number (the command line installs this; a library user may not want it).
void remove_temporaries_on_signal();

struct QualityReport;
// A quality report on its own (froth quality), for the mesh file named.
void write_quality_json(const QualityReport& q, const std::string& mesh, const std::filesystem::path& path);

// The run report as JSON; a partitioned run's adds a "partition" section (per rank: slab, seeds,
// halo, time, memory).
struct PartitionSummary;  // froth/partition.hpp
void write_report_json(const RunReport& run, const std::filesystem::path& path,
                       const PartitionSummary* partition = nullptr);
std::string report_json_text(const RunReport& run, const PartitionSummary* partition = nullptr);

}  // namespace froth
