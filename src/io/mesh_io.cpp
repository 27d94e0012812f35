// Mesh files: binary STL, Wavefront OBJ, PLY, OFF and legacy VTK polydata, written atomically
// and read back with every count checked against the file size before anything is allocated.
//
// This work is based on the published format descriptions: the binary STL layout (80-byte
// header, uint32 count, 50 bytes per facet), Paul Bourke's PLY and OFF notes, the Wavefront OBJ
// appendix and the VTK file formats document (legacy 3.0 and 5.1 polydata). Numbers are written
// with std::to_chars, the shortest text that reads back to the same float, so text formats
// round-trip exactly and independently of the locale.
#include "mesh_io.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "atomic_file.h"

namespace snert {
namespace {

constexpr std::uint32_t kNoVertex = 0xffffffffu;

// ---------------------------------------------------------------------------------------------
// Little-endian binary values (STL and our PLY are little-endian whatever the machine).

template <class T> T byte_swapped(T value) {
    std::array<char, sizeof(T)> bytes;
    std::memcpy(bytes.data(), &value, sizeof(T));
    std::reverse(bytes.begin(), bytes.end());
    std::memcpy(&value, bytes.data(), sizeof(T));
    return value;
}

template <class T> void put(char*& out, T value, bool little_endian = true) {
    if ((std::endian::native == std::endian::little) != little_endian) value = byte_swapped(value);
    std::memcpy(out, &value, sizeof(T));
    out += sizeof(T);
}

template <class T> T get(const char* in, bool little_endian = true) {
    T value;
    std::memcpy(&value, in, sizeof(T));
    if ((std::endian::native == std::endian::little) != little_endian) value = byte_swapped(value);
    return value;
}

// ---------------------------------------------------------------------------------------------
// Writing.

void check_mesh_for_writing(const Mesh& mesh, const std::string& path) {
    if (mesh.indices.size() % 3 != 0)
        throw std::invalid_argument(path + ": mesh index count is not a multiple of 3");
    for (std::uint32_t i : mesh.indices)
        if (i >= mesh.positions.size())
            throw std::invalid_argument(path + ": mesh index " + std::to_string(i) +
                                        " out of range (" + std::to_string(mesh.positions.size()) +
                                        " vertices)");
}

// Text output through a local buffer: one stream call per 64 KiB instead of per number.
class TextOut {
  public:
    explicit TextOut(std::ostream& os) : os_(os) { buffer_.reserve(kFlushAt + 256); }
    ~TextOut() { flush(); }
    TextOut& operator<<(std::string_view text) {
        buffer_.append(text);
        return maybe_flush();
    }
    TextOut& operator<<(char c) {
        buffer_.push_back(c);
        return maybe_flush();
    }
    template <class Number>
    requires std::is_arithmetic_v<Number> TextOut& operator<<(Number value) {
        char text[64];
        const auto result = std::to_chars(text, text + sizeof(text), value);
        buffer_.append(text, result.ptr);
        return maybe_flush();
    }
    TextOut& operator<<(glm::vec3 p) { return *this << p.x << ' ' << p.y << ' ' << p.z; }
    void flush() {
        os_.write(buffer_.data(), std::streamsize(buffer_.size()));
        buffer_.clear();
    }

