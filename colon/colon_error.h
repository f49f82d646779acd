/// @brief The one error type of the colon analysis: bad input for it (no air-filled colon, a
/// volume of air only, settings out of range). The message says what was found and what was
/// expected; `cvc` prints it on one line.
#pragma once

#include <stdexcept>

namespace colon {

class ColonError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace colon
