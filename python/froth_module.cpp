// froth's Python module (_froth, wrapped by froth/__init__.py): domains, meshes whose arrays are
// numpy views of the C++ mesh (no copy), the writers, the VTU reader, and froth::Error raised as
// froth.Error subclasses that carry the command line's exit code.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "froth/froth.hpp"

namespace py = pybind11;

namespace {

// A mesh and the report of the run that made it (the writers put r, seed and weld in the files).
struct Mesh {
  froth::PolyMesh mesh;
  froth::RunReport run;
};

// A read-only numpy view of `count` records of `stride` bytes at `data`, kept alive by `owner`.
template <class T>
py::array view(const py::handle& owner, const void* data, size_t count, size_t stride, size_t components = 1) {
  std::vector<py::ssize_t> shape{py::ssize_t(count)}, strides{py::ssize_t(stride)};
  if (components > 1) shape.push_back(py::ssize_t(components)), strides.push_back(sizeof(T));
  py::array a(py::dtype::of<T>(), shape, strides, static_cast<const T*>(data), owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}
template <class T, class V>
py::array view_of(const py::handle& owner, const V& values) {
  return view<T>(owner, values.data(), values.size(), sizeof(typename V::value_type));
}
py::array vec3_view(const py::handle& owner, const froth::Vec3* data, size_t count) {
  return view<double>(owner, data, count, sizeof(froth::Vec3), 3);
}

// The options the caller gave; the library resolves the rest (froth::MeshOptions), so that the
// same options give the same mesh as `froth mesh`, byte for byte.
froth::MeshOptions mesh_options(double r, double cells, uint64_t seed, std::optional<double> weld, bool quality,
                                int threads, bool grade, std::optional<double> min_r, double max_grading,
                                std::optional<double> max_memory_gb, bool convex) {
  if (cells != 0 && !(cells > 0 && std::isfinite(cells)))
    froth::fail(froth::ErrorKind::Usage, "cells must be a positive number, got " + std::to_string(cells));
  froth::MeshOptions opt;
  opt.r = r;
  opt.cells = cells;
  opt.seed = seed;
  opt.weld = weld;
  opt.convex = convex;
  opt.threads = threads;
  opt.quality = quality;
  opt.grade = grade, opt.min_r = min_r.value_or(0), opt.grading = max_grading;
  opt.max_memory_bytes = max_memory_gb.value_or(0) * 1e9;
  return opt;
}

// Called without the GIL. Ctrl-C reaches Python's handler only when Python runs: the run asks,
// as each stage starts and as sampling and cells go, whether a signal is pending (its handler
// raises KeyboardInterrupt, which then stops the run and is raised to the caller).
Mesh make_mesh(const froth::Domain& domain, froth::MeshOptions opt) {
  opt.interrupted = [] {
    py::gil_scoped_acquire held;
    return PyErr_CheckSignals() != 0;
  };
  Mesh m;
  m.mesh = froth::generate_mesh(domain, opt, &m.run);
  return m;
}

froth::TriangleSurface surface_of(const py::array_t<double, py::array::c_style | py::array::forcecast>& vertices,
                                  const py::array_t<int64_t, py::array::c_style | py::array::forcecast>& triangles) {
  if (vertices.ndim() != 2 || vertices.shape(1) != 3)
    froth::fail(froth::ErrorKind::InvalidInput, "vertices must be an array of shape (n, 3)");
  if (triangles.ndim() != 2 || triangles.shape(1) != 3)
    froth::fail(froth::ErrorKind::InvalidInput, "triangles must be an array of shape (m, 3)");
  froth::TriangleSurface s;
  const auto v = vertices.unchecked<2>();
  for (py::ssize_t i = 0; i < v.shape(0); ++i) s.vertices.push_back({v(i, 0), v(i, 1), v(i, 2)});
  const auto t = triangles.unchecked<2>();
  for (py::ssize_t i = 0; i < t.shape(0); ++i) {
    std::array<int32_t, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      if (t(i, k) < 0 || t(i, k) >= v.shape(0))
        froth::fail(froth::ErrorKind::InvalidInput,
                    "triangle " + std::to_string(i) + " names vertex " + std::to_string(t(i, k)) + ", but there are " +
                        std::to_string(v.shape(0)) + " vertices (numbered from 0)");
      tri[k] = int32_t(t(i, k));
    }
    s.triangles.push_back(tri);
  }
  return s;
}

// froth.Error and one subclass per ErrorKind, each also a subclass of the builtin exception a
// Python user would catch for it; `exit_code` and `kind` are class attributes.
struct Exceptions {
  PyObject* base = nullptr;
  PyObject* by_kind[6] = {};
};
Exceptions& exceptions() {
  static Exceptions e;
  return e;
}

void add_exceptions(py::module_& m) {
  Exceptions& e = exceptions();
  e.base = PyErr_NewExceptionWithDoc("froth.Error", "A froth error: its message names the problem; exit_code is the command line's.",
                                     PyExc_Exception, nullptr);
  m.add_object("Error", py::handle(e.base));
  struct Kind {
    froth::ErrorKind kind;
    const char *name, *label;
    PyObject* builtin;
  };
  const Kind kinds[] = {{froth::ErrorKind::Usage, "UsageError", "usage", PyExc_ValueError},
                        {froth::ErrorKind::InvalidInput, "InvalidInputError", "invalid_input", PyExc_ValueError},
                        {froth::ErrorKind::Io, "IoError", "io", PyExc_OSError},
                        {froth::ErrorKind::Internal, "InternalError", "internal", PyExc_RuntimeError}};
  for (const Kind& k : kinds) {
    py::tuple bases = py::make_tuple(py::handle(e.base), py::handle(k.builtin));
    PyObject* cls = PyErr_NewException(("froth." + std::string(k.name)).c_str(), bases.ptr(), nullptr);
    py::handle(cls).attr("exit_code") = int(k.kind);
    py::handle(cls).attr("kind") = k.label;
    e.by_kind[int(k.kind)] = cls;
    m.add_object(k.name, py::handle(cls));
  }
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const froth::Error& err) {
      if (err.kind() == froth::ErrorKind::Interrupted) {  // the signal handler's exception is pending
        if (!PyErr_Occurred()) PyErr_SetNone(PyExc_KeyboardInterrupt);
        return;
      }
      PyErr_SetString(exceptions().by_kind[err.exit_code()], err.what());
    } catch (const std::filesystem::filesystem_error& err) {  // exit 4 on the command line
      PyErr_SetString(exceptions().by_kind[int(froth::ErrorKind::Io)], err.what());
    }
  });
}

