// The Python module `cvc`: conformal-vc's loaders, ray caster, display renders, colon analysis
// and studies on numpy arrays (docs/python.md). Errors come as Python exceptions with the one-line
// messages `cvc` prints: ValueError for a bad argument (std::invalid_argument), RuntimeError for
// bad data or a failed device (std::runtime_error, volumes::VolumeError).
#include "python/bindings.h"

PYBIND11_MODULE(cvc, module) {
    module.doc() = "conformal-vc: CT volumes, the Vulkan ray caster, immersive displays and the colon analysis";
    cvc_python::addVolumeBindings(module);
    cvc_python::addRenderBindings(module);
    cvc_python::addColonBindings(module);
    cvc_python::addStudyBindings(module);
}
