// cvc.load and cvc.Volume: volumes in and out of numpy, (z, y, x) order, int16 Hounsfield units.
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "python/bindings.h"
#include "python/conversions.h"
#include "python/gpu_session.h"
#include "volumes/brick_minmax.h"
#include "volumes/load_volume.h"

namespace py = pybind11;

namespace cvc_python {
namespace {

/// A volume from a (z, y, x) array: int16 taken as HU; float32 rounded to the nearest HU, which
/// must be finite and within int16. The engine keeps its own int16 copy (its textures are made
/// from it), so the array is copied once, never referenced.
std::shared_ptr<SessionVolume> volumeFromArray(const py::array& array, const py::object& spacing, const py::object& origin,
                                               const py::object& direction) {
    if (array.ndim() != 3) throw std::invalid_argument("Volume: the array must be 3-D, (z, y, x), not " + std::to_string(array.ndim()) + "-D");
    volumes::LoadedVolume loaded;
    volumes::Volume& volume = loaded.volume;
    volume.dims = {static_cast<int>(array.shape(2)), static_cast<int>(array.shape(1)), static_cast<int>(array.shape(0))};
    volume.spacingMm = vec3Of(spacing, "spacing_mm");
    if (!origin.is_none()) volume.originLps = vec3Of(origin, "origin_mm");
    if (!direction.is_none()) {
        const auto rows = direction.cast<std::vector<std::vector<double>>>();
        if (rows.size() != 3 || rows[0].size() != 3 || rows[1].size() != 3 || rows[2].size() != 3) {
            throw std::invalid_argument("direction must be 3x3: its columns are the x, y and z axes in LPS");
        }
        for (int row = 0; row < 3; ++row) {
            for (int column = 0; column < 3; ++column) volume.directionLps[column][row] = rows[static_cast<std::size_t>(row)][static_cast<std::size_t>(column)];
        }
    }
    volumes::validateGeometry(volume, "Volume");  // before the copy: absurd sizes never allocate
    volume.hu.resize(volume.voxelCount());
    if (py::isinstance<py::array_t<int16_t>>(array)) {
        const auto voxels = py::array_t<int16_t, py::array::c_style | py::array::forcecast>::ensure(array);
        std::copy_n(voxels.data(), volume.hu.size(), volume.hu.begin());
    } else if (py::isinstance<py::array_t<float>>(array)) {
        const auto voxels = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(array);
        const float* values = voxels.data();
        for (std::size_t n = 0; n < volume.hu.size(); ++n) {
            const float hu = values[n];
            if (!std::isfinite(hu) || hu < std::numeric_limits<int16_t>::min() || hu > std::numeric_limits<int16_t>::max()) {
                throw std::invalid_argument("Volume: voxel " + std::to_string(n) + " is " + std::to_string(hu) +
                                            ", not a finite HU value within int16");
            }
            volume.hu[n] = static_cast<int16_t>(std::lround(hu));
        }
    } else {
        throw std::invalid_argument("Volume: the array must be int16 or float32 HU, not " +
                                    py::str(array.dtype()).cast<std::string>());
    }
    volumes::validateVolume(volume, "Volume");
    loaded.bricks = volumes::buildBrickMinMax(volume);
    return std::make_shared<SessionVolume>(std::move(loaded), "(numpy array)");
}

glm::dvec3 column(const glm::dmat3& matrix, int index) { return matrix[index]; }

}  // namespace

void addVolumeBindings(py::module_& module) {
    py::class_<SessionVolume, std::shared_ptr<SessionVolume>>(module, "Volume",
        "A CT volume in Hounsfield units. Voxel [z, y, x] of `array` is at volume millimetres "
        "(x, y, z) * spacing_mm; the patient frame (LPS) is origin_mm + direction @ that.")
        .def(py::init(&volumeFromArray), py::arg("array"), py::arg("spacing_mm"), py::arg("origin_mm") = py::none(),
             py::arg("direction") = py::none(),
             "From a (z, y, x) numpy array of int16 or float32 HU (copied once into the engine's int16).")
        .def_property_readonly("array", [](py::object self) {
            const SessionVolume& wrapped = self.cast<const SessionVolume&>();
            const volumes::Volume& volume = wrapped.volume();
            const std::vector<py::ssize_t> shape = {volume.dims[2], volume.dims[1], volume.dims[0]};
            py::array_t<int16_t> view(shape, volume.hu.data(), self);  // no copy: the volume owns the voxels
            view.attr("setflags")(py::arg("write") = false);
            return view;
        }, "The voxels, (z, y, x) int16 HU: a read-only view, no copy")
        .def_property_readonly("spacing_mm", [](const SessionVolume& v) {
            const glm::dvec3 s = v.volume().spacingMm;
            return py::make_tuple(s.x, s.y, s.z);
        })
        .def_property_readonly("origin_mm", [](const SessionVolume& v) {
            const glm::dvec3 o = v.volume().originLps;
            return py::make_tuple(o.x, o.y, o.z);
        })
        .def_property_readonly("direction", [](const SessionVolume& v) {
            const glm::dmat3& d = v.volume().directionLps;
            py::list rows;
            for (int row = 0; row < 3; ++row) rows.append(py::make_tuple(column(d, 0)[row], column(d, 1)[row], column(d, 2)[row]));
            return rows;
        })
        .def_property_readonly("shape", [](const SessionVolume& v) {
            const auto& d = v.volume().dims;
            return py::make_tuple(d[2], d[1], d[0]);
        })
        .def_property_readonly("source", &SessionVolume::source)
        .def("__repr__", [](const SessionVolume& v) {
            const auto& d = v.volume().dims;
            return "<cvc.Volume " + std::to_string(d[0]) + "x" + std::to_string(d[1]) + "x" + std::to_string(d[2]) +
                   " from " + v.source() + ">";
        });

    module.def("load", [](const std::string& path, const std::string& raw) {
        volumes::LoadOptions options;
        if (!raw.empty()) options.raw = volumes::parseRawSpec(raw);
        volumes::LoadedVolume loaded;
        {
            py::gil_scoped_release release;
            loaded = volumes::loadVolumeWithBricks(path, options);
        }
        return std::make_shared<SessionVolume>(std::move(loaded), path);
    }, py::arg("path"), py::arg("raw") = "",
       "A volume from a DICOM folder, .nrrd/.nhdr, .nii/.nii.gz, .mha/.mhd, .vdb, or a raw file described by `raw`");
}

}  // namespace cvc_python