  private:
    static constexpr std::size_t kFlushAt = 1 << 16;
    TextOut& maybe_flush() {
        if (buffer_.size() >= kFlushAt) flush();
        return *this;
    }
    std::ostream& os_;
    std::string buffer_;
};

glm::vec3 unit_normal(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    const glm::dvec3 n = glm::cross(glm::dvec3(b - a), glm::dvec3(c - a));
    const double length = glm::length(n);
    return length > 0 && std::isfinite(length) ? glm::vec3(n / length) : glm::vec3(0.0f);
}

void write_stl(std::ostream& os, const Mesh& mesh, const std::string& path) {
    const std::size_t triangles = mesh.triangle_count();
    if (triangles > 0xffffffffu) throw std::invalid_argument(path + ": too many triangles for STL");
    // The header must not start with "solid", which marks ASCII STL.
    std::array<char, 84> header{};
    const std::string_view title = "binary STL written by snert";
    std::copy(title.begin(), title.end(), header.begin());
    char* out = header.data() + 80;
    put(out, std::uint32_t(triangles));
    os.write(header.data(), std::streamsize(header.size()));

    constexpr std::size_t kFacet = 50, kBatch = 4096;
    std::vector<char> batch(kFacet * kBatch);
    for (std::size_t first = 0; first < triangles; first += kBatch) {
        const std::size_t last = std::min(triangles, first + kBatch);
        out = batch.data();
        for (std::size_t t = first; t < last; ++t) {
            const glm::vec3 p[3] = {mesh.positions[mesh.indices[3 * t]],
                                    mesh.positions[mesh.indices[3 * t + 1]],
                                    mesh.positions[mesh.indices[3 * t + 2]]};
            const glm::vec3 n = unit_normal(p[0], p[1], p[2]);
            for (int k = 0; k < 3; ++k) put(out, n[k]);
            for (const glm::vec3& q : p)
                for (int k = 0; k < 3; ++k) put(out, q[k]);
            put(out, std::uint16_t(0)); // attribute byte count
        }
        os.write(batch.data(), out - batch.data());
    }
}

void write_obj(std::ostream& os, const Mesh& mesh) {
    TextOut out(os);
    out << "# written by snert\n";
    for (const glm::vec3& p : mesh.positions) out << "v " << p << '\n';
    const std::vector<std::uint32_t>& i = mesh.indices;
    for (std::size_t t = 0; t < i.size(); t += 3) // OBJ counts vertices from 1
        out << "f " << i[t] + 1ull << ' ' << i[t + 1] + 1ull << ' ' << i[t + 2] + 1ull << '\n';
}

void write_ply(std::ostream& os, const Mesh& mesh, const std::string& path) {
    if (mesh.positions.size() > 0x7fffffffu)
        throw std::invalid_argument(path + ": too many vertices for PLY int indices");
    {
        TextOut header(os);
        header << "ply\nformat binary_little_endian 1.0\ncomment written by snert\n"
               << "element vertex " << mesh.positions.size() << '\n'
               << "property float x\nproperty float y\nproperty float z\n"
               << "element face " << mesh.triangle_count() << '\n'
               << "property list uchar int vertex_indices\nend_header\n";
    }
    constexpr std::size_t kBatch = 4096;
    std::vector<char> batch(kBatch * 13);
    for (std::size_t first = 0; first < mesh.positions.size(); first += kBatch) {
        const std::size_t last = std::min(mesh.positions.size(), first + kBatch);
        char* out = batch.data();
        for (std::size_t v = first; v < last; ++v)
            for (int k = 0; k < 3; ++k) put(out, mesh.positions[v][k]);
        os.write(batch.data(), out - batch.data());
    }
    for (std::size_t first = 0; first < mesh.triangle_count(); first += kBatch) {
        const std::size_t last = std::min(mesh.triangle_count(), first + kBatch);
        char* out = batch.data();
        for (std::size_t t = first; t < last; ++t) {
            put(out, std::uint8_t(3));
            for (int k = 0; k < 3; ++k) put(out, std::int32_t(mesh.indices[3 * t + k]));
        }
        os.write(batch.data(), out - batch.data());
    }
}

// "3 a b c" lines, 0-based, as OFF and VTK want them.
void write_counted_triangles(TextOut& out, const std::vector<std::uint32_t>& i) {
    for (std::size_t t = 0; t < i.size(); t += 3)
        out << "3 " << i[t] << ' ' << i[t + 1] << ' ' << i[t + 2] << '\n';
}

void write_off(std::ostream& os, const Mesh& mesh) {
    TextOut out(os);
    out << "OFF\n" << mesh.positions.size() << ' ' << mesh.triangle_count() << " 0\n";
    // As doubles: the shortest text that reads back as the float's exact value also in a reader
    // that parses doubles (TetGen, the FE check), so it tests the very mesh snert measured.
    for (const glm::vec3& p : mesh.positions)
        out << double(p.x) << ' ' << double(p.y) << ' ' << double(p.z) << '\n';
    write_counted_triangles(out, mesh.indices);
}

// Legacy 3.0 layout (POLYGONS with counts inline), which every VTK version and ParaView reads.
void write_vtk(std::ostream& os, const Mesh& mesh) {
    TextOut out(os);
    out << "# vtk DataFile Version 3.0\nsnert mesh\nASCII\nDATASET POLYDATA\n"
        << "POINTS " << mesh.positions.size() << " float\n";
    for (const glm::vec3& p : mesh.positions) out << p << '\n';
    out << "POLYGONS " << mesh.triangle_count() << ' ' << 4 * mesh.triangle_count() << '\n';
    write_counted_triangles(out, mesh.indices);
}

// ---------------------------------------------------------------------------------------------
// Reading: common parts.

std::string read_whole_file(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw std::runtime_error(path + ": cannot open: " + std::strerror(errno));
    struct stat info {};
    if (::fstat(fd, &info) != 0 || !S_ISREG(info.st_mode)) {
        ::close(fd);
        throw std::runtime_error(path + ": not a regular file");
    }
    std::string data(std::size_t(info.st_size), '\0');
    std::size_t done = 0;
    while (done < data.size()) {
        const ssize_t got = ::read(fd, data.data() + done, data.size() - done);
        if (got < 0 && errno == EINTR) continue;
        if (got <= 0) {
            const int error = got < 0 ? errno : 0;
            ::close(fd);
            throw std::runtime_error(
                path + ": cannot read: " + (error != 0 ? std::strerror(error) : "file shrank"));
        }
        done += std::size_t(got);
    }
    ::close(fd);
    return data;
}

// Appends triangles (0, k, k + 1) for a polygon: the usual reading of convex faces.
void append_fan(const std::vector<std::uint32_t>& polygon, std::vector<std::uint32_t>& indices) {
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
        indices.push_back(polygon[0]);
        indices.push_back(polygon[k]);
        indices.push_back(polygon[k + 1]);
    }
}

// Text scanning with errors that name the file and the line.
class TextScanner {
  public:
    TextScanner(std::string_view data, const std::string& path, char comment)
        : data_(data), path_(path), comment_(comment) {}

