/// @brief The parts of the Python module `cvc`, each registered by its own file: volumes
/// (load, Volume from numpy), rendering (a pinhole view, a display's walls) and the colon
/// analysis, and the studies (polyp check, coverage).
#pragma once

#include <pybind11/pybind11.h>

namespace cvc_python {

void addVolumeBindings(pybind11::module_& module);
void addRenderBindings(pybind11::module_& module);
void addColonBindings(pybind11::module_& module);
void addStudyBindings(pybind11::module_& module);

}  // namespace cvc_python
