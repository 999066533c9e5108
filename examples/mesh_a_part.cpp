// froth as a library: load a surface, mesh it, read the cells, write a VTU.
//   mesh_a_part SURFACE R OUT.vtu
// Built against an installed froth: find_package(froth) and froth::froth (examples/CMakeLists.txt).
#include <cstdio>
#include <cstdlib>
#include <string>

#include <froth/froth.hpp>

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s SURFACE R OUT.vtu\n", argv[0]);
    return 2;
  }
  try {
    // load_domain validates the surface and finds its reflex edges, as the froth program does.
    const froth::Domain domain = froth::load_domain(argv[1]);
    froth::MeshOptions options;
    options.r = std::strtod(argv[2], nullptr);
    options.seed = 1;
    options.weld = froth::default_weld_tolerance(options.r, domain.bounds.diagonal());
    options.quality = true;
    froth::RunReport report;
    const froth::PolyMesh mesh = froth::generate_mesh(domain, options, &report);

    // The cells: cell c has faces [cell_face_begin[c], cell_face_begin[c + 1]), face f has the
    // point ids face_vertices[face_vertex_begin[f] ...]; its kind, volume and seed.
    size_t kinds[4] = {0, 0, 0, 0};
    double volume = 0, largest_aspect = 0;
    for (size_t c = 0; c < mesh.cell_count(); ++c) {
      ++kinds[static_cast<int>(mesh.kinds[c])];
      volume += mesh.volumes[c];
      if (mesh.kinds[c] == froth::CellKind::Interior && mesh.quality[c].aspect > largest_aspect)
        largest_aspect = mesh.quality[c].aspect;
    }
    std::printf("%zu cells (%zu interior, %zu fringe, %zu edge, %zu vertex), %zu faces, %zu points\n",
                mesh.cell_count(), kinds[0], kinds[1], kinds[2], kinds[3], mesh.face_count(), mesh.points.size());
    std::printf("volume %.12g of %.12g; largest interior aspect ratio %.3f (Theorem 1: at most 2)\n", volume,
                domain.volume, largest_aspect);
    froth::write_vtu(mesh, report, argv[3]);
    std::printf("wrote %s\n", argv[3]);
    return 0;
  } catch (const froth::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return e.exit_code();
  }
}
