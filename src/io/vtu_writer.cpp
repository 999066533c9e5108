// VTK XML UnstructuredGrid (format 1.0, UInt64 headers, appended raw binary) of VTK_POLYHEDRON
// cells in the `faces` / `faceoffsets` layout that VTK 9.1 and ParaView read. Output is a pure
// function of the mesh and the run parameters: no time stamps, no host names.
#include <algorithm>
#include <climits>
#include <cstring>
#include <functional>
#include <sstream>

#include <zlib.h>

#include <fmt/format.h>

#include "common/cell_points.hpp"
#include "froth/io.hpp"
#include "io/atomic_file.hpp"
#include "io/quality_fields.hpp"

namespace froth {
namespace {

constexpr uint8_t kVtkPolyhedron = 42;

// Appended raw data: each block is a UInt64 byte count and the bytes. Blocks are produced by
// callbacks that stream their values, so no array is materialised beyond the mesh itself.
// Compressed (--compress), each array is produced into memory at once and cut into pieces of
// kPiece bytes that zlib compresses in parallel, in VTK's vtkZLibDataCompressor layout: the
// piece count, piece size, last piece's size and each compressed size, then the pieces.
class AppendedBlocks {
 public:
  using Producer = std::function<void(std::ostream&)>;
  explicit AppendedBlocks(bool compress) : compress_(compress) {}
  // Registers a block and returns the XML attribute text for its offset.
  std::string add(uint64_t bytes, Producer produce) {
    std::string attr = fmt::format("format=\"appended\" offset=\"{}\"", offset_);
    if (compress_) {
      std::ostringstream raw;
      produce(raw);
      std::string packed = compressed(raw.str());
      offset_ += packed.size();
      blocks_.push_back({0, [packed = std::move(packed)](std::ostream& out) {
                           out.write(packed.data(), std::streamsize(packed.size()));
                         }});
      return attr;
    }
    blocks_.push_back({bytes, std::move(produce)});
    offset_ += sizeof(uint64_t) + bytes;
    return attr;
  }
  // `progress`, if set, is told the fraction of the bytes written after each block.
  void write(std::ostream& out, const std::function<void(double)>& progress) const {
    uint64_t done = 0;
    for (const auto& [bytes, produce] : blocks_) {
      if (!compress_) out.write(reinterpret_cast<const char*>(&bytes), sizeof bytes), done += sizeof bytes;
      const auto before = out.tellp();
      produce(out);
      done += compress_ ? uint64_t(out.tellp() - before) : bytes;
      if (progress) progress(double(done) / double(offset_));
    }
  }

 private:
  static constexpr size_t kPiece = 1 << 20;
  static std::string compressed(const std::string& raw) {
    const size_t pieces = std::max<size_t>(1, (raw.size() + kPiece - 1) / kPiece);
    std::vector<std::string> out(pieces);
#pragma omp parallel for schedule(dynamic, 1)
    for (size_t k = 0; k < pieces; ++k) {
      const size_t at = k * kPiece, n = std::min(kPiece, raw.size() - std::min(raw.size(), at));
      uLongf size = compressBound(uLong(n));
      out[k].resize(size);
      // Level 1: most of the saving at a fraction of the time (doubles compress little further).
      compress2(reinterpret_cast<Bytef*>(out[k].data()), &size, reinterpret_cast<const Bytef*>(raw.data() + at), uLong(n), 1);
      out[k].resize(size);
    }
    std::vector<uint64_t> header{pieces, kPiece, raw.size() - (pieces - 1) * kPiece};
    if (raw.empty()) header[2] = 0;
    for (const std::string& p : out) header.push_back(p.size());
    std::string block(reinterpret_cast<const char*>(header.data()), header.size() * sizeof(uint64_t));
    size_t total = block.size();
    for (const std::string& p : out) total += p.size();
    block.reserve(total);
    for (const std::string& p : out) block += p;
    return block;
  }
  bool compress_ = false;
  std::vector<std::pair<uint64_t, Producer>> blocks_;
  uint64_t offset_ = 0;
};

// Buffers small writes of one type.
template <class T>
class ValueWriter {
 public:
  explicit ValueWriter(std::ostream& out) : out_(out) { buf_.reserve(kSize); }
  ~ValueWriter() { flush(); }
  void put(T v) {
    buf_.push_back(v);
    if (buf_.size() == kSize) flush();
  }
  void flush() {
    out_.write(reinterpret_cast<const char*>(buf_.data()), std::streamsize(buf_.size() * sizeof(T)));
    buf_.clear();
  }

