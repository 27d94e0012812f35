// Sizes and memory: the dimensions a header states, the memory the grid needs and what the
// machine (and its cgroup) has available, and the messages that refuse a file.
#include "sizes.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <unistd.h>

namespace snert::detail {

glm::ivec3 checked_dims(const std::string& name, std::uint64_t x, std::uint64_t y,
                        std::uint64_t z) {
    const std::uint64_t axes[3] = {x, y, z};
    const std::string text =
        std::to_string(x) + " x " + std::to_string(y) + " x " + std::to_string(z);
    for (std::uint64_t n : axes)
        if (n < 1 || n > max_axis_extent)
            throw std::runtime_error(name + ": absurd dimensions " + text +
                                     " (each axis must hold 1 to " +
                                     std::to_string(max_axis_extent) + " samples)");
    std::uint64_t bytes = sizeof(float);
    for (std::uint64_t n : axes)
        if (__builtin_mul_overflow(bytes, n, &bytes) ||
            bytes > std::numeric_limits<std::size_t>::max() / 2)
            throw std::runtime_error(name + ": absurd dimensions " + text +
                                     " (the sample count overflows)");
    return {int(x), int(y), int(z)};
}

std::uint64_t parse_meminfo_available(const std::string& meminfo) {
    std::istringstream lines(meminfo);
    std::string line;
    while (std::getline(lines, line)) {
        if (line.rfind("MemAvailable:", 0) != 0) continue;
        std::istringstream fields(line.substr(13));
        std::uint64_t kib = 0;
        std::string unit;
        if (!(fields >> kib >> unit) || unit != "kB") return 0;
        if (kib > std::numeric_limits<std::uint64_t>::max() / 1024) return 0;
        return kib * 1024;
    }
    return 0;
}

namespace {
std::string read_small_text(const char* path) {
    std::ifstream in(path);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// Room left under a cgroup v2 memory limit ("max" or absent: no limit).
std::uint64_t cgroup_room() {
    const std::string max_text = read_small_text("/sys/fs/cgroup/memory.max");
    const std::string current_text = read_small_text("/sys/fs/cgroup/memory.current");
    if (max_text.empty() || max_text.rfind("max", 0) == 0 || current_text.empty())
        return std::numeric_limits<std::uint64_t>::max();
    try {
        const std::uint64_t max = std::stoull(max_text), current = std::stoull(current_text);
        return max > current ? max - current : 0;
    } catch (const std::exception&) {
        return std::numeric_limits<std::uint64_t>::max();
    }
}
} // namespace

std::uint64_t available_memory_bytes() {
    std::uint64_t bytes = parse_meminfo_available(read_small_text("/proc/meminfo"));
    if (bytes == 0) {
        const long pages = sysconf(_SC_AVPHYS_PAGES), page = sysconf(_SC_PAGESIZE);
        if (pages > 0 && page > 0) bytes = std::uint64_t(pages) * std::uint64_t(page);
    }
    return std::min(bytes, cgroup_room());
}

std::string format_bytes(std::uint64_t bytes) {
    const char* units[] = {"KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    if (bytes < 1024) return std::to_string(bytes) + " bytes";
    double value = double(bytes) / 1024.0;
    int unit = 0;
    while (value >= 1024.0 && unit < 5) {
        value /= 1024.0;
        ++unit;
    }
    char text[64];
    std::snprintf(text, sizeof text, "%.1f %s", value, units[unit]);
    return text;
}

void check_memory(const std::string& name, glm::ivec3 dims, std::uint64_t extra_bytes,
                  std::uint64_t limit_bytes) {
    const std::uint64_t grid =
        std::uint64_t(dims.x) * std::uint64_t(dims.y) * std::uint64_t(dims.z) * sizeof(float);
    std::uint64_t need = 0;
    if (__builtin_add_overflow(grid, extra_bytes, &need))
        need = std::numeric_limits<std::uint64_t>::max();
    const bool explicit_limit = limit_bytes != 0;
    const std::uint64_t limit = explicit_limit ? limit_bytes : available_memory_bytes();
    if (limit == 0 || need <= limit) return;
    std::string message = name + ": " + std::to_string(dims.x) + " x " + std::to_string(dims.y) +
                          " x " + std::to_string(dims.z) + " samples need " + format_bytes(grid) +
                          " as float32";
    if (extra_bytes) message += " plus " + format_bytes(extra_bytes) + " while reading";
    message += explicit_limit ? ", above the memory limit of " + format_bytes(limit)
                              : ", but only " + format_bytes(limit) + " of memory is available";
    throw std::runtime_error(message);
}

std::uint64_t checked_product(const std::vector<std::uint64_t>& factors) {
    std::uint64_t product = 1;
    for (std::uint64_t f : factors)
        if (__builtin_mul_overflow(product, f, &product)) return 0;
    return product;
}

// Absurd dimensions, then memory, for a header's axes (extra axes fold into z).
void check_grid(const std::string& path, const std::vector<std::uint64_t>& axes,
                std::uint64_t memory_limit) {
    std::uint64_t d[3] = {1, 1, 1};
    for (std::size_t a = 0; a < axes.size(); ++a) {
        if (a < 3) {
            d[a] = axes[a];
        } else if (__builtin_mul_overflow(d[2], axes[a], &d[2])) {
            d[2] = std::numeric_limits<std::uint64_t>::max();
        }
    }
    check_memory(path, checked_dims(path, d[0], d[1], d[2]), 0, memory_limit);
}

[[noreturn]] void throw_short(const std::string& path, const std::string& what, std::uint64_t need,
                              const std::string& data_path, std::uint64_t have) {
    throw std::runtime_error(path + ": truncated " + what + ": the header promises " +
                             std::to_string(need) + " bytes of samples, " +
                             (data_path == path ? std::string("the file") : data_path) + " holds " +
                             std::to_string(have));
}

} // namespace snert::detail