// The cell data a VTU carries, as views where the mesh's layout allows (the quality metrics are
// strided views into the per-cell records); piece, center and radius are made when the mesh
// keeps them implicit (no split cell, a convex domain, an ungraded run).
py::dict cell_data(const py::object& self) {
  const Mesh& m = self.cast<const Mesh&>();
  const froth::PolyMesh& pm = m.mesh;
  const size_t n = pm.cell_count();
  py::dict d;
  d["seed"] = vec3_view(self, pm.seeds.data(), n);
  d["kind"] = view_of<uint8_t>(self, pm.kinds);
  d["volume"] = view_of<double>(self, pm.volumes);
  if (pm.piece.size() == n) d["piece"] = view_of<uint32_t>(self, pm.piece);
  else d["piece"] = py::module_::import("numpy").attr("zeros")(n, "uint32");
  if (pm.parent.size() == n) d["parent"] = view_of<uint32_t>(self, pm.parent);
  if (pm.region.size() == n) d["region"] = view_of<int32_t>(self, pm.region);
  if (pm.centers.size() == n) d["center"] = vec3_view(self, pm.centers.data(), n);
  else d["center"] = d["seed"];
  {
    py::array_t<uint8_t> kernel(static_cast<py::ssize_t>(n));
    auto k = kernel.mutable_unchecked<1>();
    for (size_t c = 0; c < n; ++c) k(py::ssize_t(c)) = pm.has_kernel(c);
    d["kernel"] = kernel;
  }
  if (pm.radii.size() == n) d["radius"] = view_of<double>(self, pm.radii);
  else {
    d["radius"] = py::module_::import("numpy").attr("full")(n, m.run.r);
  }
  if (pm.quality.size() == n) {
    const auto* q = pm.quality.data();
    const size_t stride = sizeof(froth::CellQuality);
    d["aspect"] = view<double>(self, &q->aspect, n, stride);
    d["outradius"] = view<double>(self, &q->outradius, n, stride);
    d["inradius"] = view<double>(self, &q->inradius, n, stride);
    d["min_dihedral"] = view<double>(self, &q->min_dihedral, n, stride);
    d["max_dihedral"] = view<double>(self, &q->max_dihedral, n, stride);
    d["min_edge"] = view<double>(self, &q->min_edge, n, stride);
  }
  return d;
}

}  // namespace