 private:
  static constexpr size_t kSize = 1 << 16;
  std::ostream& out_;
  std::vector<T> buf_;
};

std::string data_array(AppendedBlocks& w, uint64_t bytes, AppendedBlocks::Producer p, const char* type,
                       const char* name, int components = 1) {
  // NumberOfComponents only for vectors: meshio reads a declared single component as a column.
  std::string comps = components > 1 ? fmt::format(" NumberOfComponents=\"{}\"", components) : "";
  return fmt::format("<DataArray type=\"{}\" Name=\"{}\"{} {}/>\n", type, name, comps, w.add(bytes, std::move(p)));
}

template <class Vector>
std::string raw_array(AppendedBlocks& w, const Vector& v, const char* type, const char* name, int components = 1) {
  const uint64_t bytes = v.size() * sizeof(v[0]);
  return data_array(
      w, bytes, [&v, bytes](std::ostream& out) { out.write(reinterpret_cast<const char*>(v.data()), std::streamsize(bytes)); },
      type, name, components);
}

// The VTK name of an index type.
template <class Index>
const char* index_type() {
  return sizeof(Index) == 4 ? "Int32" : "Int64";
}

// A VTK offsets array: the running end of each cell's entries, given each cell's length.
template <class Index, class Length>
std::string end_offsets(AppendedBlocks& w, size_t cells, Length length, const char* name) {
  return data_array(
      w, cells * sizeof(Index),
      [cells, length](std::ostream& out) {
        ValueWriter<Index> vw(out);
        int64_t end = 0;
        for (size_t c = 0; c < cells; ++c) vw.put(Index(end += length(c)));
      },
      index_type<Index>(), name);
}

// The options that shaped h (--grade): the floor and slope in effect, when grading was asked for.
std::string grading_field_data(const RunReport& run) {
  if (!run.grade) return "";
  const double floor = run.sizing.graded ? run.sizing.min_r : run.r;
  return fmt::format("<DataArray type=\"Int32\" Name=\"grade\" NumberOfTuples=\"1\" format=\"ascii\">1</DataArray>\n"
                     "<DataArray type=\"Float64\" Name=\"min_r\" NumberOfTuples=\"1\" format=\"ascii\">{:.17g}</DataArray>\n"
                     "<DataArray type=\"Float64\" Name=\"max_grading\" NumberOfTuples=\"1\" format=\"ascii\">{:.17g}</DataArray>\n",
                     floor, run.grading);
}

// Names as a VTK string array (ascii: each name's bytes, then 0), as vtkStringArray reads it;
// nothing for none. A multi-region mesh's region names (cell data `region` indexes them), a
// cracked solid's crack names.
std::string names_field_data(const char* field, const std::vector<std::string>& names) {
  if (names.empty()) return "";
  std::string bytes;
  for (const std::string& name : names) {
    for (unsigned char ch : name) bytes += fmt::format("{} ", int(ch));
    bytes += "0 ";
  }
  bytes.pop_back();
  return fmt::format("<DataArray type=\"String\" Name=\"{}\" NumberOfTuples=\"{}\" format=\"ascii\">{}</DataArray>\n",
                     field, names.size(), bytes);
}

std::string version_numbers(std::string v) {
  std::replace(v.begin(), v.end(), '.', ' ');
  return v;
}

// Streams index values cell by cell: cell c has count(c) values, written by fill(c, out).
// Cells go in batches; each batch is filled by all threads, then written in order, so the file
// is the same for any thread count and only one batch is held in memory.
template <class Index, class Count, class Fill>
void stream_cells(std::ostream& out, size_t n, Count count, Fill fill) {
  constexpr size_t kBatch = size_t(1) << 15;
  std::vector<int64_t> offsets;
  std::vector<Index> values;
  for (size_t b0 = 0; b0 < n; b0 += kBatch) {
    const size_t b1 = std::min(n, b0 + kBatch);
    offsets.assign(1, 0);
    for (size_t c = b0; c < b1; ++c) offsets.push_back(offsets.back() + int64_t(count(c)));
    values.resize(size_t(offsets.back()));
#pragma omp parallel for schedule(dynamic, 256)
    for (size_t c = b0; c < b1; ++c) fill(c, values.data() + offsets[c - b0]);
    out.write(reinterpret_cast<const char*>(values.data()), std::streamsize(values.size() * sizeof(Index)));
  }
}

// The Cells arrays (connectivity, offsets, types, faces, faceoffsets) with ids of type Index.
// `npts`: each cell's distinct point count; `connectivity` and `faces`: the two streams' lengths.
// The blocks are produced after this returns: the producers capture the mesh by reference and
// everything else by value.
template <class Index, class StreamLength>
std::string cell_arrays(AppendedBlocks& w, const PolyMesh& m, const std::vector<uint16_t>& npts, uint64_t connectivity,
                        uint64_t faces, StreamLength stream_length) {
  const size_t n = m.cell_count();
  std::string xml;
  xml += data_array(
      w, connectivity * sizeof(Index),
      [&m, &npts, n](std::ostream& out) {
        stream_cells<Index>(
            out, n, [&npts](size_t c) { return npts[c]; },
            [&m](size_t c, Index* dst) {
              thread_local std::vector<int32_t> pts;
              cell_points(m, c, pts);
              std::copy(pts.begin(), pts.end(), dst);
            });
      },
      index_type<Index>(), "connectivity");
  xml += end_offsets<Index>(w, n, [&npts](size_t c) { return int64_t(npts[c]); }, "offsets");
  xml += data_array(
      w, n,
      [n](std::ostream& out) {
        ValueWriter<uint8_t> vw(out);
        for (size_t c = 0; c < n; ++c) vw.put(kVtkPolyhedron);
      },
      "UInt8", "types");
  xml += data_array(
      w, faces * sizeof(Index),
      [&m, n, stream_length](std::ostream& out) {
        stream_cells<Index>(out, n, stream_length, [&m](size_t c, Index* dst) {
          *dst++ = Index(m.cell_face_begin[c + 1] - m.cell_face_begin[c]);
          for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) {
            *dst++ = Index(m.face_vertex_begin[f + 1] - m.face_vertex_begin[f]);
            for (int64_t k = m.face_vertex_begin[f]; k < m.face_vertex_begin[f + 1]; ++k) *dst++ = m.face_vertices[k];
          }
        });
      },
      index_type<Index>(), "faces");
  xml += end_offsets<Index>(w, n, stream_length, "faceoffsets");
  return xml;
}

}  // namespace

