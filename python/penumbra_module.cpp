// The Python module `penumbra._penumbra` (pybind11) over the library's API: frames come back as
// NumPy arrays that own the rendered buffers (no copy after the read-back), and rendering releases
// the GIL. python/penumbra/__init__.py gives it its Pythonic face.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <vector>

#include "penumbra/penumbra.h"

namespace py = pybind11;
using penumbra::api::Error;
using penumbra::api::Frame;
using penumbra::api::Options;
using penumbra::api::Renderer;
using penumbra::api::Scene;

namespace {

// `values` moved into a NumPy array of `shape` that owns them.
template <class T>
py::array_t<T> owned(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
  auto* heap = new std::vector<T>(std::move(values));
  py::capsule release(heap, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(shape, heap->data(), release);
}

py::dict toDict(Frame&& f) {
  const py::ssize_t h = f.height, w = f.width;
  py::dict d;
  d["width"] = f.width;
  d["height"] = f.height;
  d["visibility"] = owned(std::move(f.visibility), {h, w});
  d["image"] = owned(std::move(f.rgba), {h, w, 4});
  d["covered"] = owned(std::move(f.covered), {h, w});
  d["pip"] = f.pip.empty() ? py::object(py::none()) : py::object(owned(std::move(f.pip), {h, w}));
  d["stats"] = f.stats;
  return d;
}

}  // namespace

PYBIND11_MODULE(_penumbra, m) {
  m.doc() = "Penumbra's renderer (the C++ library penumbra/penumbra.h)";
  py::register_exception<Error>(m, "Error", PyExc_ValueError);
  py::class_<Scene>(m, "Scene")
      .def(py::init<const std::string&>(), py::arg("spec"), py::call_guard<py::gil_scoped_release>())
      .def_property_readonly("spec", &Scene::spec)
      .def_property_readonly("triangles", &Scene::triangles);
  py::class_<Renderer>(m, "Renderer")
      .def(py::init<const Scene&, const Options&>(), py::arg("scene"), py::arg("options"),
           py::call_guard<py::gil_scoped_release>(), py::keep_alive<1, 2>())
      .def("render",
           [](Renderer& r, const std::string& method) {
             Frame f;
             {
               py::gil_scoped_release released;
               f = r.render(method);
             }
             return toDict(std::move(f));
           })
      .def("compare", &Renderer::compare, py::call_guard<py::gil_scoped_release>())
      .def_property("camera", &Renderer::camera, &Renderer::setCamera)
      .def_property("light", &Renderer::light, &Renderer::setLight)
      .def("settings", &Renderer::settings);
}