PYBIND11_MODULE(_froth, m) {
  m.doc() = "froth's native module; use the froth package (froth/__init__.py)";
  m.attr("version") = FROTH_VERSION;
  add_exceptions(m);

  py::class_<froth::Domain>(m, "Domain", "A solid to mesh: a box or the inside of a closed triangle surface")
      .def_readonly("description", &froth::Domain::description)
      .def_readonly("volume", &froth::Domain::volume)
      .def_readonly("surface_area", &froth::Domain::surface_area)
      .def_readonly("convex", &froth::Domain::convex)
      .def_readonly("shells", &froth::Domain::shells)
      .def_readonly("cavities", &froth::Domain::cavities)
      .def_property_readonly("triangles", [](const froth::Domain& d) { return d.surface.triangles.size(); })
      .def_property_readonly("bounds",
                             [](const froth::Domain& d) {
                               const froth::Box& b = d.bounds;
                               return py::make_tuple(py::make_tuple(b.lo.x, b.lo.y, b.lo.z),
                                                     py::make_tuple(b.hi.x, b.hi.y, b.hi.z));
                             })
      .def("__repr__", [](const froth::Domain& d) {
        return "<froth.Domain " + d.description + ": " + std::to_string(d.surface.triangles.size()) + " triangles>";
      });

  m.def(
      "load",
      [](const std::string& input, double feature_angle, bool repair) {
        py::gil_scoped_release unlocked;
        return froth::load_domain(input, {feature_angle, repair});
      },
      "A solid from a surface file (STL, OBJ, OFF, PLY) or 'box:X0,Y0,Z0,X1,Y1,Z1', validated as froth mesh "
      "validates it; feature_angle and repair as --feature-angle and --repair",
      py::arg("input"), py::arg("feature_angle") = froth::kDefaultFeatureAngle, py::arg("repair") = false);
  m.def(
      "load_regions",
      [](const std::vector<std::string>& inputs, double feature_angle, bool repair) {
        py::gil_scoped_release unlocked;
        return froth::load_regions(inputs, {feature_angle, repair});
      },
      "A multi-region solid: one region per closed surface file, sharing their interfaces",
      py::arg("inputs"), py::arg("feature_angle") = froth::kDefaultFeatureAngle, py::arg("repair") = false);
  m.def(
      "load_cracks",
      [](const froth::Domain& solid, const std::vector<std::string>& sheets) {
        py::gil_scoped_release unlocked;
        return froth::load_cracks(solid, sheets);
      },
      "The solid cut open along crack sheets (files), as froth mesh --crack: each sheet's faces twice in the mesh, "
      "on patches crack_NAME_a and crack_NAME_b",
      py::arg("solid"), py::arg("sheets"));
  m.def(
      "from_surface",
      [](const py::array_t<double, py::array::c_style | py::array::forcecast>& vertices,
         const py::array_t<int64_t, py::array::c_style | py::array::forcecast>& triangles, const std::string& name,
         double feature_angle, bool repair) {
        froth::TriangleSurface s = surface_of(vertices, triangles);
        py::gil_scoped_release unlocked;
        return froth::domain_anywhere(s, name, {feature_angle, repair});
      },
      "A solid from arrays: vertices (n, 3) and triangles (m, 3) of a closed surface, validated as a file is",
      py::arg("vertices"), py::arg("triangles"), py::arg("name") = "surface",
      py::arg("feature_angle") = froth::kDefaultFeatureAngle, py::arg("repair") = false);

  py::class_<Mesh>(m, "Mesh", py::dynamic_attr(), "A conforming polyhedral mesh; its arrays are read-only views, valid while it lives")
      .def_property_readonly("points", [](py::object self) {
        const auto& pm = self.cast<const Mesh&>().mesh;
        return vec3_view(self, pm.points.data(), pm.points.size());
      })
      .def_property_readonly("face_vertices",
                             [](py::object self) { return view_of<int32_t>(self, self.cast<const Mesh&>().mesh.face_vertices); })
      .def_property_readonly("face_offsets",
                             [](py::object self) { return view_of<int64_t>(self, self.cast<const Mesh&>().mesh.face_vertex_begin); })
      .def_property_readonly("cell_offsets",
                             [](py::object self) { return view_of<int64_t>(self, self.cast<const Mesh&>().mesh.cell_face_begin); })
      .def_property_readonly("face_generator",
                             [](py::object self) { return view_of<int32_t>(self, self.cast<const Mesh&>().mesh.face_generator); })
      .def_property_readonly("face_patch",
                             [](const Mesh& m) {
                               py::array_t<int32_t> out(py::ssize_t(m.mesh.face_count()));
                               for (size_t f = 0; f < m.mesh.face_count(); ++f)
                                 out.mutable_at(f) = froth::is_border_generator(m.mesh.face_generator[f]) ? m.mesh.patch_of(f) : -1;
                               return out;
                             })
      .def_property_readonly("patch_names", [](const Mesh& m) { return m.mesh.patch_names; })
      .def_property_readonly("region_names", [](const Mesh& m) { return m.mesh.region_names; })
      .def_property_readonly("crack_names", [](const Mesh& m) { return m.mesh.crack_names; })
      .def_property_readonly("cell_data", &cell_data)
      .def_property_readonly("r", [](const Mesh& m) { return m.run.r; })
      .def_property_readonly("seed", [](const Mesh& m) { return m.run.seed; })
      .def_property_readonly("weld", [](const Mesh& m) { return m.run.weld; })
      .def_property_readonly("cell_count", [](const Mesh& m) { return m.mesh.cell_count(); })
      .def_property_readonly("face_count", [](const Mesh& m) { return m.mesh.face_count(); })
      .def("__len__", [](const Mesh& m) { return m.mesh.cell_count(); }, "The number of cells")
      .def("report_json", [](const Mesh& m) { return froth::report_json_text(m.run); },
           "The run report as the JSON text froth mesh --report writes")
      .def(
          "write",
          [](const Mesh& m, const std::filesystem::path& path, bool compress) {
            py::gil_scoped_release unlocked;
            froth::write_mesh(m.mesh, m.run, path, {}, compress);
          },
          "Write the mesh; the format by the extension (.vtu, .exo/.e, a folder named polyMesh, .npz, .nodes), "
          "to a temporary name renamed on success",
          py::arg("path"), py::arg("compress") = false)
      .def(
          "write_report",
          [](const Mesh& m, const std::filesystem::path& path) {
            py::gil_scoped_release unlocked;
            froth::write_report_json(m.run, path);
          },
          "Write the run report (JSON)", py::arg("path"))
      .def(
          "write_boundary",
          [](const Mesh& m, const std::filesystem::path& path) {
            py::gil_scoped_release unlocked;
            froth::write_boundary_vtu(m.mesh, path);
          },
          "Write the boundary faces with their patches (VTU), as froth mesh --boundary", py::arg("path"));

  m.def(
      "mesh",
      [](const froth::Domain& domain, double r, double cells, uint64_t seed, std::optional<double> weld, bool quality,
         int threads, bool grade, std::optional<double> min_r, double max_grading, std::optional<double> max_memory_gb,
         bool convex) {
        py::gil_scoped_release unlocked;
        const froth::MeshOptions opt =
            mesh_options(r, cells, seed, weld, quality, threads, grade, min_r, max_grading, max_memory_gb, convex);
        return make_mesh(domain, opt);
      },
      "Mesh a Domain (froth.mesh is the documented entry; this takes r = 0 or cells = 0 for 'not given')",
      py::arg("domain"), py::arg("r") = 0.0, py::arg("cells") = 0.0, py::arg("seed") = 0, py::arg("weld") = py::none(),
      py::arg("quality") = true, py::arg("threads") = 0, py::arg("grade") = false, py::arg("min_r") = py::none(),
      py::arg("max_grading") = 0.2, py::arg("max_memory") = py::none(), py::arg("convex") = false);
  m.def(
      "read",
      [](const std::filesystem::path& path) {
        py::gil_scoped_release unlocked;
        Mesh m;
        m.mesh = froth::read_vtu(path, &m.run);  // with what the VTU's field data keep, as froth convert does
        return m;
      },
      "A mesh read back from a froth VTU (cell data and field data as written)", py::arg("path"));
  m.def("member_seed", &froth::member_seed, "The seed of ensemble member k of an ensemble with this seed",
        py::arg("seed"), py::arg("k"));
}