void write_vtu(const PolyMesh& m, const RunReport& run, const std::filesystem::path& path,
               const std::function<void(double)>& progress, bool compress) {
  const size_t n = m.cell_count();
  static_assert(sizeof(Vec3) == 3 * sizeof(double));
  // Sizes first (the XML header holds every block's offset), values streamed afterwards.
  std::vector<uint16_t> npts(n);
  uint64_t connectivity = 0;
#pragma omp parallel
  {
    std::vector<int32_t> pts;
#pragma omp for schedule(static) reduction(+ : connectivity)
    for (size_t c = 0; c < n; ++c) {
      cell_points(m, c, pts);
      npts[c] = uint16_t(pts.size());
      connectivity += pts.size();
    }
  }
  // faces: per cell its face count, then per face its size and vertex ids.
  const uint64_t faces = n + m.face_count() + m.face_vertices.size();
  const auto stream_length = [&m](size_t c) {
    const int64_t f0 = m.cell_face_begin[c], f1 = m.cell_face_begin[c + 1];
    return 1 + (f1 - f0) + (m.face_vertex_begin[f1] - m.face_vertex_begin[f0]);
  };

  AppendedBlocks w(compress);
  std::ostringstream xml;
  xml << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\""
      << (compress ? " compressor=\"vtkZLibDataCompressor\"" : "") << ">\n"
      << "<UnstructuredGrid>\n<FieldData>\n"
      << fmt::format("<DataArray type=\"Float64\" Name=\"r\" NumberOfTuples=\"1\" format=\"ascii\">{:.17g}</DataArray>\n", run.r)
      << fmt::format("<DataArray type=\"Float64\" Name=\"weld\" NumberOfTuples=\"1\" format=\"ascii\">{:.17g}</DataArray>\n", run.weld)
      << fmt::format("<DataArray type=\"UInt64\" Name=\"random_seed\" NumberOfTuples=\"1\" format=\"ascii\">{}</DataArray>\n", run.seed)
      // Numeric (major, minor, patch): meshio cannot read VTK string arrays.
      << fmt::format("<DataArray type=\"Int32\" Name=\"version\" NumberOfTuples=\"3\" format=\"ascii\">{}</DataArray>\n",
                     version_numbers(FROTH_VERSION))
      << grading_field_data(run)
      << names_field_data("region_names", m.region_names) << names_field_data("crack_names", m.crack_names)
      << "</FieldData>\n"
      << fmt::format("<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", m.points.size(), n)
      << "<Points>\n" << raw_array(w, m.points, "Float64", "Points", 3) << "</Points>\n<Cells>\n";
  // Point ids and offsets in 32 bits when every value fits (half the file); VTK and meshio
  // read either width.
  const bool narrow = std::max({uint64_t(m.points.size()), connectivity, faces}) <= uint64_t(INT32_MAX);
  xml << (narrow ? cell_arrays<int32_t>(w, m, npts, connectivity, faces, stream_length)
                 : cell_arrays<int64_t>(w, m, npts, connectivity, faces, stream_length));
  xml << "</Cells>\n<CellData>\n" << raw_array(w, m.seeds, "Float64", "seed", 3);
  // An Int32 cell array, value_of(c) per cell (kept by value: the block is produced when the
  // file is written, after this call returns).
  auto int_cell_array = [&](const char* name, auto value_of) {
    return data_array(
        w, n * 4,
        [&, value_of](std::ostream& out) {
          ValueWriter<int32_t> vw(out);
          for (size_t c = 0; c < n; ++c) vw.put(int32_t(value_of(c)));
        },
        "Int32", name);
  };
  xml << int_cell_array("kind", [&](size_t c) { return m.kinds[c]; });
  xml << raw_array(w, m.volumes, "Float64", "volume");
  xml << int_cell_array("piece", [&](size_t c) { return m.piece_of(c); });
  if (!m.region.empty()) xml << int_cell_array("region", [&](size_t c) { return m.region[c]; });
  if (!m.parent.empty()) xml << int_cell_array("parent", [&](size_t c) { return m.parent[c]; });
  xml << data_array(
      w, n * 24,
      [&](std::ostream& out) {
        ValueWriter<double> vw(out);
        for (size_t c = 0; c < n; ++c) {
          const Vec3 p = m.center_of(c);
          vw.put(p.x), vw.put(p.y), vw.put(p.z);
        }
      },
      "Float64", "center", 3);
  xml << int_cell_array("kernel", [&](size_t c) { return m.has_kernel(c) ? 1 : 0; });
  xml << data_array(
      w, n * 8,
      [&](std::ostream& out) {
        ValueWriter<double> vw(out);
        for (size_t c = 0; c < n; ++c) vw.put(m.radius_of(c, run.r));
      },
      "Float64", "radius");
  if (m.quality.size() == n) {
    // Quality metrics, streamed field by field from the per-cell records.
    auto field = [&](const char* name, double CellQuality::*member) {
      xml << data_array(
          w, n * 8,
          [&m, member](std::ostream& out) {
            ValueWriter<double> vw(out);
            for (const CellQuality& q : m.quality) vw.put(q.*member);
          },
          "Float64", name);
    };
    for (const auto& [name, member] : kQualityFields) field(name, member);
  }
  xml << "</CellData>\n"
      << "</Piece>\n</UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n_";
  write_atomically(path, [&](std::ostream& out) {
    out << xml.str();
    w.write(out, progress);
    out << "\n</AppendedData>\n</VTKFile>\n";
  });
}

