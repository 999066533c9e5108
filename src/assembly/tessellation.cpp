// Every seed's cell (assembly/cell_builder.hpp), built in chunks of seeds in parallel, then
// assembled into one mesh.
//
// Conformity: a vertex's name is the sorted set of its generators plus the cell's own seed
// ({a,b,c,d} for a Voronoi vertex, {a,b,P,Q} on a domain edge, ...). Every cell that has the
// vertex computes the same name, so the vertex's owner, the cell of its smallest seed, gives it
// one global id and the other cells look it up there. Ids follow the seed order, so the mesh is
// the same for any thread count.
#include "common/face_scratch.hpp"
#include "assembly/tessellation.hpp"

#include <omp.h>

#include <algorithm>
#include <functional>
#include <atomic>
#include <chrono>
#include <exception>
#include <cmath>
#include <mutex>
#include <optional>

#include <fmt/format.h>

#include "clip/clip_cell.hpp"
#include "common/page_allocator.hpp"
#include "common/tolerances.hpp"
#include "froth/error.hpp"
#include "voronoi/convex_cell.hpp"
#include "assembly/cell_builder.hpp"
#include "assembly/holed_faces.hpp"
#include "assembly/region_cells.hpp"
#include "assembly/split_pieces.hpp"
#include "assembly/glue_extensions.hpp"
#include "input/cracked_domain.hpp"

namespace froth {
namespace {

constexpr size_t kCellsPerChunk = 2048;

// Cells of one chunk as built. Other cells read only the names of the vertices a cell owns;
// everything else is read by the chunk itself during assembly and freed right after, which
// keeps the peak memory of assembly low.
template <class T>
using PagedVector = std::vector<T, PageAllocator<T>>;

struct CellChunk {
  // Read by other chunks (owner look-ups) until assembly ends.
  PagedVector<uint32_t> owned_begin{0};      // per cell, into owned_key_len
  PagedVector<uint32_t> owned_key_begin{0};  // per cell, into owned_keys
  PagedVector<uint8_t> owned_key_len;        // per owned vertex
  PagedVector<int32_t> owned_keys;           // sorted generator names, own seed left out
  // Read by this chunk only.
  PagedVector<uint32_t> vertex_begin{0};     // per cell, into vertex_info
  PagedVector<uint8_t> vertex_info;          // per vertex: key length, top bit set if owned
  PagedVector<int32_t> other_keys;           // names of the vertices owned by other cells
  PagedVector<Vec3> owned_points;
  PagedVector<uint32_t> face_begin{0};       // per cell, into face_gen
  PagedVector<int32_t> face_gen;
  PagedVector<int32_t> face_region;          // a multi-region solid's: each face's region
  PagedVector<uint8_t> face_size;            // 0: a face of over 255 vertices, its size in long_faces
  std::vector<uint32_t> long_faces;
  // Local vertex ids in bytes; a chunk switches to 16 bits once a (clipped) cell has more than
  // 256 vertices, so convex domains keep the byte's memory.
  PagedVector<uint8_t> face_vert;
  PagedVector<uint16_t> face_vert_wide;
  bool wide = false;
  uint16_t local_vertex(size_t k) const { return wide ? face_vert_wide[k] : face_vert[k]; }
  PagedVector<CellKind> kinds;
  size_t face_vertex_count = 0;
  std::vector<int32_t> in_pieces;  // cells (of the mesh) whose part of the domain is in several pieces
  std::vector<std::pair<uint32_t, uint32_t>> holed;  // faces with holes: (first face in the chunk, loops)

  // Room for typical cells, generously: pages never touched cost no memory, and growth would
  // copy.
  void reserve(size_t cells) {
    for (auto* v : {&owned_begin, &owned_key_begin, &vertex_begin, &face_begin}) v->reserve(cells + 1);
    owned_key_len.reserve(cells * 16);
    owned_keys.reserve(cells * 64);
    vertex_info.reserve(cells * 64);
    other_keys.reserve(cells * 192);
    owned_points.reserve(cells * 16);
    face_gen.reserve(cells * 40);
    face_size.reserve(cells * 40);
    face_vert.reserve(cells * 192);
    kinds.reserve(cells);
  }