    std::size_t position() const { return pos_; }
    std::size_t remaining() const { return data_.size() - pos_; }
    bool at_end() {
        skip_space();
        return pos_ >= data_.size();
    }

    // Next whitespace-separated word (comments skipped); empty at the end of the data.
    std::string_view peek_word() {
        const std::size_t saved = pos_, saved_mark = mark_;
        const std::string_view next = word();
        pos_ = saved;
        mark_ = saved_mark;
        return next;
    }
    std::string_view word() {
        skip_space();
        const std::size_t begin = pos_;
        mark_ = begin;
        while (pos_ < data_.size() && !is_space(data_[pos_])) ++pos_;
        return data_.substr(begin, pos_ - begin);
    }
    // Rest of the current line without its end; moves to the start of the next line.
    std::string_view line() {
        const std::size_t begin = pos_;
        mark_ = begin;
        const std::size_t end = std::min(data_.find('\n', pos_), data_.size());
        pos_ = end < data_.size() ? end + 1 : end;
        std::string_view text = data_.substr(begin, end - begin);
        if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
        return text;
    }
    void skip_line() { line(); }

    float real(const char* what) { return parse_real(word(), what); }
    long long integer(const char* what) { return parse_integer(word(), what); }
    void expect(std::string_view keyword) {
        const std::string_view got = word();
        if (!equal_ignoring_case(got, keyword))
            fail("expected '" + std::string(keyword) + "', found '" + std::string(got) + "'");
    }

    float parse_real(std::string_view text, const char* what) const {
        if (!text.empty() && text.front() == '+') text.remove_prefix(1);
        float value = 0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (text.empty() || error != std::errc() || end != text.data() + text.size())
            fail(bad(text, what));
        return value;
    }
    long long parse_integer(std::string_view text, const char* what) const {
        if (!text.empty() && text.front() == '+') text.remove_prefix(1);
        long long value = 0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (text.empty() || error != std::errc() || end != text.data() + text.size())
            fail(bad(text, what));
        return value;
    }
    // A count announced by the file, checked against what is left of it: each item needs at
    // least `min_bytes`, so a lying count fails here instead of in an allocation.
    std::size_t count(const char* what, std::size_t min_bytes) {
        const long long n = integer(what);
        if (n < 0) fail(std::string("negative ") + what);
        if (std::size_t(n) > remaining() / min_bytes)
            fail(std::string(what) + " " + std::to_string(n) + " is more than the " +
                 std::to_string(remaining()) + " remaining bytes can hold (truncated file?)");
        return std::size_t(n);
    }

    [[noreturn]] void fail(const std::string& message) const {
        const std::size_t line =
            1 + std::size_t(std::count(data_.begin(), data_.begin() + std::ptrdiff_t(mark_), '\n'));
        throw std::runtime_error(path_ + ": line " + std::to_string(line) + ": " + message);
    }

    static bool equal_ignoring_case(std::string_view a, std::string_view b) {
        return a.size() == b.size() &&
               std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
                   return std::tolower((unsigned char)x) == std::tolower((unsigned char)y);
               });
    }

  private:
    static bool is_space(char c) {
        return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
    }
    static std::string bad(std::string_view text, const char* what) {
        if (text.empty()) return std::string("unexpected end of file, expected ") + what;
        return std::string("bad ") + what + " '" + std::string(text.substr(0, 40)) + "'";
    }
    void skip_space() {
        while (pos_ < data_.size()) {
            if (is_space(data_[pos_])) {
                ++pos_;
            } else if (comment_ != 0 && data_[pos_] == comment_) {
                while (pos_ < data_.size() && data_[pos_] != '\n') ++pos_;
            } else {
                break;
            }
        }
    }

    std::string_view data_;
    const std::string& path_;
    char comment_;
    std::size_t pos_ = 0;
    std::size_t mark_ = 0; // start of the last word or line read, for the line number of errors
};

// Next word of a line (spaces and tabs separate words).
std::string_view next_word(std::string_view& rest) {
    std::size_t begin = 0;
    while (begin < rest.size() && (rest[begin] == ' ' || rest[begin] == '\t')) ++begin;
    std::size_t end = begin;
    while (end < rest.size() && rest[end] != ' ' && rest[end] != '\t') ++end;
    const std::string_view word = rest.substr(begin, end - begin);
    rest.remove_prefix(end);
    return word;
}

void check_indices(const Mesh& mesh, const std::string& path) {
    for (std::uint32_t i : mesh.indices)
        if (i >= mesh.positions.size())
            throw std::runtime_error(path + ": vertex index " + std::to_string(i) +
                                     " out of range (" + std::to_string(mesh.positions.size()) +
                                     " vertices)");
}

// ---------------------------------------------------------------------------------------------
// STL.

