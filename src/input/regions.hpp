// A single file whose shells share triangles: a multi-region solid (froth/domain.hpp's
// RegionSet), found as domain_from_regions finds several files' regions.
#pragma once
#include <string>

#include "froth/domain.hpp"

namespace froth {

// Does some triangle appear twice (the same three vertices, either way round)?
bool has_shared_triangles(const TriangleSurface& s);

// The regions of a file whose solids touch along shared triangles, one region per solid, named
// by the file's patch (`solid` block, OBJ group) most of its triangles are on.
Domain regions_from_shared_triangles(const TriangleSurface& s, const std::string& name, const DomainOptions& options);

}  // namespace froth
