// Writers. Every output is written to a temporary name and renamed on success.
#pragma once
#include <filesystem>

#include "froth/mesh.hpp"

namespace froth {

// VTK XML UnstructuredGrid of VTK_POLYHEDRON cells, appended raw binary. Cell data: seed,
// kind, volume; field data: r, random_seed, weld, version.
void write_vtu(const PolyMesh& mesh, const RunReport& run, const std::filesystem::path& path);

// The run report as JSON.
void write_report_json(const RunReport& run, const std::filesystem::path& path);
std::string report_json_text(const RunReport& run);

}  // namespace froth
