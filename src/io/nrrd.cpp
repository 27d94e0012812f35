// NRRD headers and the size check of the data they promise.
//
// This work is based on the NRRD format definition (teem, "NRRD: Nearly Raw Raster Data",
// format version 4 and earlier): a magic line, "field: value" lines, a blank line, then the
// attached data, or detached data in another file.
#include "nrrd.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "file_bytes.h"
#include "gzip.h"
#include "header_text.h"
#include "sizes.h"

namespace snert::detail {

namespace {

std::optional<ScalarType> nrrd_type(const std::string& name) {
    static const std::pair<const char*, ScalarType> table[] = {
        {"signed char", ScalarType::Int8},
        {"int8", ScalarType::Int8},
        {"int8_t", ScalarType::Int8},
        {"uchar", ScalarType::UInt8},
        {"unsigned char", ScalarType::UInt8},
        {"uint8", ScalarType::UInt8},
        {"uint8_t", ScalarType::UInt8},
        {"short", ScalarType::Int16},
        {"short int", ScalarType::Int16},
        {"signed short", ScalarType::Int16},
        {"signed short int", ScalarType::Int16},
        {"int16", ScalarType::Int16},
        {"int16_t", ScalarType::Int16},
        {"ushort", ScalarType::UInt16},
        {"unsigned short", ScalarType::UInt16},
        {"unsigned short int", ScalarType::UInt16},
        {"uint16", ScalarType::UInt16},
        {"uint16_t", ScalarType::UInt16},
        {"int", ScalarType::Int32},
        {"signed int", ScalarType::Int32},
        {"int32", ScalarType::Int32},
        {"int32_t", ScalarType::Int32},
        {"uint", ScalarType::UInt32},
        {"unsigned int", ScalarType::UInt32},
        {"uint32", ScalarType::UInt32},
        {"uint32_t", ScalarType::UInt32},
        {"longlong", ScalarType::Int64},
        {"long long", ScalarType::Int64},
        {"long long int", ScalarType::Int64},
        {"signed long long", ScalarType::Int64},
        {"signed long long int", ScalarType::Int64},
        {"int64", ScalarType::Int64},
        {"int64_t", ScalarType::Int64},
        {"ulonglong", ScalarType::UInt64},
        {"unsigned long long", ScalarType::UInt64},
        {"unsigned long long int", ScalarType::UInt64},
        {"uint64", ScalarType::UInt64},
        {"uint64_t", ScalarType::UInt64},
        {"float", ScalarType::Float32},
        {"double", ScalarType::Float64},
    };
    const std::string key = lower(name);
    for (const auto& [n, t] : table)
        if (key == n) return t;
    return std::nullopt;
}

} // namespace

std::uint64_t NrrdHeader::data_bytes() const {
    if (!type) return 0;
    std::vector<std::uint64_t> factors = sizes;
    factors.push_back(scalar_type_size(*type));
    return checked_product(factors);
}

std::optional<NrrdHeader> parse_nrrd_header(const std::uint8_t* bytes, std::size_t size,
                                            const std::string& name) {
    LineReader lines(bytes, size);
    auto magic = lines.next();
    if (!magic || magic->size() < 8 || magic->rfind("NRRD000", 0) != 0) return std::nullopt;
    NrrdHeader h;
    std::optional<std::uint64_t> dimension;
    while (auto line = lines.next()) {
        if (line->empty()) break; // end of the header; attached data follows
        if ((*line)[0] == '#' || line->find(":=") != std::string::npos) continue;
        const std::size_t colon = line->find(": ");
        if (colon == std::string::npos) continue;
        const std::string key = lower(trim(line->substr(0, colon)));
        const std::string value = trim(line->substr(colon + 2));
        const auto bad = [&] {
            return std::runtime_error(name + ": bad NRRD header: " + key + ": " + value);
        };
        if (key == "type") {
            h.type_name = value;
            h.type = nrrd_type(value);
        } else if (key == "dimension") {
            dimension = parse_count(value);
            if (!dimension || *dimension < 1 || *dimension > 16) throw bad();
        } else if (key == "sizes") {
            h.sizes.clear();
            for (const auto& w : words(value)) {
                auto n = parse_count(w);
                if (!n) throw bad();
                h.sizes.push_back(*n);
            }
        } else if (key == "encoding") {
            h.encoding = lower(value);
        } else if (key == "data file" || key == "datafile") {
            h.data_file = value;
        } else if (key == "line skip" || key == "lineskip") {
            auto n = parse_signed(value);
            if (!n || *n < 0) throw bad();
            h.line_skip = *n;
        } else if (key == "byte skip" || key == "byteskip") {
            auto n = parse_signed(value);
            if (!n || *n < -1) throw bad();
            h.byte_skip = *n;
        }
    }
    h.data_offset = lines.position();
    if (dimension && h.sizes.size() != *dimension)
        throw std::runtime_error(name + ": bad NRRD header: " + std::to_string(h.sizes.size()) +
                                 " sizes for dimension " + std::to_string(*dimension));
    if (h.sizes.empty()) throw std::runtime_error(name + ": bad NRRD header: no sizes field");
    return h;
}

void check_nrrd_data(const std::string& path, std::uint64_t memory_limit) {
    const auto prefix = read_file_prefix(path, 1 << 20);
    const auto h = parse_nrrd_header(prefix.data(), prefix.size(), path);
    if (!h) return;
    if (!h->type)
        throw std::runtime_error(path + ": unsupported NRRD type '" + h->type_name +
                                 "'; snert reads integer and float samples");
    check_grid(path, h->sizes, memory_limit);
    const std::string& file = h->data_file;
    if (lower(file).rfind("list", 0) == 0 || file.find('%') != std::string::npos ||
        file.find(' ') != std::string::npos || h->line_skip > 0)
        return; // slice lists, patterns and line skips: left to ITK
    const std::string data_path =
        file.empty() ? path : (file[0] == '/' ? file : folder_of(path) + file);
    std::uint64_t size = 0;
    try {
        size = file_size(data_path);
    } catch (const std::runtime_error&) {
        throw std::runtime_error(path + ": its data file " + data_path + " is missing");
    }
    const std::uint64_t start = (file.empty() ? h->data_offset : 0) +
                                std::uint64_t(std::max<std::int64_t>(h->byte_skip, 0));
    const std::uint64_t need = h->data_bytes();
    if (need == 0) return;
    if (h->encoding == "raw") {
        // byte skip -1: the samples are the last bytes of the file.
        const std::uint64_t have = h->byte_skip == -1 ? size : (size > start ? size - start : 0);
        if (have < need) throw_short(path, "NRRD", need, data_path, have);
    } else if (h->encoding == "gzip" || h->encoding == "gz") {
        const std::uint64_t produced = inflated_file_bytes(data_path, start, need);
        if (produced < need) throw_short(path, "NRRD", need, data_path, produced);
    }
}

} // namespace snert::detail
