// MetaImage (.mha / .mhd): the header and the size check run before ITK reads the file (no
// ITK here).
//
// ITK 5.2 allocates what DimSize claims and zero-fills data that is missing, so the header is
// parsed here and the data it promises (in the same file after the header, or in
// ElementDataFile) is checked against the file first.
//
// The parser never reads outside the text given (tests/fuzz feeds it arbitrary bytes); every
// failure is a std::runtime_error whose message starts with `name` (the file), one line.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sample_conversion.h"

namespace snert::detail {

struct MetaHeader {
    std::vector<std::uint64_t> dims;
    std::string element_type; // e.g. "MET_SHORT"
    std::optional<ScalarType> type;
    std::uint64_t channels = 1;
    bool binary = true; // BinaryData (ASCII data is not size-checked)
    bool compressed = false;
    std::optional<std::uint64_t> compressed_size;
    std::int64_t header_size = 0;   // HeaderSize; -1: data is at the end of the file
    std::string data_file;          // ElementDataFile value; "LOCAL": after the header
    std::uint64_t local_offset = 0; // for LOCAL: first byte after the ElementDataFile line

    std::uint64_t data_bytes() const; // uncompressed bytes the header promises (0: overflow)
};
// Parses "Key = Value" lines up to and including ElementDataFile. Throws std::runtime_error
// when ElementDataFile, NDims or DimSize is missing or malformed.
MetaHeader parse_metaimage_header(const std::string& text, const std::string& name);

// Checks a MetaImage file on disk, in this order: absurd dimensions (checked_dims), memory
// (check_memory with `memory_limit`, 0: available), then the data the header promises:
// std::runtime_error "<path>: truncated MetaImage: the header promises N bytes, <file> holds
// M" when it is short (for compressed data: what it inflates to, and CompressedDataSize). An
// unsupported ElementType is refused. ASCII data and slice lists pass to ITK unchecked.
void check_metaimage_data(const std::string& path, std::uint64_t memory_limit);

} // namespace snert::detail