// Merges corners with bit-identical positions (after turning -0 into +0) with an open-addressing
// hash table that grows with the number of distinct vertices: STL stores each triangle's corners
// separately, and the metrics need shared vertices.
Mesh weld(const std::vector<glm::vec3>& corners) {
    Mesh mesh;
    mesh.indices.resize(corners.size());
    std::vector<std::uint32_t> table(std::bit_ceil(std::max<std::size_t>(64, corners.size() / 4)),
                                     kNoVertex);
    auto bits = [](glm::vec3 p) {
        std::array<std::uint32_t, 3> b;
        for (int k = 0; k < 3; ++k) {
            const float canonical = p[k] + 0.0f; // -0 + 0 = +0
            std::memcpy(&b[std::size_t(k)], &canonical, sizeof(float));
        }
        return b;
    };
    auto slot_of = [&](const std::array<std::uint32_t, 3>& b) {
        std::uint64_t h = b[0] * 0x9E3779B97F4A7C15ull ^ b[1] * 0xC2B2AE3D27D4EB4Full ^
                          b[2] * 0x165667B19E3779F9ull;
        h ^= h >> 31;
        return std::size_t(h * 0xD6E8FEB86659FD93ull >> 7) & (table.size() - 1);
    };
    auto insert = [&](std::uint32_t vertex, const std::array<std::uint32_t, 3>& b) {
        std::size_t slot = slot_of(b);
        while (table[slot] != kNoVertex) slot = (slot + 1) & (table.size() - 1);
        table[slot] = vertex;
    };
    for (std::size_t c = 0; c < corners.size(); ++c) {
        const auto b = bits(corners[c]);
        std::size_t slot = slot_of(b);
        std::uint32_t found = kNoVertex;
        for (; table[slot] != kNoVertex; slot = (slot + 1) & (table.size() - 1))
            if (bits(mesh.positions[table[slot]]) == b) {
                found = table[slot];
                break;
            }
        if (found == kNoVertex) {
            found = std::uint32_t(mesh.positions.size());
            mesh.positions.push_back(corners[c]);
            if (2 * mesh.positions.size() > table.size()) { // keep the load at most one half
                table.assign(table.size() * 2, kNoVertex);
                for (std::uint32_t v = 0; v < mesh.positions.size(); ++v)
                    insert(v, bits(mesh.positions[v]));
            } else {
                table[slot] = found;
            }
        }
        mesh.indices[c] = found;
    }
    return mesh;
}

Mesh read_ascii_stl(std::string_view data, const std::string& path) {
    TextScanner in(data, path, 0);
    std::vector<glm::vec3> corners;
    bool ended = false;
    in.expect("solid");
    in.skip_line(); // the solid's name
    for (std::string_view word = in.word(); !word.empty(); word = in.word()) {
        if (TextScanner::equal_ignoring_case(word, "vertex")) {
            glm::vec3 p;
            for (int k = 0; k < 3; ++k) p[k] = in.real("vertex coordinate");
            corners.push_back(p);
        } else if (TextScanner::equal_ignoring_case(word, "normal")) {
            for (int k = 0; k < 3; ++k) in.real("normal component");
        } else if (TextScanner::equal_ignoring_case(word, "endsolid")) {
            ended = true;
            break;
        }
    }
    if (!ended) in.fail("no 'endsolid' (truncated file?)");
    if (corners.size() % 3 != 0) in.fail("vertex count is not a multiple of 3");
    return weld(corners);
}

Mesh read_stl(const std::string& data, const std::string& path) {
    if (data.size() >= 84) {
        const std::uint64_t triangles = get<std::uint32_t>(data.data() + 80);
        if (84 + 50 * triangles == data.size()) {
            std::vector<glm::vec3> corners(3 * triangles);
            for (std::size_t t = 0; t < triangles; ++t) {
                const char* facet = data.data() + 84 + 50 * t + 12; // after the normal
                for (int j = 0; j < 3; ++j)
                    for (int k = 0; k < 3; ++k)
                        corners[3 * t + j][k] = get<float>(facet + 12 * j + 4 * k);
            }
            return weld(corners);
        }
    }
    const std::size_t text_start = data.find_first_not_of(" \t\r\n");
    if (text_start != std::string::npos && data.compare(text_start, 5, "solid") == 0 &&
        data.find("facet", text_start) != std::string::npos)
        return read_ascii_stl(std::string_view(data).substr(text_start), path);
    if (data.size() < 84)
        throw std::runtime_error(path + ": not an STL file (" + std::to_string(data.size()) +
                                 " bytes, shorter than the 84-byte binary header)");
    throw std::runtime_error(
        path + ": not a valid binary STL: the header announces " +
        std::to_string(get<std::uint32_t>(data.data() + 80)) + " triangles (" +
        std::to_string(84 + 50 * std::uint64_t(get<std::uint32_t>(data.data() + 80))) +
        " bytes) but the file has " + std::to_string(data.size()) + " bytes");
}

// ---------------------------------------------------------------------------------------------
// OBJ: positions and faces; texture coordinates, normals, groups and materials are ignored.

