// Exodus II (Sandia's SEACAS format, Debian's libexodusii): one NSIDED face block holding every
// face once (interior faces in the orientation out of their lower cell, border faces outward),
// one NFACED element block per cell kind (interior, fringe, edge, vertex: ids 1 to 4, empty
// kinds left out) whose elements list their faces, element variables for the cell data at one
// time step (t = 0), one side set per input patch (ids from 1, named) with its border faces as
// (element, local face), and
// double-precision coordinates. Elements are numbered block by block; the element id map and the
// variable cell_id give each element's froth cell number (from 1).
#include <map>
#include <algorithm>

#include <fmt/format.h>

#include "froth/error.hpp"
#include "froth/io.hpp"
#include "froth/quality.hpp"
#include "io/quality_fields.hpp"
#include "io/atomic_file.hpp"

#ifdef FROTH_EXODUS
#include <exodusII.h>
#include <netcdf.h>
#endif

namespace froth {

#ifndef FROTH_EXODUS
void write_exodus(const PolyMesh&, const RunReport&, const std::filesystem::path& path) {
  fail(ErrorKind::Usage, fmt::format("{}: this froth was built without Exodus II (install Debian's libexodusii-dev "
                                     "and build again)",
                                     path.string()));
}
#else
namespace {

constexpr const char* kKindNames[] = {"interior", "fringe", "edge", "vertex", "interface_face", "interface_edge"};

void check(int status, const std::filesystem::path& path, const char* what) {
  if (status < 0) fail(ErrorKind::Io, fmt::format("{}: Exodus II could not write {} (error {})", path.string(), what, status));
}

// The VTU's cell data, one variable per component, in cell order.
std::vector<std::pair<std::string, std::vector<double>>> element_variables(const PolyMesh& m) {
  const size_t n = m.cell_count();
  std::vector<std::pair<std::string, std::vector<double>>> vars;
  auto add = [&](const std::string& name, auto value) {
    std::vector<double> v(n);
    for (size_t c = 0; c < n; ++c) v[c] = value(c);
    vars.push_back({name, std::move(v)});
  };
  add("cell_id", [&](size_t c) { return double(c + 1); });
  add("kind", [&](size_t c) { return double(int(m.kinds[c])); });
  add("volume", [&](size_t c) { return m.volumes[c]; });
  add("seedX", [&](size_t c) { return m.seeds[c].x; });
  add("seedY", [&](size_t c) { return m.seeds[c].y; });
  add("seedZ", [&](size_t c) { return m.seeds[c].z; });
  add("centerX", [&](size_t c) { return m.center_of(c).x; });
  add("centerY", [&](size_t c) { return m.center_of(c).y; });
  add("centerZ", [&](size_t c) { return m.center_of(c).z; });
  add("kernel", [&](size_t c) { return m.has_kernel(c) ? 1.0 : 0.0; });
  add("radius", [&](size_t c) { return m.radius_of(c, m.r); });
  add("piece", [&](size_t c) { return double(m.piece_of(c)); });
  if (m.quality.size() == n)
    for (const auto& field : kQualityFields)  // (not a structured binding: clang 14 cannot capture one)
      add(field.first, [&m, member = field.second](size_t c) { return m.quality[c].*member; });
  return vars;
}

}  // namespace

void write_exodus(const PolyMesh& m, const RunReport& run, const std::filesystem::path& path) {
  const size_t n = m.cell_count();
  if (m.face_vertices.size() > size_t(INT32_MAX) || m.face_count() > size_t(INT32_MAX))
    fail(ErrorKind::Usage, "this mesh is too large for Exodus II's 32-bit connectivity");
  // Every face once: its id (from 1) for each cell face, and the cells' local face of each
  // border face (for the side set).
  std::vector<int32_t> face_id(m.face_count(), 0);
  std::vector<int> face_nodes_count;
  std::vector<int> face_nodes;
  for (size_t c = 0; c < n; ++c)
    for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) {
      const int32_t g = m.face_generator[f];
      if (is_other_piece_generator(g))
        fail(ErrorKind::Usage, "an Exodus II mesh needs the whole mesh, not one rank's piece of a partitioned run");
      if (g >= 0 && size_t(g) < c) continue;  // the twin, numbered from the lower cell
      face_id[size_t(f)] = int32_t(face_nodes_count.size() + 1);
      const int64_t b = m.face_vertex_begin[f], e = m.face_vertex_begin[f + 1];
      face_nodes_count.push_back(int(e - b));
      for (int64_t k = b; k < e; ++k) face_nodes.push_back(m.face_vertices[k] + 1);
    }
  // A face toward a lower cell takes its twin's number there: the one face of that cell toward
  // this one, or where two cells share several faces (a cell wrapped around a thin feature), the
  // one with the same points.
  auto points_of = [&](int64_t f) {
    std::vector<int32_t> v(m.face_vertices.begin() + m.face_vertex_begin[f],
                           m.face_vertices.begin() + m.face_vertex_begin[f + 1]);
    std::sort(v.begin(), v.end());
    return v;
  };
  for (size_t c = 0; c < n; ++c)
    for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) {
      const int32_t g = m.face_generator[f];
      if (g < 0 || size_t(g) >= c) continue;
      int64_t twin = -1, candidates = 0;
      for (int64_t h = m.cell_face_begin[g]; h < m.cell_face_begin[g + 1]; ++h)
        if (m.face_generator[h] == int32_t(c)) twin = h, ++candidates;
      if (candidates > 1) {
        const std::vector<int32_t> mine = points_of(f);
        twin = -1;
        for (int64_t h = m.cell_face_begin[g]; h < m.cell_face_begin[g + 1] && twin < 0; ++h)
          if (m.face_generator[h] == int32_t(c) && points_of(h) == mine) twin = h;
      }
      if (twin < 0) fail(ErrorKind::Internal, fmt::format("cell {}: a face toward cell {} has no twin there", c, g));
      face_id[size_t(f)] = face_id[size_t(twin)];
    }

  // Elements by block, within a block in cell order: a block per cell kind, or per region for a
  // multi-region mesh (a solver gives each its material).
  const bool by_region = !m.region.empty();
  const int nblocks = by_region ? int(m.region_names.size()) : kCellKinds;
  auto block_of = [&](size_t c) { return by_region ? m.region[c] : int(m.kinds[c]); };
  auto block_name = [&](int k) { return by_region ? m.region_names[size_t(k)].c_str() : kKindNames[k]; };
  std::vector<size_t> order;
  std::vector<int64_t> per_kind(size_t(nblocks), 0);
  for (int k = 0; k < nblocks; ++k)
    for (size_t c = 0; c < n; ++c)
      if (block_of(c) == k) order.push_back(c), ++per_kind[size_t(k)];
  int blocks = 0;
  for (int64_t count : per_kind) blocks += count > 0;
  const size_t patches = std::max<size_t>(1, m.patch_names.size());
  std::vector<std::vector<int>> side_elements(patches), side_faces(patches);
  std::vector<size_t> element_of(n);
  for (size_t e = 0; e < n; ++e) element_of[order[e]] = e;
  std::vector<std::string> side_names;
  for (size_t q = 0; q < patches; ++q) side_names.push_back(m.patch_names.empty() ? "walls" : m.patch_names[q]);
  // A multi-region mesh: a side set per interface after the patches', the faces of its first
  // region's cells toward its second's (where a solver puts cohesive elements).
  std::map<std::pair<int32_t, int32_t>, size_t> interface_set;
  auto side_set_of = [&](int32_t a, int32_t b) {
    const auto [it, added] = interface_set.try_emplace({a, b}, side_names.size());
    if (added) {
      side_names.push_back(fmt::format("interface_{}_{}", m.region_names[size_t(a)], m.region_names[size_t(b)]));
      side_elements.emplace_back(), side_faces.emplace_back();
    }
    return it->second;
  };
  for (size_t c = 0; c < n; ++c)
    for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) {
      const int32_t g = m.face_generator[f];
      size_t set = side_names.size();
      if (is_border_generator(g)) set = size_t(m.patch_of(size_t(f)));
      else if (!m.region.empty() && m.region[c] < m.region[size_t(g)]) set = side_set_of(m.region[c], m.region[size_t(g)]);
      if (set == side_names.size()) continue;
      side_elements[set].push_back(int(element_of[c] + 1)), side_faces[set].push_back(int(f - m.cell_face_begin[c] + 1));
    }
  const size_t side_sets = side_names.size();

  write_atomically_by_name(path, [&](const std::filesystem::path& tmp) {
    int word = 8, io_word = 8;
    // The netCDF-4 (HDF5) flavour of Exodus, as SEACAS writes by default: netCDF's classic
    // format wrote the element variables 8 KB at a time, each byte many times over.
    const int exo = ex_create(tmp.c_str(), EX_CLOBBER | EX_NETCDF4, &word, &io_word);
    if (exo < 0) fail(ErrorKind::Io, fmt::format("{}: Exodus II cannot create the file", path.string()));
    struct Closer {
      int id;
      ~Closer() { ex_close(id); }
    } closer{exo};
    // No fill values: netCDF would otherwise write every record variable's fill in small pieces
    // before its values (the Exodus id is the netCDF id).
    int old_fill = 0;
    nc_set_fill(exo, NC_NOFILL, &old_fill);
    ex_init_params p{};
    fmt::format_to_n(p.title, MAX_LINE_LENGTH, "froth {} r = {} seed {}", FROTH_VERSION, run.r, run.seed);
    p.num_dim = 3;
    p.num_nodes = int64_t(m.points.size());
    p.num_face = int64_t(face_nodes_count.size());
    p.num_face_blk = 1;
    p.num_elem = int64_t(n);
    p.num_elem_blk = blocks;
    p.num_side_sets = int64_t(side_sets);
    check(ex_put_init_ext(exo, &p), path, "the header");
    // Everything is defined before any bulk data is written: netCDF's classic format rewrites
    // the whole file each time a definition follows data.
    std::vector<std::vector<int>> faces_of(static_cast<size_t>(nblocks)), element_faces(static_cast<size_t>(nblocks));
    for (size_t e = 0, first = 0; e < size_t(nblocks); first += size_t(per_kind[e]), ++e)
      for (size_t k = first; k < first + size_t(per_kind[e]); ++k) {
        const size_t c = order[k];
        faces_of[e].push_back(int(m.cell_face_begin[c + 1] - m.cell_face_begin[c]));
        for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f)
          element_faces[e].push_back(face_id[size_t(f)]);
      }
    check(ex_put_block(exo, EX_FACE_BLOCK, 1, "NSIDED", p.num_face, int64_t(face_nodes.size()), 0, 0, 0), path,
          "the face block");
    for (int k = 0; k < nblocks; ++k)
      if (per_kind[size_t(k)] > 0)
        check(ex_put_block(exo, EX_ELEM_BLOCK, k + 1, "NFACED", per_kind[size_t(k)], 0, 0,
                           int64_t(element_faces[size_t(k)].size()), 0),
              path, "an element block");
    for (size_t q = 0; q < side_sets; ++q)
      check(ex_put_set_param(exo, EX_SIDE_SET, int64_t(q + 1), int64_t(side_elements[q].size()), 0), path,
            "a side set");
    const std::vector<std::pair<std::string, std::vector<double>>> vars = element_variables(m);
    check(ex_put_variable_param(exo, EX_ELEM_BLOCK, int(vars.size())), path, "the variables");
    std::vector<int> ids(n);
    for (size_t e = 0; e < n; ++e) ids[e] = int(order[e] + 1);
    check(ex_put_id_map(exo, EX_ELEM_MAP, ids.data()), path, "the element id map");

    const char* axes[] = {"x", "y", "z"};
    check(ex_put_coord_names(exo, const_cast<char**>(axes)), path, "the coordinate names");
    for (int k = 0; k < nblocks; ++k)
      if (per_kind[size_t(k)] > 0) check(ex_put_name(exo, EX_ELEM_BLOCK, k + 1, block_name(k)), path, "a block name");
    for (size_t q = 0; q < side_sets; ++q)
      check(ex_put_name(exo, EX_SIDE_SET, int64_t(q + 1), side_names[q].c_str()), path, "a side set's name");
    for (size_t v = 0; v < vars.size(); ++v)
      check(ex_put_variable_name(exo, EX_ELEM_BLOCK, int(v + 1), vars[v].first.c_str()), path, "a variable name");

    std::vector<double> x(m.points.size()), y(m.points.size()), z(m.points.size());
    for (size_t v = 0; v < m.points.size(); ++v) x[v] = m.points[v].x, y[v] = m.points[v].y, z[v] = m.points[v].z;
    check(ex_put_coord(exo, x.data(), y.data(), z.data()), path, "the coordinates");
    check(ex_put_conn(exo, EX_FACE_BLOCK, 1, face_nodes.data(), nullptr, nullptr), path, "the faces");
    check(ex_put_entity_count_per_polyhedra(exo, EX_FACE_BLOCK, 1, face_nodes_count.data()), path, "the face sizes");
    for (int k = 0; k < nblocks; ++k) {
      if (per_kind[size_t(k)] == 0) continue;
      check(ex_put_conn(exo, EX_ELEM_BLOCK, k + 1, nullptr, nullptr, element_faces[size_t(k)].data()), path,
            "an element block's faces");
      check(ex_put_entity_count_per_polyhedra(exo, EX_ELEM_BLOCK, k + 1, faces_of[size_t(k)].data()), path,
            "an element block's face counts");
    }
    for (size_t q = 0; q < side_sets; ++q)
      check(ex_put_set(exo, EX_SIDE_SET, int64_t(q + 1), side_elements[q].data(), side_faces[q].data()), path,
            "a side set's faces");
    const double time = 0;
    check(ex_put_time(exo, 1, &time), path, "the time step");
    size_t first = 0;
    for (int k = 0; k < nblocks; ++k) {
      if (per_kind[size_t(k)] == 0) continue;
      std::vector<double> values(static_cast<size_t>(per_kind[size_t(k)]));
      for (size_t v = 0; v < vars.size(); ++v) {
        for (size_t e = 0; e < values.size(); ++e) values[e] = vars[v].second[order[first + e]];
        check(ex_put_var(exo, 1, EX_ELEM_BLOCK, int(v + 1), k + 1, per_kind[size_t(k)], values.data()), path,
              "a variable");
      }
      first += size_t(per_kind[size_t(k)]);
    }
  });
}
#endif

}  // namespace froth
