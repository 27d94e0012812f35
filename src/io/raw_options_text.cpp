#include "raw_options_text.h"

#include <charconv>
#include <cmath>
#include <system_error>

namespace snert {

namespace {

// Exactly the whole of `text` as one number (no sign games, no spaces, no trailing bytes).
template <class T> bool parse_number(const std::string& text, T& out) {
    T value{};
    const char* end = text.data() + text.size();
    const auto [stop, error] = std::from_chars(text.data(), end, value);
    if (text.empty() || error != std::errc() || stop != end) return false;
    out = value;
    return true;
}

template <class T> std::string parse_triple(const std::string& text, glm::vec<3, T>& out) {
    glm::vec<3, T> value{};
    std::size_t start = 0;
    for (int a = 0; a < 3; ++a) {
        const std::size_t comma = text.find(',', start);
        if ((a < 2) != (comma != std::string::npos))
            return "takes three comma-separated values X,Y,Z, got '" + text + "'";
        const std::string part = text.substr(start, a < 2 ? comma - start : std::string::npos);
        if (!parse_number(part, value[a]))
            return "'" + part + "' is not a number (in '" + text + "')";
        start = comma + 1;
    }
    out = value;
    return {};
}

std::string number_text(float v) {
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
    return std::string(buffer, result.ptr);
}

} // namespace

std::string parse_raw_dims(const std::string& text, glm::ivec3& dims) {
    glm::ivec3 value{0};
    if (std::string error = parse_triple(text, value); !error.empty()) return error;
    if (value.x < 1 || value.y < 1 || value.z < 1)
        return "every dimension must be at least 1, got '" + text + "'";
    dims = value;
    return {};
}

std::string parse_raw_spacing(const std::string& text, glm::vec3& spacing) {
    glm::vec3 value{0.0f};
    if (std::string error = parse_triple(text, value); !error.empty()) return error;
    for (int a = 0; a < 3; ++a)
        if (!(value[a] > 0.0f) || !std::isfinite(value[a]))
            return "every spacing must be a positive number, got '" + text + "'";
    spacing = value;
    return {};
}

std::string raw_dims_text(glm::ivec3 dims) {
    return std::to_string(dims.x) + "," + std::to_string(dims.y) + "," + std::to_string(dims.z);
}

std::string raw_spacing_text(glm::vec3 spacing) {
    return number_text(spacing.x) + "," + number_text(spacing.y) + "," + number_text(spacing.z);
}

} // namespace snert
