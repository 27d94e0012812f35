// MetaImage headers and the size check of the data they promise.
//
// This work is based on the MetaImage / MetaIO key = value header description (Kitware, MetaIO
// documentation).
#include "metaimage.h"

#include <stdexcept>

#include "file_bytes.h"
#include "gzip.h"
#include "header_text.h"
#include "sizes.h"

namespace snert::detail {

namespace {

bool parse_bool_word(const std::string& value) {
    const std::string v = lower(value);
    return v == "true" || v == "1" || v == "yes";
}

std::optional<ScalarType> meta_type(std::string element_type) {
    const std::string suffix = "_ARRAY";
    if (element_type.size() > suffix.size() &&
        element_type.compare(element_type.size() - suffix.size(), suffix.size(), suffix) == 0)
        element_type.resize(element_type.size() - suffix.size());
    // MetaIO sizes: MET_LONG / MET_ULONG are 4 bytes, MET_LONG_LONG 8.
    static const std::pair<const char*, ScalarType> table[] = {
        {"MET_UCHAR", ScalarType::UInt8},       {"MET_CHAR", ScalarType::Int8},
        {"MET_USHORT", ScalarType::UInt16},     {"MET_SHORT", ScalarType::Int16},
        {"MET_UINT", ScalarType::UInt32},       {"MET_INT", ScalarType::Int32},
        {"MET_ULONG", ScalarType::UInt32},      {"MET_LONG", ScalarType::Int32},
        {"MET_ULONG_LONG", ScalarType::UInt64}, {"MET_LONG_LONG", ScalarType::Int64},
        {"MET_FLOAT", ScalarType::Float32},     {"MET_DOUBLE", ScalarType::Float64},
    };
    for (const auto& [n, t] : table)
        if (element_type == n) return t;
    return std::nullopt;
}

} // namespace

std::uint64_t MetaHeader::data_bytes() const {
    std::vector<std::uint64_t> factors = dims;
    factors.push_back(channels);
    factors.push_back(type ? scalar_type_size(*type) : 0);
    return checked_product(factors);
}

MetaHeader parse_metaimage_header(const std::string& text, const std::string& name) {
    MetaHeader h;
    std::optional<std::uint64_t> ndims;
    bool have_dims = false, have_file = false;
    std::size_t pos = 0;
    while (pos < text.size() && !have_file) {
        std::size_t end = text.find('\n', pos);
        const std::size_t next = end == std::string::npos ? text.size() : end + 1;
        const std::string line = text.substr(pos, next - pos);
        pos = next;
        const std::size_t eq = line.find('=');
        if (eq == std::string::npos) continue;
        const std::string key = lower(trim(line.substr(0, eq)));
        const std::string value = trim(line.substr(eq + 1));
        if (key == "ndims") {
            ndims = parse_count(value);
            if (!ndims || *ndims < 1 || *ndims > 16)
                throw std::runtime_error(name + ": bad MetaImage header: NDims = " + value);
        } else if (key == "dimsize") {
            h.dims.clear();
            for (const auto& w : words(value)) {
                auto n = parse_count(w);
                if (!n)
                    throw std::runtime_error(name + ": bad MetaImage header: DimSize = " + value);
                h.dims.push_back(*n);
            }
            have_dims = true;
        } else if (key == "elementtype") {
            h.element_type = value;
            h.type = meta_type(value);
        } else if (key == "elementnumberofchannels") {
            auto n = parse_count(value);
            if (!n || *n < 1)
                throw std::runtime_error(name +
                                         ": bad MetaImage header: "
                                         "ElementNumberOfChannels = " +
                                         value);
            h.channels = *n;
        } else if (key == "binarydata") {
            h.binary = parse_bool_word(value);
        } else if (key == "compresseddata") {
            h.compressed = parse_bool_word(value);
        } else if (key == "compresseddatasize") {
            h.compressed_size = parse_count(value);
        } else if (key == "headersize") {
            auto n = parse_signed(value);
            if (!n || *n < -1)
                throw std::runtime_error(name + ": bad MetaImage header: HeaderSize = " + value);
            h.header_size = *n;
        } else if (key == "elementdatafile") {
            h.data_file = value;
            h.local_offset = pos;
            have_file = true;
        }
    }
    if (!have_file)
        throw std::runtime_error(name + ": bad MetaImage header: no ElementDataFile line");
    if (!have_dims || h.dims.empty())
        throw std::runtime_error(name + ": bad MetaImage header: no DimSize line");
    if (ndims) {
        if (h.dims.size() < *ndims)
            throw std::runtime_error(name + ": bad MetaImage header: DimSize has " +
                                     std::to_string(h.dims.size()) +
                                     " values for NDims = " + std::to_string(*ndims));
        h.dims.resize(*ndims);
    }
    return h;
}

void check_metaimage_data(const std::string& path, std::uint64_t memory_limit) {
    const auto prefix = read_file_prefix(path, 1 << 20);
    const MetaHeader h = parse_metaimage_header(std::string(prefix.begin(), prefix.end()), path);
    if (!h.element_type.empty() && !h.type)
        throw std::runtime_error(path + ": unsupported MetaImage ElementType " + h.element_type);
    check_grid(path, h.dims, memory_limit);
    const std::string data_file = lower(h.data_file);
    if (!h.binary || data_file == "list" || h.data_file.find('%') != std::string::npos ||
        h.data_file.empty())
        return;
    const std::uint64_t need = h.data_bytes();
    if (need == 0) return; // unknown type or overflow: ITK refuses, or checked_dims does
    const bool local = data_file == "local";
    const std::string data_path =
        local ? path : (h.data_file[0] == '/' ? h.data_file : folder_of(path) + h.data_file);
    std::uint64_t size = 0;
    try {
        size = file_size(data_path);
    } catch (const std::runtime_error&) {
        throw std::runtime_error(path + ": its data file " + data_path + " is missing");
    }
    std::uint64_t start = local ? h.local_offset : 0;
    if (h.header_size > 0) start += std::uint64_t(h.header_size);
    if (h.compressed) {
        const std::uint64_t stored = size > start ? size - start : 0;
        if (h.compressed_size && stored < *h.compressed_size)
            throw std::runtime_error(path + ": truncated MetaImage: CompressedDataSize is " +
                                     std::to_string(*h.compressed_size) + " bytes, " + data_path +
                                     " holds " + std::to_string(stored));
        const std::uint64_t produced = inflated_file_bytes(data_path, start, need);
        if (produced < need) throw_short(path, "MetaImage", need, data_path, produced);
        return;
    }
    // HeaderSize = -1: the samples are the last bytes of the file, whatever precedes them.
    const std::uint64_t have = h.header_size == -1 ? size : (size > start ? size - start : 0);
    if (have < need) throw_short(path, "MetaImage", need, data_path, have);
}

} // namespace snert::detail