Mesh read_obj(const std::string& data, const std::string& path) {
    TextScanner in(data, path, 0);
    Mesh mesh;
    std::vector<std::uint32_t> polygon;
    while (in.remaining() > 0) {
        std::string_view rest = in.line();
        if (const std::size_t hash = rest.find('#'); hash != std::string_view::npos)
            rest = rest.substr(0, hash);
        const std::string_view keyword = next_word(rest);
        if (keyword == "v") {
            glm::vec3 p;
            for (int k = 0; k < 3; ++k) p[k] = in.parse_real(next_word(rest), "vertex coordinate");
            mesh.positions.push_back(p);
        } else if (keyword == "f") {
            polygon.clear();
            for (std::string_view ref = next_word(rest); !ref.empty(); ref = next_word(rest)) {
                // "i", "i/t", "i//n" or "i/t/n"; negative i counts back from the last vertex.
                const long long i = in.parse_integer(ref.substr(0, ref.find('/')), "face index");
                const long long vertex = i > 0 ? i - 1 : (long long)mesh.positions.size() + i;
                if (i == 0 || vertex < 0 || vertex >= (long long)mesh.positions.size())
                    in.fail("face index " + std::to_string(i) + " out of range (" +
                            std::to_string(mesh.positions.size()) + " vertices so far)");
                polygon.push_back(std::uint32_t(vertex));
            }
            if (polygon.size() < 3) in.fail("face with fewer than 3 vertices");
            append_fan(polygon, mesh.indices);
        }
    }
    return mesh;
}

// ---------------------------------------------------------------------------------------------
// OFF.

Mesh read_off(const std::string& data, const std::string& path) {
    TextScanner in(data, path, '#');
    const std::string_view magic = in.word();
    if (magic != "OFF") in.fail("not an OFF file (it does not start with 'OFF')");
    // A vertex line needs at least "0 0 0\n", a face line at least "3 0 1 2\n".
    const std::size_t vertices = in.count("vertex count", 6);
    const std::size_t faces = in.count("face count", 8);
    in.integer("edge count");
    in.skip_line();
    if (vertices > in.remaining() / 6 || faces > (in.remaining() - 6 * vertices) / 8)
        in.fail("the counts announce more data than the file holds (truncated file?)");
    Mesh mesh;
    mesh.positions.resize(vertices);
    for (glm::vec3& p : mesh.positions) {
        for (int k = 0; k < 3; ++k) p[k] = in.real("vertex coordinate");
        in.skip_line(); // colours and other extra columns
    }
    mesh.indices.reserve(3 * faces);
    std::vector<std::uint32_t> polygon;
    for (std::size_t f = 0; f < faces; ++f) {
        const std::size_t n = in.count("face size", 2);
        if (n < 3) in.fail("face with fewer than 3 vertices");
        polygon.clear();
        for (std::size_t k = 0; k < n; ++k) {
            const long long i = in.integer("vertex index");
            if (i < 0 || std::size_t(i) >= vertices)
                in.fail("vertex index " + std::to_string(i) + " out of range (" +
                        std::to_string(vertices) + " vertices)");
            polygon.push_back(std::uint32_t(i));
        }
        in.skip_line(); // face colour
        append_fan(polygon, mesh.indices);
    }
    return mesh;
}

// ---------------------------------------------------------------------------------------------
// Legacy VTK polydata, ASCII: POINTS, POLYGONS and TRIANGLE_STRIPS, in the 3.0 layout (counts
// inline) or the 5.1 one (OFFSETS and CONNECTIVITY). VERTICES and LINES are skipped; point or
// cell data end the reading.

class VtkReader {
  public:
    VtkReader(const std::string& data, const std::string& path) : in_(data, path, 0) {}

    Mesh read() {
        if (in_.line().rfind("# vtk DataFile", 0) != 0) in_.fail("not a legacy VTK file");
        in_.skip_line(); // title
        const std::string_view encoding = in_.line();
        if (encoding.rfind("ASCII", 0) != 0)
            in_.fail("only ASCII legacy VTK files are supported, not '" + std::string(encoding) +
                     "'");
        in_.expect("DATASET");
        const std::string_view dataset = in_.word();
        if (dataset != "POLYDATA")
            in_.fail("dataset '" + std::string(dataset) + "' is not POLYDATA");
        for (std::string_view section = in_.word(); !section.empty(); section = in_.word()) {
            if (section == "POINTS") {
                read_points();
            } else if (section == "POLYGONS") {
                read_cells([&] { append_fan(cell_, mesh_.indices); });
            } else if (section == "TRIANGLE_STRIPS") {
                read_cells([&] { append_strip(); });
            } else if (section == "VERTICES" || section == "LINES") {
                read_cells([] {});
            } else if (section == "METADATA") {
                skip_metadata();
            } else if (section == "POINT_DATA" || section == "CELL_DATA" || section == "FIELD") {
                break;
            } else {
                in_.fail("unknown section '" + std::string(section) + "'");
            }
        }
        return std::move(mesh_);
    }

  private:
    void read_points() {
        if (!mesh_.positions.empty()) in_.fail("second POINTS section");
        const std::size_t n = in_.count("point count", 6);
        in_.word(); // data type: numbers are read as text whatever it says
        mesh_.positions.resize(n);
        for (glm::vec3& p : mesh_.positions)
            for (int k = 0; k < 3; ++k) p[k] = in_.real("point coordinate");
    }

    std::uint32_t point_index() {
        const long long i = in_.integer("point index");
        if (i < 0 || std::size_t(i) >= mesh_.positions.size())
            in_.fail("point index " + std::to_string(i) + " out of range (" +
                     std::to_string(mesh_.positions.size()) + " points)");
        return std::uint32_t(i);
    }

