// Features of the input surface (paper §2.2): each edge is flat (between facets of a curved
// surface), convex or reflex, by the angle its two triangles turn through; non-flat edges chain
// into feature curves, which end at corners.
#pragma once
#include <cstdint>
#include <vector>

#include "froth/domain.hpp"

namespace froth {

enum class EdgeClass : uint8_t { Flat = 0, Convex = 1, Reflex = 2 };

struct FeatureCurve {
  EdgeClass cls;
  std::vector<int32_t> vertices;  // in order; first == last for a closed loop
  bool closed = false;
};

struct SurfaceFeatures {
  double angle_degrees = 0;
  size_t flat_edges = 0, convex_edges = 0, reflex_edges = 0;
  size_t flat_reflex_edges = 0;  // flat, but turning the reflex way: a concave curved surface
  std::vector<FeatureCurve> curves;
  std::vector<int32_t> corners;  // vertices where feature curves end or change class
  FeatureSummary summary() const;
};

// The surface must be closed, edge-manifold and consistently oriented (outward). An edge is a
// feature if its triangles' normals differ by more than `angle_degrees`; convex or reflex by
// the exact orientation of one triangle's far vertex against the other's plane. A corner is a
// vertex with one or more than two feature edges, or where two meet that differ in class.
SurfaceFeatures classify_features(const TriangleSurface& surface, double angle_degrees);

}  // namespace froth
