// froth: uniform random Voronoi meshes by maximal Poisson-disk sampling.
#pragma once
#include "froth/communicator.hpp"
#include "froth/domain.hpp"
#include "froth/ensemble.hpp"
#include "froth/error.hpp"
#include "froth/geometry.hpp"
#include "froth/io.hpp"
#include "froth/mesh.hpp"
#include "froth/partition.hpp"
#include "froth/quality.hpp"
#include "froth/validate.hpp"
#include "froth/weld.hpp"