    // Calls emit() once per cell with cell_ holding its point indices.
    template <class Emit> void read_cells(Emit&& emit) {
        const std::size_t first = in_.count("cell count", 2);
        const std::size_t size = in_.count("cell array size", 2);
        if (in_.peek_word() == "OFFSETS") {
            // 5.1: `first` offsets (cells + 1) into a connectivity array of `size` indices.
            in_.word();
            in_.word(); // offset type
            offsets_.resize(first);
            for (std::size_t& o : offsets_) {
                const long long value = in_.integer("offset");
                if (value < 0 || std::size_t(value) > size) in_.fail("offset out of range");
                o = std::size_t(value);
            }
            if (first == 0 || offsets_.front() != 0 || offsets_.back() != size ||
                !std::is_sorted(offsets_.begin(), offsets_.end()))
                in_.fail("the offsets do not describe the connectivity array");
            in_.expect("CONNECTIVITY");
            in_.word(); // index type
            for (std::size_t c = 0; c + 1 < first; ++c) {
                cell_.clear();
                for (std::size_t k = offsets_[c]; k < offsets_[c + 1]; ++k)
                    cell_.push_back(point_index());
                emit();
            }
            return;
        }
        // 3.0: `first` cells, `size` numbers in all, each cell its point count then its points.
        std::size_t used = 0;
        for (std::size_t c = 0; c < first; ++c) {
            const std::size_t n = in_.count("cell size", 2);
            used += n + 1;
            if (used > size) in_.fail("cells larger than the announced array size");
            cell_.clear();
            for (std::size_t k = 0; k < n; ++k) cell_.push_back(point_index());
            emit();
        }
        if (used != size) in_.fail("cells smaller than the announced array size");
    }

    // Strip p0 p1 p2 p3 ...: triangle k is (k, k+1, k+2), every other one flipped to keep the
    // winding of the first.
    void append_strip() {
        for (std::size_t k = 0; k + 2 < cell_.size(); ++k) {
            const bool odd = k % 2 == 1;
            mesh_.indices.push_back(cell_[k]);
            mesh_.indices.push_back(cell_[odd ? k + 2 : k + 1]);
            mesh_.indices.push_back(cell_[odd ? k + 1 : k + 2]);
        }
    }

    // VTK 5.1 may follow an array with "METADATA" lines up to a blank line.
    void skip_metadata() {
        in_.skip_line();
        while (in_.remaining() > 0 && !in_.line().empty()) {
        }
    }

    TextScanner in_;
    Mesh mesh_;
    std::vector<std::uint32_t> cell_;
    std::vector<std::size_t> offsets_;
};

// ---------------------------------------------------------------------------------------------
// PLY: ASCII and both binary byte orders, any elements and properties; the mesh comes from
// vertex x, y, z and the face list vertex_indices (or vertex_index).

enum class PlyType { Int8, Uint8, Int16, Uint16, Int32, Uint32, Float32, Float64 };

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::Float32; // the items' type for a list
    bool list = false;
    PlyType count_type = PlyType::Uint8;
};

struct PlyElement {
    std::string name;
    std::size_t count = 0;
    std::vector<PlyProperty> properties;
};

std::size_t ply_size(PlyType type) {
    switch (type) {
    case PlyType::Int8:
    case PlyType::Uint8:
        return 1;
    case PlyType::Int16:
    case PlyType::Uint16:
        return 2;
    case PlyType::Int32:
    case PlyType::Uint32:
    case PlyType::Float32:
        return 4;
    case PlyType::Float64:
        return 8;
    }
    return 1;
}

class PlyReader {
  public:
    PlyReader(const std::string& data, const std::string& path) : data_(data), path_(path) {}

    Mesh read() {
        read_header();
        for (const PlyElement& element : elements_) {
            if (element.name == "vertex") {
                read_vertices(element);
            } else if (element.name == "face") {
                read_faces(element);
            } else {
                for (std::size_t i = 0; i < element.count; ++i)
                    for (const PlyProperty& p : element.properties) skip_property(p);
            }
        }
        if (!saw_vertices_) fail("no vertex element");
        return std::move(mesh_);
    }

  private:
    enum class Encoding { Ascii, LittleEndian, BigEndian };

    [[noreturn]] void fail(const std::string& message) const {
        throw std::runtime_error(path_ + ": " + message);
    }

    static bool parse_type(std::string_view name, PlyType& type) {
        static constexpr std::pair<std::string_view, PlyType> kNames[] = {
            {"char", PlyType::Int8},      {"int8", PlyType::Int8},
            {"uchar", PlyType::Uint8},    {"uint8", PlyType::Uint8},
            {"short", PlyType::Int16},    {"int16", PlyType::Int16},
            {"ushort", PlyType::Uint16},  {"uint16", PlyType::Uint16},
            {"int", PlyType::Int32},      {"int32", PlyType::Int32},
            {"uint", PlyType::Uint32},    {"uint32", PlyType::Uint32},
            {"float", PlyType::Float32},  {"float32", PlyType::Float32},
            {"double", PlyType::Float64}, {"float64", PlyType::Float64}};
        for (const auto& [text, value] : kNames)
            if (text == name) {
                type = value;
                return true;
            }
        return false;
    }

