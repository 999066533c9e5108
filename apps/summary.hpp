// What the command line prints when a run succeeds: a short block of labelled lines (cells,
// volume, quality, time, what was written), notes where the user should know something (walls
// thinner than r, cells that are not star-shaped, a chosen r), and with --verbose the details of
// every stage.
#pragma once
#include <string>
#include <vector>

#include "froth/froth.hpp"

namespace froth_cli {

enum class Verbosity { Quiet, Normal, Verbose };

// `written`: the files the run wrote, in order.
std::string mesh_summary(const froth::RunReport& run, const std::vector<std::string>& written, Verbosity v);

// `froth quality MESH`: the check and the quality line.
std::string quality_summary(const std::string& mesh, const froth::MeshCheck& check, const froth::QualityReport& q,
                            const std::vector<std::string>& written);

// "interior aspect ratio A to B (mean M)", or "no interior cells".
std::string interior_aspect_text(const froth::QualityReport& q);

}  // namespace froth_cli
