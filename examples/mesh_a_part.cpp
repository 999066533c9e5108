// froth as a library: load a surface, mesh it, read the cells, write a VTU.
//   mesh_a_part SURFACE [SURFACE ...] R OUT.vtu    (several surfaces: one region each)
// Built against an installed froth: find_package(froth) and froth::froth (examples/CMakeLists.txt).
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <froth/froth.hpp>

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s SURFACE [SURFACE ...] R OUT.vtu\n", argv[0]);
    return 2;
  }
  const std::vector<std::string> surfaces(argv + 1, argv + argc - 2);
  try {
    // load_domain validates the surface and finds its reflex edges, as the froth program does;
    // load_regions makes one region per surface, sharing their interfaces.
    const froth::Domain domain = surfaces.size() == 1 ? froth::load_domain(surfaces[0]) : froth::load_regions(surfaces);
    froth::MeshOptions options;  // every other option at froth mesh's default (welded, quality measured)
    options.r = std::strtod(argv[argc - 2], nullptr);
    options.seed = 1;
    froth::RunReport report;
    const froth::PolyMesh mesh = froth::generate_mesh(domain, options, &report);

    // The cells: cell c has faces [cell_face_begin[c], cell_face_begin[c + 1]), face f has the
    // point ids face_vertices[face_vertex_begin[f] ...]; its kind, volume and seed.
    size_t kinds[froth::kCellKinds] = {};
    double volume = 0, largest_aspect = 0;
    for (size_t c = 0; c < mesh.cell_count(); ++c) {
      ++kinds[static_cast<int>(mesh.kinds[c])];
      volume += mesh.volumes[c];
      if (mesh.kinds[c] == froth::CellKind::Interior && mesh.quality[c].aspect > largest_aspect)
        largest_aspect = mesh.quality[c].aspect;
    }
    std::printf("%zu cells (%zu interior, %zu fringe, %zu edge, %zu vertex, %zu interface face, %zu interface edge), "
                "%zu faces, %zu points\n",
                mesh.cell_count(), kinds[0], kinds[1], kinds[2], kinds[3], kinds[4], kinds[5], mesh.face_count(),
                mesh.points.size());
    std::printf("volume %.12g of %.12g; largest interior aspect ratio %.3f (Theorem 1: at most 2)\n", volume,
                domain.volume, largest_aspect);
    froth::write_vtu(mesh, report, argv[argc - 1]);
    std::printf("wrote %s\n", argv[argc - 1]);
    return 0;
  } catch (const froth::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return e.exit_code();
  }
}
