// The per-cell quality arrays of froth's VTU (cell data), written when the quality stage ran and
// read back by read_vtu, so that a converted mesh keeps them.
#pragma once
#include <utility>

#include "froth/mesh.hpp"

namespace froth {

constexpr std::pair<const char*, double CellQuality::*> kQualityFields[] = {
    {"aspect", &CellQuality::aspect},           {"outradius", &CellQuality::outradius},
    {"inradius", &CellQuality::inradius},       {"min_dihedral", &CellQuality::min_dihedral},
    {"max_dihedral", &CellQuality::max_dihedral}, {"min_edge", &CellQuality::min_edge}};

}  // namespace froth
