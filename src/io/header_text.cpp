// Text of the key / value headers: trimmed, lower-cased, split, and whole numbers.
#include "header_text.h"

#include <cctype>
#include <cstring>
#include <limits>
#include <sstream>

namespace snert::detail {

std::string trim(const std::string& s) {
    std::size_t b = 0, e = s.size();
    while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
    while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
    return s.substr(b, e - b);
}

std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

// A whole unsigned decimal number (no sign, no trailing text), or empty.
std::optional<std::uint64_t> parse_count(const std::string& text) {
    if (text.empty() || text.size() > 19) return std::nullopt;
    std::uint64_t value = 0;
    for (char c : text) {
        if (!std::isdigit(static_cast<unsigned char>(c))) return std::nullopt;
        value = value * 10 + std::uint64_t(c - '0');
    }
    return value;
}

std::optional<std::int64_t> parse_signed(const std::string& text) {
    if (!text.empty() && text[0] == '-') {
        auto v = parse_count(text.substr(1));
        if (!v || *v > std::uint64_t(std::numeric_limits<std::int64_t>::max())) return std::nullopt;
        return -std::int64_t(*v);
    }
    auto v = parse_count(text);
    if (!v || *v > std::uint64_t(std::numeric_limits<std::int64_t>::max())) return std::nullopt;
    return std::int64_t(*v);
}

std::vector<std::string> words(const std::string& text) {
    std::istringstream in(text);
    std::vector<std::string> out;
    std::string w;
    while (in >> w) out.push_back(w);
    return out;
}

std::optional<std::string> LineReader::next() {
    if (pos_ >= size_) return std::nullopt;
    const auto* start = bytes_ + pos_;
    const auto* nl = static_cast<const std::uint8_t*>(std::memchr(start, '\n', size_ - pos_));
    const std::size_t len = nl ? std::size_t(nl - start) : size_ - pos_;
    pos_ += len + (nl ? 1 : 0);
    std::string line(reinterpret_cast<const char*>(start), len);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return line;
}

} // namespace snert::detail
