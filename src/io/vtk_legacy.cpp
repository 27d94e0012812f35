// VTK legacy structured points headers and the size check of the samples they promise.
//
// This work is based on the VTK legacy file format, structured points (VTK User's Guide, "VTK
// File Formats").
#include "vtk_legacy.h"

#include <cctype>
#include <stdexcept>
#include <vector>

#include "file_bytes.h"
#include "header_text.h"
#include "sizes.h"

namespace snert::detail {

namespace {

std::optional<ScalarType> vtk_type(const std::string& name) {
    static const std::pair<const char*, ScalarType> table[] = {
        {"unsigned_char", ScalarType::UInt8},   {"char", ScalarType::Int8},
        {"unsigned_short", ScalarType::UInt16}, {"short", ScalarType::Int16},
        {"unsigned_int", ScalarType::UInt32},   {"int", ScalarType::Int32},
        {"unsigned_long", ScalarType::UInt64},  {"long", ScalarType::Int64},
        {"vtktypeuint64", ScalarType::UInt64},  {"vtktypeint64", ScalarType::Int64},
        {"float", ScalarType::Float32},         {"double", ScalarType::Float64},
    };
    const std::string key = lower(name);
    for (const auto& [n, t] : table)
        if (key == n) return t;
    return std::nullopt;
}

} // namespace

std::uint64_t VtkHeader::data_bytes() const {
    if (!type) return 0;
    return checked_product({points, components, scalar_type_size(*type)});
}

std::optional<VtkHeader> parse_vtk_header(const std::uint8_t* bytes, std::size_t size,
                                          const std::string& name) {
    LineReader lines(bytes, size);
    auto first = lines.next();
    if (!first || first->rfind("# vtk DataFile Version", 0) != 0) return std::nullopt;
    if (!lines.next()) return std::nullopt; // title
    auto encoding = lines.next();
    if (!encoding) return std::nullopt;
    VtkHeader h;
    const std::string enc = lower(trim(*encoding));
    if (enc == "binary")
        h.binary = true;
    else if (enc != "ascii")
        return std::nullopt;
    bool structured_points = false, have_dims = false, have_points = false;
    while (auto line = lines.next()) {
        const auto w = words(*line);
        if (w.empty()) continue;
        const std::string key = lower(w[0]);
        if (key == "dataset") {
            if (w.size() < 2 || lower(w[1]) != "structured_points") return std::nullopt;
            structured_points = true;
        } else if (key == "dimensions") {
            if (w.size() != 4) return std::nullopt;
            for (int a = 0; a < 3; ++a) {
                auto n = parse_count(w[std::size_t(a) + 1]);
                if (!n) return std::nullopt;
                h.dims[a] = *n;
            }
            have_dims = true;
        } else if (key == "spacing" || key == "aspect_ratio" || key == "origin") {
            continue;
        } else if (key == "point_data") {
            auto n = w.size() == 2 ? parse_count(w[1]) : std::nullopt;
            if (!n) return std::nullopt;
            h.points = *n;
            have_points = true;
        } else if (key == "scalars" && have_points) {
            if (w.size() < 3) return std::nullopt;
            h.attribute = "SCALARS";
            h.type = vtk_type(w[2]);
            if (w.size() >= 4) {
                auto n = parse_count(w[3]);
                if (!n || *n < 1 || *n > 4) return std::nullopt;
                h.components = *n;
            }
            auto table = lines.next(); // LOOKUP_TABLE name: required after SCALARS
            const auto table_words = table ? words(*table) : std::vector<std::string>{};
            if (table_words.empty() || lower(table_words[0]) != "lookup_table") return std::nullopt;
            h.data_offset = lines.position();
            break;
        } else if (key == "vectors" && have_points) {
            if (w.size() < 3) return std::nullopt;
            h.attribute = "VECTORS";
            h.type = vtk_type(w[2]);
            h.components = 3;
            h.data_offset = lines.position();
            break;
        } else {
            return std::nullopt; // FIELD, CELL_DATA, COLOR_SCALARS ...: not checked here
        }
    }
    if (!structured_points || !have_dims || !have_points || h.attribute.empty() || !h.type)
        return std::nullopt;
    const std::uint64_t grid = checked_product({h.dims[0], h.dims[1], h.dims[2]});
    if (grid != h.points)
        throw std::runtime_error(name + ": bad VTK header: POINT_DATA " + std::to_string(h.points) +
                                 " does not match DIMENSIONS " + std::to_string(h.dims[0]) + " " +
                                 std::to_string(h.dims[1]) + " " + std::to_string(h.dims[2]));
    return h;
}

std::uint64_t count_tokens(const std::uint8_t* bytes, std::size_t size, std::uint64_t enough) {
    std::uint64_t tokens = 0;
    bool in_token = false;
    for (std::size_t i = 0; i < size && tokens < enough; ++i) {
        const bool space = std::isspace(bytes[i]) != 0;
        if (!space && !in_token) ++tokens;
        in_token = !space;
    }
    return tokens;
}

void check_vtk_data(const std::string& path, std::uint64_t memory_limit) {
    const std::uint64_t size = file_size(path);
    const auto prefix = read_file_prefix(path, 1 << 16);
    const auto h = parse_vtk_header(prefix.data(), prefix.size(), path);
    if (!h || h->data_offset > size) return;
    check_grid(path, {h->dims[0], h->dims[1], h->dims[2]}, memory_limit);
    if (h->binary) {
        const std::uint64_t need = h->data_bytes();
        if (need != 0 && size - h->data_offset < need)
            throw_short(path, "VTK", need, path, size - h->data_offset);
        return;
    }
    const std::uint64_t need = h->points * h->components;
    const auto all = read_file_prefix(path, std::size_t(size));
    const std::uint64_t have =
        count_tokens(all.data() + h->data_offset, all.size() - std::size_t(h->data_offset), need);
    if (have < need)
        throw std::runtime_error(path + ": truncated VTK: the header promises " +
                                 std::to_string(need) + " ASCII values, the file holds " +
                                 std::to_string(have));
}

} // namespace snert::detail
