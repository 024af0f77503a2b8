// The checks every outline passes before it is built (leaf2d_io.cpp), private to model/.
#pragma once
#include <string>

#include "leafdig/model/leaf2d/leaf2d.hpp"

namespace leafdig::model::detail {

// At least 8 and at most a million finite points within the bounds of limits.hpp, an area,
// a margin that does not cross itself, a base and tip on it. Throws InputError naming `source`.
void checkOutline(const Outline2d& outline, const std::string& source);

}  // namespace leafdig::model::detail
