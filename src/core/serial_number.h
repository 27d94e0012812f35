// Process-wide serial numbers, for tagging what a thread keeps between calls.
#pragma once

#include <atomic>
#include <cstdint>

namespace snert {

// A number no earlier call returned (never 0): a thread's kept state tagged with the serial of the
// object it was filled for is never read for another, even one later allocated at the same address.
inline std::uint64_t next_serial_number() {
    static std::atomic<std::uint64_t> last{0};
    return ++last;
}

} // namespace snert
