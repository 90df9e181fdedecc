// A vehicle's link key on disk (docs/security.md): one line of 32 hexadecimal digits, the 128-bit
// key, kept outside the repository (mode 0600). The vehicle gets it at flashing time, the ground
// station and the HIL processes read it from the file named on their command lines.
#pragma once

#include <string>

#include "pa/link_auth.hpp"

namespace pa::auth {

// False with "path: message" when the file cannot be read, does not hold exactly 32 hex digits
// (surrounding white space aside), or holds a key that is no key (all zeros or all ones).
bool read_key_file(const std::string& path, Key& key, std::string& error);

}  // namespace pa::auth
