// Slabs, the cells' seed halo and the extraction of a rank's cells (froth/partition.hpp).
#include "pipeline/partition.hpp"

#include <algorithm>
#include <cstring>
#include <functional>
#include <optional>
#include <type_traits>

#include <fmt/format.h>

#include "froth/error.hpp"
#include "froth/quality.hpp"
#include "froth/weld.hpp"
#include "common/wire_bytes.hpp"

namespace froth {

Slab slab_of(int rank, int ranks, int nz) {
  if (ranks < 1 || rank < 0 || rank >= ranks) fail(ErrorKind::Internal, fmt::format("rank {} of {}", rank, ranks));
  if (ranks > 1 && nz / ranks < kCellHaloLayers)
    fail(ErrorKind::Usage,
         fmt::format("a partition over {} ranks needs at least {} layers of sampling cubes (side r/sqrt(3)) per rank "
                     "along z, and the grid has {} layers ({} of them its empty margins): use fewer ranks or a "
                     "smaller r",
                     ranks, kCellHaloLayers, nz, 2 * BackgroundGrid::kMargin + 1));
  Slab s;
  s.owned_begin = int(int64_t(nz) * rank / ranks);
  s.owned_end = int(int64_t(nz) * (rank + 1) / ranks);
  s.window_begin = std::max(0, s.owned_begin - kSamplingHaloLayers);
  s.window_end = std::min(nz, s.owned_end + kSamplingHaloLayers);
  return s;
}

namespace {

// A seed on the wire: its base cube, position, and protection (kind < 0: a free seed).
struct WireSeed {
  uint32_t base;
  int32_t kind;
  Vec3 p, inward;
};

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
  const std::vector<uint64_t> counts = comm.gather(own.size());
  for (int k = 0; k < comm.size(); ++k) {
    if (k < comm.rank()) first_own += int64_t(counts[k]);
    w.total_seeds += counts[k];
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
  const std::vector<WireSeed> below = from_bytes<WireSeed>(below_bytes), above = from_bytes<WireSeed>(above_bytes);

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
  out.r = m.r;
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
  if (!m.piece.empty()) out.piece.assign(m.piece.begin() + begin, m.piece.begin() + end);
  if (!m.region.empty()) out.region.assign(m.region.begin() + begin, m.region.begin() + end);
  out.region_names = m.region_names;
  out.crack_names = m.crack_names;
  if (!m.radii.empty()) {
    out.radii.assign(m.radii.begin() + begin, m.radii.begin() + end);
    for (size_t c = begin; c < end; ++c) out.near_graded.push_back(graded_near(m, c));  // the ring knows every neighbour
  }
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

namespace froth {
namespace {

// Plain values in and out of bytes, for the reports the ranks trade.
class Packer {
 public:
  template <class T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const uint8_t*>(&v);
    bytes.insert(bytes.end(), p, p + sizeof v);
  }
  void put(const QualityReport& q) {
    put(q.cells), put(q.aspect), put(q.outradius), put(q.inradius), put(q.min_edge), put(q.faces), put(q.dihedral);
    for (const auto& h : q.aspect_histogram) put(h);
    for (const auto& h : q.dihedral_histogram) put(h);
    put(q.theorem1_violations), put(q.lemma6_interior_violations), put(q.lemma6_border_violations);
    put(q.graded_cells), put(q.graded_outside.theorem1), put(q.graded_outside.lemma6_interior),
        put(q.graded_outside.lemma6_border);
    put(q.shortest_edge);
  }
  void put(const Histogram& h) {
    put(h.lo), put(h.hi), put(uint64_t(h.counts.size()));
    for (uint64_t c : h.counts) put(c);
  }
  Communicator::Bytes bytes;
};

class Unpacker {
 public:
  explicit Unpacker(const Communicator::Bytes& b) : b_(b) {}
  template <class T>
  void get(T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (at_ + sizeof v > b_.size()) fail(ErrorKind::Internal, "a rank's report is truncated");
    std::memcpy(static_cast<void*>(&v), b_.data() + at_, sizeof v);
    at_ += sizeof v;
  }
  void get(QualityReport& q) {
    get(q.cells), get(q.aspect), get(q.outradius), get(q.inradius), get(q.min_edge), get(q.faces), get(q.dihedral);
    for (auto& h : q.aspect_histogram) get(h);
    for (auto& h : q.dihedral_histogram) get(h);
    get(q.theorem1_violations), get(q.lemma6_interior_violations), get(q.lemma6_border_violations);
    get(q.graded_cells), get(q.graded_outside.theorem1), get(q.graded_outside.lemma6_interior),
        get(q.graded_outside.lemma6_border);
    get(q.shortest_edge);
  }
  void get(Histogram& h) {
    uint64_t n = 0;
    get(h.lo), get(h.hi), get(n);
    h.counts.resize(n);
    for (uint64_t& c : h.counts) get(c);
  }

 private:
  const Communicator::Bytes& b_;
  size_t at_ = 0;
};

}  // namespace

PartitionSummary combine_rank_reports(Communicator& comm, const RunReport& mine, const PartitionReport& part) {
  Packer out;
  out.put(part);
  out.put(mine.cells), out.put(mine.interior_cells), out.put(mine.fringe_cells), out.put(mine.edge_cells),
      out.put(mine.vertex_cells), out.put(mine.faces), out.put(mine.points), out.put(mine.not_star_shaped),
      out.put(mine.without_kernel), out.put(mine.split_seeds), out.put(mine.extra_pieces), out.put(mine.without_center);
  out.put(mine.volume_sum), out.put(mine.border_area), out.put(mine.star_violation), out.put(mine.total_seconds),
      out.put(mine.peak_rss_bytes), out.put(mine.weld_aspect_shift), out.put(mine.weld_dihedral_shift);
  // A multi-region solid's counts per region and interface (an interface face joins two parts of
  // one seed's cell, which a rank holds together: each is counted on one rank).
  out.put(mine.interface_cells);
  for (const RunReport::Region& r : mine.regions) out.put(r.cells), out.put(r.volume);
  for (const RunReport::Interface& i : mine.interfaces) out.put(i.from_a), out.put(i.from_b);
  for (const RunReport::Crack& c : mine.cracks) out.put(c.from_a), out.put(c.from_b), out.put(c.faces_a), out.put(c.faces_b),
        out.put(c.faces_on_front);
  out.put(uint64_t(mine.stages.size()));
  for (const StageTiming& s : mine.stages) out.put(s.seconds), out.put(s.peak_rss_bytes);
  out.put(bool(mine.welding));
  if (mine.welding) out.put(*mine.welding);
  for (const auto* q : {&mine.quality, &mine.bounds_before_weld}) {
    out.put(bool(*q));
    if (*q) out.put(**q);
  }

  PartitionSummary sum;
  RunReport& run = sum.run;
  run = mine;
  run.cells = run.interior_cells = run.fringe_cells = run.edge_cells = run.vertex_cells = 0;
  run.faces = run.points = run.not_star_shaped = run.without_kernel = run.split_seeds = run.extra_pieces = 0;
  run.without_center = 0;
  run.volume_sum = run.border_area = run.star_violation = run.total_seconds = 0;
  run.peak_rss_bytes = 0;
  run.weld_aspect_shift = run.weld_dihedral_shift = 0;
  run.interface_cells = 0;
  for (RunReport::Region& r : run.regions) r.cells = 0, r.volume = 0;
  for (RunReport::Interface& i : run.interfaces) i.from_a = i.from_b = 0;
  for (RunReport::Crack& c : run.cracks) c.from_a = c.from_b = 0, c.faces_a = c.faces_b = c.faces_on_front = 0;
  for (StageTiming& s : run.stages) s.seconds = 0, s.peak_rss_bytes = 0;
  std::optional<WeldStats> weld;
  std::optional<QualityReport> quality[2];
  for (const Communicator::Bytes& bytes : comm.all_gather(out.bytes)) {
    Unpacker in(bytes);
    PartitionReport p;
    in.get(p);
    sum.ranks.push_back(p);
    size_t n[12];
    for (size_t& v : n) in.get(v);
    run.cells += n[0], run.interior_cells += n[1], run.fringe_cells += n[2], run.edge_cells += n[3];
    run.vertex_cells += n[4], run.faces += n[5], run.points += n[6], run.not_star_shaped += n[7];
    run.without_kernel += n[8], run.split_seeds += n[9], run.extra_pieces += n[10], run.without_center += n[11];
    double volume, area, star, seconds, aspect_shift, dihedral_shift;
    size_t peak;
    in.get(volume), in.get(area), in.get(star), in.get(seconds), in.get(peak), in.get(aspect_shift),
        in.get(dihedral_shift);
    run.volume_sum += volume, run.border_area += area, run.star_violation = std::max(run.star_violation, star);
    run.total_seconds = std::max(run.total_seconds, seconds), run.peak_rss_bytes = std::max(run.peak_rss_bytes, peak);
    run.weld_aspect_shift = std::max(run.weld_aspect_shift, aspect_shift);
    run.weld_dihedral_shift = std::max(run.weld_dihedral_shift, dihedral_shift);
    sum.rank_seconds.push_back(seconds), sum.rank_peak_rss.push_back(peak);
    size_t interface_cells = 0;
    in.get(interface_cells);
    run.interface_cells += interface_cells;
    for (RunReport::Region& r : run.regions) {
      size_t cells = 0;
      double volume = 0;
      in.get(cells), in.get(volume);
      r.cells += cells, r.volume += volume;
    }
    for (RunReport::Interface& i : run.interfaces) {
      double a = 0, b = 0;
      in.get(a), in.get(b);
      i.from_a += a, i.from_b += b;
    }
    for (RunReport::Crack& c : run.cracks) {
      double a = 0, b = 0;
      size_t fa = 0, fb = 0, front = 0;  // (a face and its twin on two ranks: counted on neither)
      in.get(a), in.get(b), in.get(fa), in.get(fb), in.get(front);
      c.from_a += a, c.from_b += b, c.faces_a += fa, c.faces_b += fb, c.faces_on_front += front;
    }
    uint64_t stages = 0;
    in.get(stages);
    if (stages != run.stages.size()) fail(ErrorKind::Internal, "the ranks ran different stages");
    for (StageTiming& s : run.stages) {
      double t;
      size_t m;
      in.get(t), in.get(m);
      s.seconds = std::max(s.seconds, t), s.peak_rss_bytes = std::max(s.peak_rss_bytes, m);
    }
    bool has = false;
    in.get(has);
    if (has) {
      WeldStats w;
      in.get(w);
      if (!weld) {
        weld = w;
      } else {
        weld->edges_collapsed += w.edges_collapsed, weld->faces_removed += w.faces_removed;
        weld->clusters_refused += w.clusters_refused, weld->border_area += w.border_area;
        weld->shortest_edge_before = std::min(weld->shortest_edge_before, w.shortest_edge_before);
        weld->shortest_edge_after = std::min(weld->shortest_edge_after, w.shortest_edge_after);
        weld->max_displacement = std::max(weld->max_displacement, w.max_displacement);
        weld->max_nonplanarity = std::max(weld->max_nonplanarity, w.max_nonplanarity);
      }
    }
    for (auto& q : quality) {
      in.get(has);
      if (!has) continue;
      QualityReport r;
      in.get(r);
      if (q) merge_quality(*q, r);
      else q = std::move(r);
    }
  }
  run.welding = weld ? std::make_shared<const WeldStats>(*weld) : nullptr;
  run.quality = quality[0] ? std::make_shared<const QualityReport>(*quality[0]) : nullptr;
  run.bounds_before_weld = quality[1] ? std::make_shared<const QualityReport>(*quality[1]) : nullptr;
  return sum;
}

}  // namespace froth
