// The errors corebox throws, shared by its public API and its internals. Each is a std::runtime_error
// whose what() is a message a user can act on; each maps to one exit code of `corebox run` and one
// error code of the C API (corebox_c.h): InputError 2 (a bad definition, scene, file, id or value),
// InstabilityError 3 (a blow-up: non-finite values, a particle outside the box, a runaway energy),
// DeviceError 4 (a GPU missing or failing).
#pragma once

#include <stdexcept>

#include "corebox/export.h"

namespace corebox {

class COREBOX_API InputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class COREBOX_API InstabilityError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class COREBOX_API DeviceError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace corebox
