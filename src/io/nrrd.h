// NRRD (.nrrd / .nhdr): the header and the size check run before ITK reads the file (no ITK
// here).
//
// ITK 5.2 allocates what `sizes` claims before reading, and reports absurd sizes in its
// parser's words; so the header is parsed here and the data it promises (attached after the
// blank line, or in a detached data file; raw or gzip) is checked against the file first.
//
// The parser takes a byte range and never reads outside it (tests/fuzz feeds it arbitrary
// bytes); every failure is a std::runtime_error whose message starts with `name`, one line.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sample_conversion.h"

namespace snert::detail {

struct NrrdHeader {
    std::vector<std::uint64_t> sizes;
    std::string type_name;          // as written, e.g. "short"
    std::optional<ScalarType> type; // empty for "block" and unknown names
    std::string encoding = "raw";   // lower case: raw, gzip, gz, ascii, text, txt, hex, bzip2 ...
    std::string data_file;          // empty: attached data after the blank line
    std::int64_t line_skip = 0, byte_skip = 0; // byte_skip -1: raw data ends the file
    std::uint64_t data_offset = 0;             // attached data: first byte after the blank line

    std::uint64_t data_bytes() const; // bytes promised (0: overflow or unknown type)
};
// Parses a NRRD header (magic "NRRD000N", "field: value" lines up to a blank line). Returns
// empty when the magic is missing. Throws std::runtime_error for a malformed sizes, dimension
// or skip field.
std::optional<NrrdHeader> parse_nrrd_header(const std::uint8_t* bytes, std::size_t size,
                                            const std::string& name);

// Checks a NRRD file on disk, in this order: an unsupported type is refused, then absurd
// dimensions (checked_dims), memory (check_memory with `memory_limit`, 0: available), then the
// data the header promises: std::runtime_error "<path>: truncated NRRD: the header promises N
// bytes, <file> holds M" when it is short (gzip: what it inflates to). Slice lists, file name
// patterns, line skips and encodings other than raw and gzip pass to ITK unchecked.
void check_nrrd_data(const std::string& path, std::uint64_t memory_limit);

} // namespace snert::detail