void write_pvtu(const std::vector<std::string>& pieces, bool with_quality, bool with_regions,
                const std::filesystem::path& path) {
  std::ostringstream xml;
  xml << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      << "<PUnstructuredGrid GhostLevel=\"0\">\n"
      << "<PPoints>\n<PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n</PPoints>\n"
      << "<PCellData>\n<PDataArray type=\"Float64\" Name=\"seed\" NumberOfComponents=\"3\"/>\n"
      << "<PDataArray type=\"Int32\" Name=\"kind\"/>\n<PDataArray type=\"Float64\" Name=\"volume\"/>\n"
      << "<PDataArray type=\"Int32\" Name=\"piece\"/>\n"
      << (with_regions ? "<PDataArray type=\"Int32\" Name=\"region\"/>\n" : "")
      << "<PDataArray type=\"Float64\" Name=\"center\" NumberOfComponents=\"3\"/>\n"
      << "<PDataArray type=\"Float64\" Name=\"radius\"/>\n";
  if (with_quality)
    for (const auto& [name, member] : kQualityFields) xml << fmt::format("<PDataArray type=\"Float64\" Name=\"{}\"/>\n", name);
  xml << "</PCellData>\n";
  for (const std::string& p : pieces) xml << fmt::format("<Piece Source=\"{}\"/>\n", p);
  xml << "</PUnstructuredGrid>\n</VTKFile>\n";
  write_atomically(path, [&](std::ostream& out) { out << xml.str(); });
}

}  // namespace froth
