// The one error type for bad input: a volume, option or file that cannot give a result (too
// large a mesh for 32-bit indices, an empty surface, an unreadable file). The command line
// exits with code 2 for it (and 1 for anything else); the message is one line naming the input.
#pragma once

#include <stdexcept>

namespace snert {

struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

} // namespace snert
