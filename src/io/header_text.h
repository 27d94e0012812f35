// Text of the key / value headers (MetaImage, NRRD, VTK legacy): lines, words and whole
// numbers, read without locale and without ever reading outside the bytes given.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace snert::detail {

std::string trim(const std::string& s);               // without leading and trailing space
std::string lower(std::string s);                     // ASCII lower case
std::vector<std::string> words(const std::string& s); // whitespace-separated
// A whole unsigned decimal number (no sign, no trailing text, at most 19 digits), or empty.
std::optional<std::uint64_t> parse_count(const std::string& text);
// parse_count with an optional leading '-'; empty outside the int64 range.
std::optional<std::int64_t> parse_signed(const std::string& text);

// Reads lines of a byte range, remembering where the next line starts.
class LineReader {
  public:
    LineReader(const std::uint8_t* bytes, std::size_t size) : bytes_(bytes), size_(size) {}
    // The next line without its "\n" or "\r\n"; empty at the end of the bytes.
    std::optional<std::string> next();
    // Offset of the first byte not yet read (the data after a header's last line).
    std::size_t position() const { return pos_; }

  private:
    const std::uint8_t* bytes_;
    std::size_t size_, pos_ = 0;
};

} // namespace snert::detail
