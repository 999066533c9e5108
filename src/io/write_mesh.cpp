// The mesh writers chosen by the output's name.
#include <algorithm>
#include <cctype>

#include <fmt/format.h>

#include "froth/error.hpp"
#include "froth/io.hpp"

namespace froth {

MeshFormat mesh_format_of(const std::filesystem::path& path) {
  std::filesystem::path p = path;
  if (!p.has_filename()) p = p.parent_path();  // "case/constant/polyMesh/"
  if (p.filename() == "polyMesh") return MeshFormat::OpenFoam;
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".vtu") return MeshFormat::Vtu;
  if (ext == ".npz") return MeshFormat::FacetGraph;
  if (ext == ".nodes") return MeshFormat::PeridynamicNodes;
  if (ext == ".exo" || ext == ".e") return MeshFormat::Exodus;
  return MeshFormat::Unknown;
}

void write_mesh(const PolyMesh& mesh, const RunReport& run, const std::filesystem::path& path,
                const std::function<void(double)>& progress, bool compress) {
  switch (mesh_format_of(path)) {
    case MeshFormat::Vtu: return write_vtu(mesh, run, path, progress, compress);
    case MeshFormat::OpenFoam: return write_openfoam(mesh, path);
    case MeshFormat::FacetGraph: return write_facet_graph(mesh, path);
    case MeshFormat::PeridynamicNodes: return write_peridynamic_nodes(mesh, path);
    case MeshFormat::Exodus: return write_exodus(mesh, run, path);
    case MeshFormat::Unknown: break;
  }
  fail(ErrorKind::Usage, fmt::format("{}: froth cannot write this format; it writes NAME.vtu (VTK), NAME.exo or "
                                     "NAME.e (Exodus II), a folder named polyMesh (OpenFOAM), NAME.npz (facet graph) "
                                     "and NAME.nodes (peridynamic nodes)",
                                     path.string()));
}

}  // namespace froth
