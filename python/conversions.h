/// @brief Python values the bindings take, made into the engine's types.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace cvc_python {

/// Three numbers (a tuple, list or array) as a vector; `name` names the argument in the error.
inline glm::dvec3 vec3Of(const pybind11::object& value, const char* name) {
    const auto numbers = value.cast<std::vector<double>>();
    if (numbers.size() != 3) throw std::invalid_argument(std::string(name) + " must hold three numbers");
    return {numbers[0], numbers[1], numbers[2]};
}

}  // namespace cvc_python