    void read_header() {
        std::string_view rest(data_);
        auto next_line = [&] {
            const std::size_t end = rest.find('\n');
            if (end == std::string_view::npos) fail("header has no end_header line");
            std::string_view line = rest.substr(0, end);
            rest.remove_prefix(end + 1);
            if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
            return line;
        };
        if (next_line() != "ply") fail("not a PLY file (it does not start with 'ply')");
        bool have_format = false;
        for (std::string_view line = next_line(); line != "end_header"; line = next_line()) {
            std::string_view words = line;
            const std::string_view keyword = next_word(words);
            if (keyword == "format") {
                const std::string_view format = next_word(words);
                if (format == "ascii")
                    encoding_ = Encoding::Ascii;
                else if (format == "binary_little_endian")
                    encoding_ = Encoding::LittleEndian;
                else if (format == "binary_big_endian")
                    encoding_ = Encoding::BigEndian;
                else
                    fail("unknown PLY format '" + std::string(format) + "'");
                have_format = true;
            } else if (keyword == "element") {
                PlyElement element;
                element.name = std::string(next_word(words));
                const std::string_view count = next_word(words);
                const auto [end, error] =
                    std::from_chars(count.data(), count.data() + count.size(), element.count);
                if (count.empty() || error != std::errc() || end != count.data() + count.size())
                    fail("bad count '" + std::string(count) + "' of element " + element.name);
                elements_.push_back(std::move(element));
            } else if (keyword == "property") {
                if (elements_.empty()) fail("property before any element");
                PlyProperty property;
                std::string_view type = next_word(words);
                if (type == "list") {
                    property.list = true;
                    if (!parse_type(next_word(words), property.count_type))
                        fail("bad list count type in: " + std::string(line));
                    type = next_word(words);
                }
                if (!parse_type(type, property.type))
                    fail("unknown property type in: " + std::string(line));
                property.name = std::string(next_word(words));
                elements_.back().properties.push_back(std::move(property));
            } else if (keyword != "comment" && keyword != "obj_info" && !keyword.empty()) {
                fail("unknown header line: " + std::string(line));
            }
        }
        if (!have_format) fail("header has no format line");
        pos_ = data_.size() - rest.size();
    }

    std::size_t remaining() const { return data_.size() - pos_; }

    // The smallest number of bytes one element can take, to check its count before reading.
    std::size_t min_element_bytes(const PlyElement& element) const {
        if (encoding_ == Encoding::Ascii) return 2 * element.properties.size(); // "0 " each
        std::size_t bytes = 0;
        for (const PlyProperty& p : element.properties)
            bytes += p.list ? ply_size(p.count_type) : ply_size(p.type);
        return bytes;
    }

    void check_count(const PlyElement& element) const {
        const std::size_t bytes = min_element_bytes(element);
        if (element.count > 0 && bytes == 0) fail("element " + element.name + " has no properties");
        if (bytes > 0 && element.count > remaining() / bytes)
            fail("element " + element.name + " announces " + std::to_string(element.count) +
                 " items, more than the " + std::to_string(remaining()) +
                 " remaining bytes can hold (truncated file?)");
    }

    double value(PlyType type) {
        if (encoding_ == Encoding::Ascii) return ascii_value();
        const std::size_t size = ply_size(type);
        if (remaining() < size) fail("unexpected end of data (truncated file?)");
        const char* at = data_.data() + pos_;
        pos_ += size;
        const bool little = encoding_ == Encoding::LittleEndian;
        switch (type) {
        case PlyType::Int8:
            return double(get<std::int8_t>(at, little));
        case PlyType::Uint8:
            return double(get<std::uint8_t>(at, little));
        case PlyType::Int16:
            return double(get<std::int16_t>(at, little));
        case PlyType::Uint16:
            return double(get<std::uint16_t>(at, little));
        case PlyType::Int32:
            return double(get<std::int32_t>(at, little));
        case PlyType::Uint32:
            return double(get<std::uint32_t>(at, little));
        case PlyType::Float32:
            return double(get<float>(at, little));
        case PlyType::Float64:
            return get<double>(at, little);
        }
        return 0;
    }

