// Label names from NIfTI-1 header extensions (see nifti_label_names.h).
#include "nifti_label_names.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <exception>
#include <string_view>
#include <vector>

#include <zlib.h>

namespace snert {

namespace {

constexpr std::size_t kHeaderBytes = 348;

struct GzReader {
    gzFile file = nullptr;
    explicit GzReader(const std::string& path) : file(gzopen(path.c_str(), "rb")) {}
    ~GzReader() {
        if (file) gzclose(file);
    }
    GzReader(const GzReader&) = delete;
    GzReader& operator=(const GzReader&) = delete;

    // Reads up to `size` bytes (gzread also reads uncompressed files as they are); returns
    // how many were read, fewer at the end of the file or on an error.
    std::size_t read(std::uint8_t* out, std::size_t size) {
        std::size_t done = 0;
        while (done < size) {
            const unsigned chunk = unsigned(std::min<std::size_t>(size - done, 1u << 20));
            const int got = gzread(file, out + done, chunk);
            if (got <= 0) break;
            done += std::size_t(got);
        }
        return done;
    }
};

std::int32_t read_i32(const std::uint8_t* p, bool swap) {
    std::uint8_t b[4] = {p[0], p[1], p[2], p[3]};
    if (swap) std::swap(b[0], b[3]), std::swap(b[1], b[2]);
    std::int32_t v;
    std::memcpy(&v, b, 4);
    return v;
}

float read_f32(const std::uint8_t* p, bool swap) {
    const std::int32_t bits = read_i32(p, swap);
    float v;
    std::memcpy(&v, &bits, 4);
    return v;
}

std::string decode_entities(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    static constexpr std::pair<std::string_view, char> entities[] = {
        {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
    for (std::size_t i = 0; i < text.size();) {
        bool replaced = false;
        if (text[i] == '&')
            for (const auto& [entity, c] : entities)
                if (text.substr(i, entity.size()) == entity) {
                    out += c;
                    i += entity.size();
                    replaced = true;
                    break;
                }
        if (!replaced) out += text[i++];
    }
    return out;
}

std::string trim(std::string_view s) {
    const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; };
    while (!s.empty() && space(s.front())) s.remove_prefix(1);
    while (!s.empty() && space(s.back())) s.remove_suffix(1);
    return std::string(s);
}

// The integer value of attribute `name` in the start tag `tag`, or false.
bool int_attribute(std::string_view tag, std::string_view name, int& value) {
    for (std::size_t at = tag.find(name); at != std::string_view::npos;
         at = tag.find(name, at + 1)) {
        // A whole attribute name: preceded by white space, followed by optional space and '='.
        if (at == 0 || !(tag[at - 1] == ' ' || tag[at - 1] == '\t' || tag[at - 1] == '\n' ||
                         tag[at - 1] == '\r'))
            continue;
        std::size_t i = at + name.size();
        while (i < tag.size() && tag[i] == ' ') ++i;
        if (i >= tag.size() || tag[i] != '=') continue;
        ++i;
        while (i < tag.size() && tag[i] == ' ') ++i;
        if (i >= tag.size() || (tag[i] != '"' && tag[i] != '\'')) continue;
        const char quote = tag[i++];
        const std::size_t end = tag.find(quote, i);
        if (end == std::string_view::npos) return false;
        const std::string text = trim(tag.substr(i, end - i));
        if (text.empty() || text.size() > 11) return false;
        long long v = 0;
        std::size_t k = 0;
        const bool negative = text[0] == '-';
        if (negative) k = 1;
        if (k == text.size()) return false;
        for (; k < text.size(); ++k) {
            if (text[k] < '0' || text[k] > '9') return false;
            v = v * 10 + (text[k] - '0');
        }
        if (negative) v = -v;
        if (v < -2147483647LL - 1 || v > 2147483647LL) return false;
        value = int(v);
        return true;
    }
    return false;
}

} // namespace

std::map<int, std::string> label_names_from_xml(const std::string& xml) {
    std::map<int, std::string> names;
    const std::string_view text(xml);
    std::size_t at = 0;
    while ((at = text.find("<Label", at)) != std::string_view::npos) {
        const std::size_t after = at + 6;
        // <LabelTable> and the like are other elements.
        if (after >= text.size() ||
            !(text[after] == ' ' || text[after] == '\t' || text[after] == '\n' ||
              text[after] == '\r' || text[after] == '>')) {
            at = after;
            continue;
        }
        const std::size_t tag_end = text.find('>', after);
        if (tag_end == std::string_view::npos) break;
        const std::string_view tag = text.substr(after, tag_end - after);
        at = tag_end + 1;
        if (!tag.empty() && tag.back() == '/') continue; // <Label ... />: no name
        const std::size_t close = text.find("</Label>", at);
        if (close == std::string_view::npos) break;
        std::string_view content = text.substr(at, close - at);
        at = close + 8;
        int key = 0;
        if (!int_attribute(tag, "Key", key)) continue;
        std::string name;
        if (const std::size_t cdata = content.find("<![CDATA["); cdata != std::string_view::npos) {
            const std::size_t start = cdata + 9;
            const std::size_t end = content.find("]]>", start);
            if (end == std::string_view::npos) continue;
            name = trim(content.substr(start, end - start));
        } else {
            name = trim(decode_entities(content));
        }
        if (!name.empty()) names[key] = std::move(name);
    }
    return names;
}

std::map<int, std::string> nifti_label_names(const std::string& path) {
    try {
        GzReader reader(path);
        if (!reader.file) return {};
        std::uint8_t header[kHeaderBytes + 4];
        if (reader.read(header, sizeof header) != sizeof header) return {};
        bool swap = false;
        if (read_i32(header, false) != 348) {
            if (read_i32(header, true) != 348) return {}; // not NIfTI-1 (NIfTI-2 is 540)
            swap = true;
        }
        if (header[kHeaderBytes] == 0) return {}; // extension flag: no extensions
        // Single-file NIfTI ("n+1"): the extensions end at vox_offset. Otherwise (a .hdr of
        // an .hdr/.img pair) they run to the end of the header file.
        const bool single_file = std::memcmp(header + 344, "n+1", 4) == 0;
        std::size_t end = kHeaderBytes + 4 + kMaxNiftiExtensionBytes;
        if (single_file) {
            const float vox_offset = read_f32(header + 108, swap);
            if (!(vox_offset >= float(kHeaderBytes + 4))) return {};
            end = std::size_t(std::min<double>(vox_offset, double(end)));
        }
        std::vector<std::uint8_t> bytes(end - (kHeaderBytes + 4));
        bytes.resize(reader.read(bytes.data(), bytes.size()));

        std::map<int, std::string> names;
        for (std::size_t at = 0; at + 8 <= bytes.size();) {
            const std::int32_t esize = read_i32(bytes.data() + at, swap);
            const std::int32_t ecode = read_i32(bytes.data() + at + 4, swap);
            if (esize < 16 || std::size_t(esize) > bytes.size() - at) break;
            if (ecode == 0 || ecode == 30 || ecode == 32) { // unknown, Caret/Workbench, CIFTI
                const std::string xml(reinterpret_cast<const char*>(bytes.data() + at + 8),
                                      std::size_t(esize) - 8);
                for (auto& [key, name] : label_names_from_xml(xml))
                    names.emplace(key, std::move(name));
            }
            at += std::size_t(esize);
        }
        return names;
    } catch (const std::exception&) {
        return {}; // e.g. out of memory: no names
    }
}

} // namespace snert