  void release_private() {
    for (auto* v : {&vertex_begin, &face_begin}) PagedVector<uint32_t>().swap(*v);
    for (auto* v : {&vertex_info, &face_size, &face_vert}) PagedVector<uint8_t>().swap(*v);
    PagedVector<uint16_t>().swap(face_vert_wide);
    PagedVector<int32_t>().swap(other_keys);
    PagedVector<int32_t>().swap(face_gen);
    PagedVector<int32_t>().swap(face_region);
    PagedVector<Vec3>().swap(owned_points);
    PagedVector<CellKind>().swap(kinds);
  }
};

constexpr uint8_t kOwnedBit = 0x80;

// The vertex's owner: the smallest seed of its name among the cells built (from `first` on).
int32_t owner_of(const int32_t* key, int len, int32_t first) {
  return *std::find_if(key, key + len, [first](int32_t g) { return g >= first; });
}

// Do the names a + {self} and b + {owner} agree (each sorted, each without its own cell's
// seed)? As owner is in a, that is a - {owner} == b - {self}, with self in b.
bool same_vertex(const int32_t* a, int32_t self, const int32_t* b, int32_t owner, int len) {
  if (len == 3) {  // nearly every vertex: without the branches of the general walk, which mispredict
    const int32_t a_lo = a[0] == owner ? a[1] : a[0], a_hi = a[2] == owner ? a[1] : a[2];
    const int32_t b_lo = b[0] == self ? b[1] : b[0], b_hi = b[2] == self ? b[1] : b[2];
    return ((b[0] == self) | (b[1] == self) | (b[2] == self)) & (a_lo == b_lo) & (a_hi == b_hi);
  }
  int i = 0, j = 0;
  for (;;) {
    if (i < len && a[i] == owner) { ++i; continue; }
    if (j < len && b[j] == self) { ++j; continue; }
    if (i == len || j == len) return i == len && j == len;
    if (a[i++] != b[j++]) return false;
  }
}

// Is the name a + {self} (sorted, len entries) inside the name b + {owner} (sorted, blen)? A
// vertex where more seeds meet than a vertex's three faces need (seeds on one sphere: protection
// seeds at equal distances on one planar face) is one vertex, named by all of them, in the cell
// whose clipping found them within its tolerance, and two vertices a rounding error apart,
// named by fewer, in another cell: both of those are that one vertex.
bool inside_name(const int32_t* a, int32_t self, int len, const int32_t* b, int32_t owner, int blen) {
  auto in_b = [&](int32_t g) { return g == owner || std::binary_search(b, b + blen, g); };
  if (!in_b(self)) return false;
  for (int i = 0; i < len; ++i)
    if (!in_b(a[i])) return false;
  return true;
}

// Drops each face's repeated consecutive vertices (cyclically) and the faces left with fewer
// than three: where inside_name merged the two vertices of a degenerate one.
void drop_repeated_vertices(PolyMesh& m) {
  const size_t nc = m.cell_count();
  int64_t face = 0, entry = 0;
  for (size_t c = 0; c < nc; ++c) {
    const int64_t f0 = m.cell_face_begin[c], f1 = m.cell_face_begin[c + 1];
    m.cell_face_begin[c] = face;
    for (int64_t f = f0; f < f1; ++f) {
      const int64_t b = m.face_vertex_begin[f], e = m.face_vertex_begin[f + 1], start = entry;
      for (int64_t k = b; k < e; ++k)
        if (entry == start || m.face_vertices[entry - 1] != m.face_vertices[k]) m.face_vertices[entry++] = m.face_vertices[k];
      while (entry - start > 1 && m.face_vertices[entry - 1] == m.face_vertices[start]) --entry;
      if (entry - start < 3) {
        entry = start;
        continue;
      }
      m.face_generator[face] = m.face_generator[f];
      m.face_vertex_begin[face++] = start;
    }
  }
  m.cell_face_begin[nc] = face;
  m.face_vertex_begin[face] = entry;
  m.face_generator.resize(size_t(face));
  m.face_vertex_begin.resize(size_t(face) + 1);
  m.face_vertices.resize(size_t(entry));
}

template <class Cell>
void append_cell(CellChunk& ch, int32_t i, Vec3 x, const Cell& cell, const std::vector<ConvexCell::Names>& names,
                 const Sample::Protected* protection, SeedRange built) {
  int32_t key[ConvexCell::kMaxGenerators];
  bool fringe = false;
  for (size_t v = 0; v < cell.vertex_count(); ++v) {
    // The vertex's name without the cell's own seed, which is implied; sorted.
    const int n = names[v].n;
    std::copy_n(names[v].gen, ConvexCell::kMaxGenerators, key);  // all of them: a fixed-size copy, no call
    if (n == 3) {  // nearly every vertex: a sorting network, without the branches that mispredict
      auto order = [](int32_t& a, int32_t& b) {
        const int32_t lo = std::min(a, b), hi = std::max(a, b);
        a = lo, b = hi;
      };
      order(key[0], key[1]), order(key[1], key[2]), order(key[0], key[1]);
    } else {  // at most kMaxGenerators (std::sort here also drew a false GCC 12 -Warray-bounds)
      insertion_sort(key, key + n, std::less<int32_t>());
    }
    // This cell owns the vertex iff its seed is the smallest built seed of the name (owner_of).
    bool owned = true;
    for (int a = 0; a < n; ++a) owned &= !(key[a] >= built.begin && key[a] < i);
    ch.vertex_info.push_back(uint8_t(n | (owned ? kOwnedBit : 0)));
    if (owned) {
      ch.owned_key_len.push_back(uint8_t(n));
      for (int a = 0; a < n; ++a) ch.owned_keys.push_back(key[a]);  // (a range insert called memmove)
      ch.owned_points.push_back(x + cell.vertex(v));
    } else {
      for (int a = 0; a < n; ++a) ch.other_keys.push_back(key[a]);
    }
  }
  if (!ch.wide && cell.vertex_count() > 256) {
    ch.face_vert_wide.assign(ch.face_vert.begin(), ch.face_vert.end());
    PagedVector<uint8_t>().swap(ch.face_vert);
    ch.wide = true;
  }
  for (size_t f = 0; f < cell.face_count(); ++f) {
    int32_t g = cell.face_generator(f);
    fringe |= is_border_generator(g);
    if constexpr (requires { cell.face_loop(f); }) {
      if (cell.face_loop(f) == 1) ch.holed.push_back({uint32_t(ch.face_gen.size()), 1});
      if (cell.face_loop(f) == 2) ++ch.holed.back().second;
    }
    // Neighbours by cell index; one that is not built is another piece's.
    if (g >= 0) g = g >= built.begin && g < built.end ? g - built.begin : kOtherPiece;
    ch.face_gen.push_back(g);
    if constexpr (requires { cell.face_region(f); }) ch.face_region.push_back(cell.face_region(f));
    const size_t size = cell.face_size(f);
    ch.face_size.push_back(size <= 255 ? uint8_t(size) : 0);
    if (size > 255) ch.long_faces.push_back(uint32_t(size));
    const uint16_t* fv = cell.face_begin(f);
    for (size_t k = 0; k < cell.face_size(f); ++k)
      ch.wide ? ch.face_vert_wide.push_back(fv[k]) : ch.face_vert.push_back(uint8_t(fv[k]));
    ch.face_vertex_count += cell.face_size(f);
  }
  ch.kinds.push_back(protection ? protection->kind : fringe ? CellKind::Fringe : CellKind::Interior);
  ch.vertex_begin.push_back(uint32_t(ch.vertex_info.size()));
  ch.owned_begin.push_back(uint32_t(ch.owned_key_len.size()));
  ch.owned_key_begin.push_back(uint32_t(ch.owned_keys.size()));
  ch.face_begin.push_back(uint32_t(ch.face_gen.size()));
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The global id of a vertex that cell i (of seed first_seed + i) does not own, named by `key`
// (len generators): its rank among its owner's owned vertices. The owner is the smallest built
// seed among the name and this cell; names hold seed indices, `owner` and `i` are cell indices.
// -1 where the owner has no such vertex; `degenerate` set where it was found as the owner's one
// vertex whose longer name holds this one.
int32_t owned_vertex(const std::vector<CellChunk>& chunks, const std::vector<int64_t>& owned_base, const int32_t* key,
                     int len, int32_t i, int32_t first_seed, bool& degenerate) {
  const int32_t owner = owner_of(key, len, first_seed) - first_seed;
  const CellChunk& oc = chunks[owner / kCellsPerChunk];
  const size_t ok = owner % kCellsPerChunk;
  uint32_t okb = oc.owned_key_begin[ok];
  int32_t found = -1;
  for (uint32_t w = oc.owned_begin[ok]; w < oc.owned_begin[ok + 1]; ++w) {
    const int olen = oc.owned_key_len[w];
    if (olen == len && same_vertex(key, i + first_seed, &oc.owned_keys[okb], owner + first_seed, len)) {
      found = int32_t(owned_base[owner] + (w - oc.owned_begin[ok]));
      break;
    }
    okb += olen;
  }
  if (found < 0) {  // a degenerate vertex: the owner's one vertex whose name holds this one's
    okb = oc.owned_key_begin[ok];
    for (uint32_t w = oc.owned_begin[ok]; w < oc.owned_begin[ok + 1]; ++w) {
      const int olen = oc.owned_key_len[w];
      if (olen > len && inside_name(key, i + first_seed, len, &oc.owned_keys[okb], owner + first_seed, olen)) {
        if (found >= 0) {  // two such: no single one to take
          found = -1;
          break;
        }
        found = int32_t(owned_base[owner] + (w - oc.owned_begin[ok]));
      }
      okb += olen;
    }
    degenerate = found >= 0;
  }
  return found;
}

// The cells of seeds `built` (all: {0, -1}), chunk by chunk in parallel; `times` gets the cells
// stage's figures.
std::vector<CellChunk> build_cells(const Domain& domain, const Sample& sample, double r, SeedRange built,
                                   TessellationTimes* times, const std::function<void(double)>& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  const int32_t first_seed = built.begin;
  const size_t n = size_t(built.end - built.begin);
  const size_t nchunks = (n + kCellsPerChunk - 1) / kCellsPerChunk;
  std::vector<CellChunk> chunks;
  std::mutex error_mutex;
  size_t first_bad = n;
  CellBuilder::CellError first_error;
  std::atomic<bool> stop = false;
  std::exception_ptr stopped;
  // A convex domain's cells are cut by its planes; if one overflows (a cone's apex, where more
  // planes meet than a ConvexCell holds), every cell is built again clipped to the surface, as a
  // non-convex domain's are, so that all cells name their vertices alike.
  for (const bool clip_convex : {false, true}) {
    chunks.assign(nchunks, CellChunk());
    first_bad = n, first_error = {};
    CellBuilder builder(domain, sample, r, clip_convex);
    std::atomic<size_t> chunks_done = 0;
    const std::vector<int32_t> seed_region = builder.seed_regions();

#pragma omp parallel
    {
      CellBuilder::Workspace w = builder.workspace();
#pragma omp for schedule(dynamic, 1)
      for (size_t c = 0; c < nchunks; ++c) {
        if (stop.load(std::memory_order_relaxed)) continue;
        CellChunk& ch = chunks[c];
        ch.reserve(std::min(n, (c + 1) * kCellsPerChunk) - c * kCellsPerChunk);
        for (size_t k = c * kCellsPerChunk; k < std::min(n, (c + 1) * kCellsPerChunk); ++k) {
          const int32_t i = first_seed + int32_t(k);
          const CellBuilder::CellError err = builder.build(i, w, seed_region.empty() ? -1 : seed_region[size_t(i)]);
          if (err.failed()) {
            std::lock_guard lock(error_mutex);
            if (k < first_bad) first_bad = k, first_error = err;
            break;
          }
          const Sample::Protected* protection = sample.protection_of(i);
          if (w.region_clipper) {
            append_cell(ch, i, sample.seeds[i], w.in_regions, w.in_regions.names(), protection, built);
            if (w.in_regions.pieces() > 1) ch.in_pieces.push_back(int32_t(k));
            continue;
          }
          if (w.is_clipped) append_cell(ch, i, sample.seeds[i], w.clipped, w.clipped.names(), protection, built);
          else append_cell(ch, i, sample.seeds[i], w.cell, w.names, protection, built);
          if (w.is_clipped && w.clipped.pieces() > 1) ch.in_pieces.push_back(int32_t(k));
        }
        const size_t finished = chunks_done.fetch_add(1, std::memory_order_relaxed) + 1;
        // The caller may stop the run from its progress callback: its error is carried out of
        // the threads, which skip the chunks left.
        if (progress && omp_get_thread_num() == 0) try {
            progress(double(finished) / double(nchunks));
          } catch (...) {
            stopped = std::current_exception();
            stop.store(true, std::memory_order_relaxed);
          }
      }
    }
    if (stopped) std::rethrow_exception(stopped);
    if (times) times->recut_cells = builder.recut_cells();
    if (!(first_error.failed() && first_error.cut_failed && !clip_convex)) break;
  }
  if (first_error.failed()) fail(first_error.kind, first_error.text);
  if (times) times->cells = seconds_since(t0), times->cells_peak_rss = peak_rss_bytes();
  return chunks;
}

// Global numbering: owned vertices in seed order; faces and face vertices in cell order. The
// chunks' private parts are freed as they are copied; `chunk_face` gets each chunk's first face.
PolyMesh number_globally(const Domain& domain, Sample& sample, double r, SeedRange built, std::vector<CellChunk>& chunks,
                         std::vector<int64_t>& chunk_face, bool& merged_any) {
  const int32_t first_seed = built.begin;
  const size_t n = size_t(built.end - built.begin), nchunks = chunks.size();
  PolyMesh mesh;
  mesh.r = r;
  // The grid is not needed any more: free it before the peak.
  std::vector<int32_t>().swap(sample.cube_seed);
  if (n == sample.seeds.size()) mesh.seeds = std::move(sample.seeds);
  else mesh.seeds.assign(sample.seeds.begin() + built.begin, sample.seeds.begin() + built.end);
  std::vector<int64_t> owned_base(n + 1, 0);
  chunk_face.assign(nchunks + 1, 0);
  std::vector<int64_t> chunk_fv(nchunks + 1, 0);
  for (size_t c = 0; c < nchunks; ++c) {
    const CellChunk& ch = chunks[c];
    size_t first = c * kCellsPerChunk;
    for (size_t k = 0; k + 1 < ch.owned_begin.size(); ++k)
      owned_base[first + k + 1] = owned_base[first + k] + (ch.owned_begin[k + 1] - ch.owned_begin[k]);
    chunk_face[c + 1] = chunk_face[c] + int64_t(ch.face_gen.size());
    chunk_fv[c + 1] = chunk_fv[c] + int64_t(ch.face_vertex_count);
  }
  mesh.points.resize(owned_base[n]);
  mesh.kinds.resize(n);
  mesh.cell_face_begin.resize(n + 1);
  mesh.face_generator.resize(chunk_face[nchunks]);
  if (domain.regions) scratch_of(mesh).face_region.resize(chunk_face[nchunks]);
  mesh.face_vertex_begin.resize(chunk_face[nchunks] + 1);
  mesh.face_vertices.resize(chunk_fv[nchunks]);
  mesh.cell_face_begin[n] = chunk_face[nchunks];
  mesh.face_vertex_begin[chunk_face[nchunks]] = chunk_fv[nchunks];

  std::atomic<size_t> unmatched{0}, merged_degenerate{0};
#pragma omp parallel
  {
    std::vector<int32_t> gid;
#pragma omp for schedule(dynamic, 1)
    for (size_t c = 0; c < nchunks; ++c) {
      CellChunk& ch = chunks[c];
      const size_t first = c * kCellsPerChunk;
      std::copy(ch.owned_points.begin(), ch.owned_points.end(), mesh.points.begin() + owned_base[first]);
      std::copy(ch.kinds.begin(), ch.kinds.end(), mesh.kinds.begin() + first);
      int64_t face = chunk_face[c], fv = chunk_fv[c];
      size_t local_fv = 0, other = 0, long_face = 0;
      for (size_t k = 0; k + 1 < ch.vertex_begin.size(); ++k) {
        const int32_t i = int32_t(first + k);  // cell index; its seed is first_seed + i
        // Global id of each local vertex: its rank among the owner's owned vertices.
        gid.clear();
        int32_t rank = 0;
        for (uint32_t v = ch.vertex_begin[k]; v < ch.vertex_begin[k + 1]; ++v) {
          const int len = ch.vertex_info[v] & ~kOwnedBit;
          if (ch.vertex_info[v] & kOwnedBit) {
            gid.push_back(int32_t(owned_base[i] + rank++));
            continue;
          }
          const int32_t* key = &ch.other_keys[other];
          other += len;
          bool degenerate = false;
          const int32_t found = owned_vertex(chunks, owned_base, key, len, i, first_seed, degenerate);
          if (degenerate) merged_degenerate.fetch_add(1, std::memory_order_relaxed);
          if (found < 0) unmatched.fetch_add(1, std::memory_order_relaxed);
          gid.push_back(std::max(found, 0));
        }
        mesh.cell_face_begin[i] = face;
        for (uint32_t f = ch.face_begin[k]; f < ch.face_begin[k + 1]; ++f) {
          mesh.face_generator[face] = ch.face_gen[f];
          if (!ch.face_region.empty()) scratch_of(mesh).face_region[face] = ch.face_region[f];
          mesh.face_vertex_begin[face] = fv;
          const size_t size = ch.face_size[f] ? ch.face_size[f] : ch.long_faces[long_face++];
          for (size_t s = 0; s < size; ++s) mesh.face_vertices[fv++] = gid[ch.local_vertex(local_fv++)];
          ++face;
        }
      }
      ch.release_private();
    }
  }
  if (unmatched > 0)
    fail(ErrorKind::Internal,
         fmt::format("{} cell vertices are missing from the cell that owns them: neighbouring cells disagree "
                     "(near-degenerate seeds?)",
                     unmatched.load()));
  merged_any = merged_degenerate > 0;
  return mesh;
}

}  // namespace

PolyMesh build_voronoi_mesh(const Domain& domain, Sample&& sample, double r, TessellationTimes* times,
                            SeedRange built, double min_piece_volume, const std::function<void(double)>& progress) {
  if (built.end < 0) built = {0, int32_t(sample.seeds.size())};
  const int32_t first_seed = built.begin;
  std::vector<CellChunk> chunks = build_cells(domain, sample, r, built, times, progress);
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<int64_t> chunk_face;
  bool merged_degenerate = false;
  PolyMesh mesh = number_globally(domain, sample, r, built, chunks, chunk_face, merged_degenerate);
  // Faces with holes as triangles, then a cell whose part of the domain is in several pieces
  // as one cell per piece.
  std::vector<HoledFace> holed;
  for (size_t c = 0; c < chunks.size(); ++c)
    for (const auto& [face, loops] : chunks[c].holed) holed.push_back({chunk_face[c] + face, loops});
  if (const std::string error = triangulate_holed_faces(mesh, holed); !error.empty()) fail(ErrorKind::Internal, error);
  std::vector<SplitCell> split;
  for (const CellChunk& ch : chunks)
    for (int32_t k : ch.in_pieces) {
      const Sample::Protected* p = sample.protection_of(first_seed + k);
      const Vec3 x = mesh.seeds[size_t(k)];
      // A crack's two sides are cells of their own however small (one merged into the other
      // would reach across the crack); only a fin of no volume (clip/clip_cell.cpp) stays with
      // the seed's piece, for glue_extensions to remove.
      split.push_back({k, p ? x + 1e-6 * r * p->inward : x, domain.cracks ? 1e-12 * r * r * r : min_piece_volume});
    }
  split_pieces(mesh, split, domain.regions.get(), domain.cracks != nullptr);
  if (merged_degenerate) drop_repeated_vertices(mesh);
  if (domain.cracks) {
    const CrackSet& set = *domain.cracks;
    std::vector<std::array<int32_t, 3>> sheet_planes;
    for (size_t k = 0; k < set.plane_middle.size(); ++k)
      sheet_planes.push_back({set.plane_begin[k], set.plane_middle[k], set.plane_begin[k + 1]});
    if (const std::string error = glue_extensions(mesh, set.extension_planes, sheet_planes, 1e-9 * r); !error.empty())
      fail(ErrorKind::Internal, error);
    scratch_of(mesh).point_twins = crack_point_twins(mesh, sheet_planes, 1e-9 * r);
  }
  if (times) times->assembly = seconds_since(t0);
  return mesh;
}

}  // namespace froth
