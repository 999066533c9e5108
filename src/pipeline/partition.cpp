// Slabs, the cells' seed halo and the extraction of a rank's cells (froth/partition.hpp).
#include "pipeline/partition.hpp"

#include <algorithm>
#include <cstring>
#include <functional>

#include <fmt/format.h>

#include "froth/error.hpp"

namespace froth {

Slab slab_of(int rank, int ranks, int nz) {
  if (ranks < 1 || rank < 0 || rank >= ranks) fail(ErrorKind::Internal, fmt::format("rank {} of {}", rank, ranks));
  if (ranks > 1 && nz / ranks < kCellHaloLayers)
    fail(ErrorKind::Usage,
         fmt::format("--partition over {} ranks needs at least {} layers of sampling cubes (side r/sqrt(3)) per rank "
                     "along z, and the grid has {} layers: use fewer ranks or a smaller r",
                     ranks, kCellHaloLayers, nz));
  Slab s;
  s.owned_begin = int(int64_t(nz) * rank / ranks);
  s.owned_end = int(int64_t(nz) * (rank + 1) / ranks);
  s.window_begin = std::max(0, s.owned_begin - kSamplingHaloLayers);
  s.window_end = std::min(nz, s.owned_end + kSamplingHaloLayers);
  return s;
}

uint64_t sum_over_ranks(Communicator& comm, uint64_t value) {
  Communicator::Bytes mine(sizeof value);
  std::memcpy(mine.data(), &value, sizeof value);
  uint64_t sum = 0;
  for (const auto& b : comm.all_gather(mine)) {
    uint64_t v;
    std::memcpy(&v, b.data(), sizeof v);
    sum += v;
  }
  return sum;
}

namespace {

// A seed on the wire: its base cube, position, and protection (kind < 0: a free seed).
struct WireSeed {
  uint32_t base;
  int32_t kind;
  Vec3 p, inward;
};

template <class T>
Communicator::Bytes to_bytes(const T* data, size_t n) {
  Communicator::Bytes out(n * sizeof(T));
  if (n) std::memcpy(out.data(), data, out.size());
  return out;
}

std::vector<WireSeed> from_bytes(const Communicator::Bytes& b) {
  std::vector<WireSeed> out(b.size() / sizeof(WireSeed));
  if (!out.empty()) std::memcpy(static_cast<void*>(out.data()), b.data(), out.size() * sizeof(WireSeed));
  return out;
}

}  // namespace

CellWindow exchange_cell_halo(const Sample& sampled, const Slab& slab, Communicator& comm) {
  const BackgroundGrid& g = sampled.grid;
  const int64_t layer = int64_t(g.nx) * g.ny;
  auto layer_of = [layer](uint32_t base) { return int(base / layer); };

  // This rank's seeds, in global order.
  std::vector<WireSeed> own;
  for (int64_t c = layer * slab.owned_begin; c < layer * slab.owned_end; ++c)
    sampled.for_seeds_in_cube(c, [&](int32_t q) {
      const Sample::Protected* p = sampled.protection_of(q);
      own.push_back({uint32_t(c), p ? int32_t(p->kind) : -1, sampled.seeds[q], p ? p->inward : Vec3{}});
    });
  CellWindow w;
  int64_t first_own = 0;
  {
    const uint64_t n = own.size();
    const auto counts = comm.all_gather(to_bytes(&n, 1));
    for (int k = 0; k < comm.size(); ++k) {
      uint64_t v;
      std::memcpy(&v, counts[k].data(), sizeof v);
      if (k < comm.rank()) first_own += int64_t(v);
      w.total_seeds += v;
    }
  }
  // Slabs are at least kCellHaloLayers thick (slab_of), so the halo comes from the neighbours.
  const auto lower_end = std::find_if(own.begin(), own.end(), [&](const WireSeed& s) {
    return layer_of(s.base) >= slab.owned_begin + kCellHaloLayers;
  });
  const auto upper_begin = std::find_if(own.begin(), own.end(), [&](const WireSeed& s) {
    return layer_of(s.base) >= slab.owned_end - kCellHaloLayers;
  });
  Communicator::Bytes below_bytes, above_bytes;
  comm.exchange_with_neighbours(to_bytes(own.data(), size_t(lower_end - own.begin())),
                                to_bytes(own.data() + (upper_begin - own.begin()), size_t(own.end() - upper_begin)), below_bytes, above_bytes);
  const std::vector<WireSeed> below = from_bytes(below_bytes), above = from_bytes(above_bytes);

  std::vector<WireSeed> all;
  all.reserve(below.size() + own.size() + above.size());
  for (const auto& part : {std::cref(below), std::cref(own), std::cref(above)}) all.insert(all.end(), part.get().begin(), part.get().end());
  w.first_global = first_own - int64_t(below.size());
  w.owned = {int32_t(below.size()), int32_t(below.size() + own.size())};
  const int built_begin = slab.owned_begin - kGhostCellLayers, built_end = slab.owned_end + kGhostCellLayers;
  w.built.begin = int32_t(std::find_if(all.begin(), all.end(), [&](const WireSeed& s) { return layer_of(s.base) >= built_begin; }) - all.begin());
  w.built.end = int32_t(std::find_if(all.begin(), all.end(), [&](const WireSeed& s) { return layer_of(s.base) >= built_end; }) - all.begin());

  Sample& s = w.sample;
  s.grid = g;
  s.stats = sampled.stats;
  const int window_begin = std::max(0, slab.owned_begin - kCellHaloLayers);
  const int window_end = std::min(g.nz, slab.owned_end + kCellHaloLayers);
  s.cube_offset = layer * window_begin;
  s.cube_seed.assign(size_t(layer * (window_end - window_begin)), -1);
  s.cube_extra_begin.assign(1, 0);
  s.seeds.reserve(all.size());
  for (size_t k = 0; k < all.size();) {
    // The seeds of one cube are consecutive; protection seeds can share a cube.
    size_t e = k + 1;
    while (e < all.size() && all[e].base == all[k].base) ++e;
    int32_t& entry = s.cube_seed[all[k].base - s.cube_offset];
    if (e - k == 1) {
      entry = int32_t(k);
    } else {
      entry = -2 - int32_t(s.cube_extra_begin.size() - 1);
      for (size_t q = k; q < e; ++q) s.cube_extra.push_back(int32_t(q));
      s.cube_extra_begin.push_back(int32_t(s.cube_extra.size()));
    }
    for (size_t q = k; q < e; ++q) {
      s.seeds.push_back(all[q].p);
      if (all[q].kind >= 0) s.protected_seeds.push_back({int32_t(q), CellKind(all[q].kind), all[q].inward});
    }
    k = e;
  }
  return w;
}

PolyMesh extract_cells(const PolyMesh& m, size_t begin, size_t end, size_t& other_piece_faces) {
  PolyMesh out;
  const int64_t f0 = m.cell_face_begin[begin], f1 = m.cell_face_begin[end];
  const int64_t v0 = m.face_vertex_begin[f0], v1 = m.face_vertex_begin[f1];
  // Points keep their relative order.
  std::vector<int32_t> id(m.points.size(), -1);
  for (int64_t k = v0; k < v1; ++k) id[m.face_vertices[k]] = 0;
  int32_t next = 0;
  for (size_t p = 0; p < id.size(); ++p)
    if (id[p] == 0) id[p] = next++;
  out.points.resize(size_t(next));
  for (size_t p = 0; p < id.size(); ++p)
    if (id[p] >= 0) out.points[id[p]] = m.points[p];
  out.seeds.assign(m.seeds.begin() + begin, m.seeds.begin() + end);
  out.kinds.assign(m.kinds.begin() + begin, m.kinds.begin() + end);
  out.cell_face_begin.resize(end - begin + 1);
  for (size_t c = begin; c <= end; ++c) out.cell_face_begin[c - begin] = m.cell_face_begin[c] - f0;
  out.face_generator.resize(size_t(f1 - f0));
  out.face_vertex_begin.resize(size_t(f1 - f0 + 1));
  other_piece_faces = 0;
  for (int64_t f = f0; f < f1; ++f) {
    int32_t g = m.face_generator[f];
    if (g >= 0) {
      if (size_t(g) >= begin && size_t(g) < end) {
        g -= int32_t(begin);
      } else {
        // A cell outside the range: built (its kind is known), or not.
        if (!is_other_piece_generator(g)) g = m.kinds[size_t(g)] >= CellKind::Edge ? kOtherPieceProtected : kOtherPiece;
        ++other_piece_faces;
      }
    }
    out.face_generator[f - f0] = g;
    out.face_vertex_begin[f - f0] = m.face_vertex_begin[f] - v0;
  }
  out.face_vertex_begin[f1 - f0] = v1 - v0;
  out.face_vertices.resize(size_t(v1 - v0));
  for (int64_t k = v0; k < v1; ++k) out.face_vertices[k - v0] = id[m.face_vertices[k]];
  return out;
}

}  // namespace froth