    double ascii_value() {
        while (pos_ < data_.size() && std::isspace((unsigned char)data_[pos_])) ++pos_;
        const std::size_t begin = pos_;
        while (pos_ < data_.size() && !std::isspace((unsigned char)data_[pos_])) ++pos_;
        std::string_view text(data_.data() + begin, pos_ - begin);
        if (!text.empty() && text.front() == '+') text.remove_prefix(1);
        double v = 0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), v);
        if (text.empty()) fail("unexpected end of data (truncated file?)");
        if (error != std::errc() || end != text.data() + text.size())
            fail("bad number '" + std::string(text.substr(0, 40)) + "'");
        return v;
    }

    std::size_t list_count(const PlyProperty& p) {
        const double n = value(p.count_type);
        const std::size_t item = encoding_ == Encoding::Ascii ? 2 : ply_size(p.type);
        if (!(n >= 0) || n != std::floor(n) || n > double(remaining()) / double(item))
            fail("bad list length " + std::to_string(n) + " of property " + p.name);
        return std::size_t(n);
    }

    void skip_property(const PlyProperty& p) {
        const std::size_t n = p.list ? list_count(p) : 1;
        for (std::size_t k = 0; k < n; ++k) value(p.type);
    }

    void read_vertices(const PlyElement& element) {
        if (saw_vertices_) fail("second vertex element");
        saw_vertices_ = true;
        check_count(element);
        int axis_of[3] = {-1, -1, -1};
        for (std::size_t i = 0; i < element.properties.size(); ++i) {
            const PlyProperty& p = element.properties[i];
            for (int k = 0; k < 3; ++k)
                if (!p.list && p.name == std::string_view("xyz" + k, 1)) axis_of[k] = int(i);
        }
        if (axis_of[0] < 0 || axis_of[1] < 0 || axis_of[2] < 0)
            fail("vertex element lacks x, y or z");
        mesh_.positions.resize(element.count);
        for (glm::vec3& position : mesh_.positions)
            for (std::size_t i = 0; i < element.properties.size(); ++i) {
                const PlyProperty& p = element.properties[i];
                if (p.list) {
                    skip_property(p);
                    continue;
                }
                const double v = value(p.type);
                for (int k = 0; k < 3; ++k)
                    if (axis_of[k] == int(i)) position[k] = float(v);
            }
    }

    void read_faces(const PlyElement& element) {
        check_count(element);
        int indices_property = -1;
        for (std::size_t i = 0; i < element.properties.size(); ++i) {
            const PlyProperty& p = element.properties[i];
            if (p.list && (p.name == "vertex_indices" || p.name == "vertex_index"))
                indices_property = int(i);
        }
        if (indices_property < 0) fail("face element lacks a vertex_indices list");
        mesh_.indices.reserve(mesh_.indices.size() + 3 * element.count);
        for (std::size_t f = 0; f < element.count; ++f)
            for (std::size_t i = 0; i < element.properties.size(); ++i) {
                const PlyProperty& p = element.properties[i];
                if (int(i) != indices_property) {
                    skip_property(p);
                    continue;
                }
                const std::size_t n = list_count(p);
                if (n < 3) fail("face " + std::to_string(f) + " has fewer than 3 vertices");
                polygon_.clear();
                for (std::size_t k = 0; k < n; ++k) {
                    const double index = value(p.type);
                    if (!(index >= 0) || index >= 4294967295.0 || index != std::floor(index))
                        fail("bad vertex index " + std::to_string(index));
                    polygon_.push_back(std::uint32_t(index));
                }
                append_fan(polygon_, mesh_.indices);
            }
    }

    const std::string& data_;
    const std::string& path_;
    Encoding encoding_ = Encoding::Ascii;
    std::vector<PlyElement> elements_;
    std::size_t pos_ = 0;
    bool saw_vertices_ = false;
    Mesh mesh_;
    std::vector<std::uint32_t> polygon_;
};

std::string lower_extension(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    const std::size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
    std::string ext = path.substr(dot);
    for (char& c : ext) c = char(std::tolower((unsigned char)c));
    return ext;
}

} // namespace

MeshFormat mesh_format_from_path(const std::string& path) {
    const std::string ext = lower_extension(path);
    if (ext == ".stl") return MeshFormat::Stl;
    if (ext == ".obj") return MeshFormat::Obj;
    if (ext == ".ply") return MeshFormat::Ply;
    if (ext == ".off") return MeshFormat::Off;
    if (ext == ".vtk") return MeshFormat::Vtk;
    throw std::invalid_argument(path + ": unknown mesh format " +
                                (ext.empty() ? std::string("(no extension)") : "'" + ext + "'") +
                                "; use .stl, .obj, .ply, .off or .vtk");
}

void write_mesh(const Mesh& mesh, const std::string& path) {
    write_mesh(mesh, path, mesh_format_from_path(path));
}

void write_mesh(const Mesh& mesh, const std::string& path, MeshFormat format) {
    check_mesh_for_writing(mesh, path);
    write_file_atomically(path, [&](std::ostream& os) {
        switch (format) {
        case MeshFormat::Stl:
            write_stl(os, mesh, path);
            break;
        case MeshFormat::Obj:
            write_obj(os, mesh);
            break;
        case MeshFormat::Ply:
            write_ply(os, mesh, path);
            break;
        case MeshFormat::Off:
            write_off(os, mesh);
            break;
        case MeshFormat::Vtk:
            write_vtk(os, mesh);
            break;
        }
    });
}

Mesh read_mesh(const std::string& path) {
    const MeshFormat format = mesh_format_from_path(path);
    const std::string data = read_whole_file(path);
    Mesh mesh;
    switch (format) {
    case MeshFormat::Stl:
        mesh = read_stl(data, path);
        break;
    case MeshFormat::Obj:
        mesh = read_obj(data, path);
        break;
    case MeshFormat::Ply:
        mesh = PlyReader(data, path).read();
        break;
    case MeshFormat::Off:
        mesh = read_off(data, path);
        break;
    case MeshFormat::Vtk:
        mesh = VtkReader(data, path).read();
        break;
    }
    check_indices(mesh, path);
    return mesh;
}

} // namespace snert
