// Reading back the mesh files snert writes: the five layouts of src/io/mesh_io.cpp and nothing
// else, with every count checked against the file's size before anything is allocated.
#include "support/read_mesh.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "io/mesh_io.h"

namespace snert {
namespace {

constexpr std::uint32_t kNoVertex = 0xffffffffu;

// A little-endian value (STL and snert's PLY are little-endian whatever the machine).
template <class T> T get(const char* in) {
    std::array<char, sizeof(T)> bytes;
    std::memcpy(bytes.data(), in, sizeof(T));
    if constexpr (std::endian::native != std::endian::little)
        std::reverse(bytes.begin(), bytes.end());
    T value;
    std::memcpy(&value, bytes.data(), sizeof(T));
    return value;
}

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

// Text scanning with errors that name the file and the line.
class TextScanner {
  public:
    TextScanner(std::string_view data, const std::string& path) : data_(data), path_(path) {}

    std::size_t remaining() const { return data_.size() - pos_; }

    // Next whitespace-separated word; empty at the end of the data.
    std::string_view word() {
        while (pos_ < data_.size() && is_space(data_[pos_])) ++pos_;
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
        if (got != keyword)
            fail("expected '" + std::string(keyword) + "', found '" + std::string(got) + "'");
    }

    float parse_real(std::string_view text, const char* what) const {
        float value = 0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (text.empty() || error != std::errc() || end != text.data() + text.size())
            fail(bad(text, what));
        return value;
    }
    long long parse_integer(std::string_view text, const char* what) const {
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

  private:
    static bool is_space(char c) {
        return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
    }
    static std::string bad(std::string_view text, const char* what) {
        if (text.empty()) return std::string("unexpected end of file, expected ") + what;
        return std::string("bad ") + what + " '" + std::string(text.substr(0, 40)) + "'";
    }

    std::string_view data_;
    const std::string& path_;
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

// A face of `n` vertices where snert writes triangles only.
std::string not_a_triangle(std::size_t n) {
    return "face with " + std::to_string(n) + " vertices (snert writes triangles)";
}

// ---- STL ---------------------------------------------------------------------------------------

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

Mesh read_stl(const std::string& data, const std::string& path) {
    if (data.size() < 84)
        throw std::runtime_error(path + ": not an STL file (" + std::to_string(data.size()) +
                                 " bytes, shorter than the 84-byte binary header)");
    const std::uint64_t triangles = get<std::uint32_t>(data.data() + 80);
    if (84 + 50 * triangles != data.size())
        throw std::runtime_error(path + ": not a valid binary STL: the header announces " +
                                 std::to_string(triangles) + " triangles (" +
                                 std::to_string(84 + 50 * triangles) + " bytes) but the file has " +
                                 std::to_string(data.size()) + " bytes");
    std::vector<glm::vec3> corners(3 * triangles);
    for (std::size_t t = 0; t < triangles; ++t) {
        const char* facet = data.data() + 84 + 50 * t + 12; // after the normal
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k)
                corners[3 * t + std::size_t(j)][k] = get<float>(facet + 12 * j + 4 * k);
    }
    return weld(corners);
}

// ---- OBJ ---------------------------------------------------------------------------------------

Mesh read_obj(const std::string& data, const std::string& path) {
    TextScanner in(data, path);
    Mesh mesh;
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
            std::vector<std::uint32_t> face;
            for (std::string_view ref = next_word(rest); !ref.empty(); ref = next_word(rest)) {
                const long long i = in.parse_integer(ref, "face index"); // 1-based
                if (i < 1 || i > (long long)mesh.positions.size())
                    in.fail("face index " + std::to_string(i) + " out of range (" +
                            std::to_string(mesh.positions.size()) + " vertices so far)");
                face.push_back(std::uint32_t(i - 1));
            }
            if (face.size() < 3) in.fail("face with fewer than 3 vertices");
            if (face.size() > 3) in.fail(not_a_triangle(face.size()));
            mesh.indices.insert(mesh.indices.end(), face.begin(), face.end());
        }
    }
    return mesh;
}

// ---- OFF ---------------------------------------------------------------------------------------

Mesh read_off(const std::string& data, const std::string& path) {
    TextScanner in(data, path);
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
        in.skip_line();
    }
    mesh.indices.reserve(3 * faces);
    for (std::size_t f = 0; f < faces; ++f) {
        const std::size_t n = in.count("face size", 2);
        if (n != 3) in.fail(not_a_triangle(n));
        for (std::size_t k = 0; k < n; ++k) {
            const long long i = in.integer("vertex index");
            if (i < 0 || std::size_t(i) >= vertices)
                in.fail("vertex index " + std::to_string(i) + " out of range (" +
                        std::to_string(vertices) + " vertices)");
            mesh.indices.push_back(std::uint32_t(i));
        }
        in.skip_line();
    }
    return mesh;
}

// ---- Legacy VTK polydata, ASCII: POINTS, then POLYGONS with inline counts (the 3.0 layout) ----

Mesh read_vtk_with_cells(const std::string& data, const std::string& path, VtkCellData* cells_out) {
    TextScanner in(data, path);
    if (in.line().rfind("# vtk DataFile", 0) != 0) in.fail("not a legacy VTK file");
    in.skip_line(); // title
    const std::string_view encoding = in.line();
    if (encoding.rfind("ASCII", 0) != 0)
        in.fail("only ASCII legacy VTK files are read, not '" + std::string(encoding) + "'");
    in.expect("DATASET");
    const std::string_view dataset = in.word();
    if (dataset != "POLYDATA") in.fail("dataset '" + std::string(dataset) + "' is not POLYDATA");
    Mesh mesh;
    bool have_points = false;
    for (std::string_view section = in.word(); !section.empty(); section = in.word()) {
        if (section == "POINTS") {
            if (have_points) in.fail("second POINTS section");
            have_points = true;
            const std::size_t n = in.count("point count", 6);
            in.word(); // data type: numbers are read as text whatever it says
            mesh.positions.resize(n);
            for (glm::vec3& p : mesh.positions)
                for (int k = 0; k < 3; ++k) p[k] = in.real("point coordinate");
        } else if (section == "POLYGONS") {
            // `cells` cells, `size` numbers in all, each cell its point count then its points.
            const std::size_t cells = in.count("cell count", 2);
            const std::size_t size = in.count("cell array size", 2);
            std::size_t used = 0;
            for (std::size_t c = 0; c < cells; ++c) {
                const std::size_t n = in.count("cell size", 2);
                if (n != 3) in.fail(not_a_triangle(n));
                used += n + 1;
                if (used > size) in.fail("cells larger than the announced array size");
                for (std::size_t k = 0; k < n; ++k) {
                    const long long i = in.integer("point index");
                    if (i < 0 || std::size_t(i) >= mesh.positions.size())
                        in.fail("point index " + std::to_string(i) + " out of range (" +
                                std::to_string(mesh.positions.size()) + " points)");
                    mesh.indices.push_back(std::uint32_t(i));
                }
            }
            if (used != size) in.fail("cells smaller than the announced array size");
        } else if (section == "CELL_DATA") {
            // Float SCALARS with the default lookup table, one value per triangle each.
            const std::size_t n = in.count("cell data count", 2);
            if (n != mesh.triangle_count())
                in.fail("CELL_DATA " + std::to_string(n) + " for " +
                        std::to_string(mesh.triangle_count()) + " triangles");
            std::size_t arrays = 0;
            for (; in.remaining() > 0 && arrays < 64; ++arrays) {
                const std::string_view keyword = in.word();
                if (keyword.empty()) break;
                if (keyword != "SCALARS")
                    in.fail("unknown cell data '" + std::string(keyword) + "'");
                const std::string name(in.word());
                in.expect("float");
                in.expect("1");
                in.expect("LOOKUP_TABLE");
                in.expect("default");
                std::vector<float> values(n);
                for (float& v : values) v = in.real("cell value");
                if (cells_out && !cells_out->emplace(name, std::move(values)).second)
                    in.fail("cell array '" + name + "' twice");
            }
            if (arrays == 0) in.fail("CELL_DATA without arrays");
        } else {
            in.fail("unknown section '" + std::string(section) + "'");
        }
    }
    return mesh;
}

Mesh read_vtk(const std::string& data, const std::string& path) {
    return read_vtk_with_cells(data, path, nullptr);
}

// ---- PLY: the header snert writes, then the binary little-endian vertices and faces ---------

Mesh read_ply(const std::string& data, const std::string& path) {
    const auto fail = [&](const std::string& message) {
        throw std::runtime_error(path + ": " + message);
    };
    std::string_view rest(data);
    auto next_line = [&] {
        const std::size_t end = rest.find('\n');
        if (end == std::string_view::npos) fail("header has no end_header line");
        std::string_view line = rest.substr(0, end);
        rest.remove_prefix(end + 1);
        return line;
    };
    if (next_line() != "ply") fail("not a PLY file (it does not start with 'ply')");
    struct Element {
        std::string name;
        std::size_t count = 0;
        std::vector<std::string> properties; // "float x", "list uchar int vertex_indices"
    };
    std::vector<Element> elements;
    bool have_format = false;
    for (std::string_view line = next_line(); line != "end_header"; line = next_line()) {
        std::string_view words = line;
        const std::string_view keyword = next_word(words);
        if (keyword == "format") {
            if (words != " binary_little_endian 1.0")
                fail("only binary_little_endian 1.0 PLY is read, not '" + std::string(line) + "'");
            have_format = true;
        } else if (keyword == "element") {
            Element element;
            element.name = std::string(next_word(words));
            const std::string_view count = next_word(words);
            const auto [end, error] =
                std::from_chars(count.data(), count.data() + count.size(), element.count);
            if (count.empty() || error != std::errc() || end != count.data() + count.size())
                fail("bad count '" + std::string(count) + "' of element " + element.name);
            elements.push_back(std::move(element));
        } else if (keyword == "property") {
            if (elements.empty()) fail("property before any element");
            elements.back().properties.emplace_back(
                words.substr(std::min<std::size_t>(1, words.size())));
        } else if (keyword != "comment") {
            fail("unknown header line: " + std::string(line));
        }
    }
    if (!have_format) fail("header has no format line");

    const std::vector<std::string> vertex_layout = {"float x", "float y", "float z"};
    const std::vector<std::string> face_layout = {"list uchar int vertex_indices"};
    std::size_t pos = data.size() - rest.size();
    const auto check_count = [&](const Element& element, std::size_t bytes) {
        if (element.count > (data.size() - pos) / bytes)
            fail("element " + element.name + " announces " + std::to_string(element.count) +
                 " items, more than the " + std::to_string(data.size() - pos) +
                 " remaining bytes can hold (truncated file?)");
    };
    Mesh mesh;
    bool have_vertices = false, have_faces = false;
    for (const Element& element : elements) {
        if (element.name == "vertex" && !have_vertices && element.properties == vertex_layout) {
            have_vertices = true;
            check_count(element, 12);
            mesh.positions.resize(element.count);
            for (glm::vec3& p : mesh.positions)
                for (int k = 0; k < 3; ++k, pos += 4) p[k] = get<float>(data.data() + pos);
        } else if (element.name == "face" && !have_faces && element.properties == face_layout) {
            have_faces = true;
            check_count(element, 13);
            mesh.indices.reserve(3 * element.count);
            for (std::size_t f = 0; f < element.count; ++f) {
                const std::size_t n = std::uint8_t(data[pos++]);
                if (n != 3) fail("face " + std::to_string(f) + ": " + not_a_triangle(n));
                for (int k = 0; k < 3; ++k, pos += 4) {
                    const std::int32_t index = get<std::int32_t>(data.data() + pos);
                    if (index < 0) fail("bad vertex index " + std::to_string(index));
                    mesh.indices.push_back(std::uint32_t(index));
                }
            }
        } else {
            fail("element " + element.name + " is not laid out as snert writes it");
        }
    }
    if (!have_vertices) fail("no vertex element");
    if (!have_faces) fail("no face element");
    if (pos != data.size()) fail(std::to_string(data.size() - pos) + " bytes after the faces");
    return mesh;
}

} // namespace

VtkCellData read_vtk_cell_data(const std::string& path) {
    if (mesh_format_from_path(path) != MeshFormat::Vtk)
        throw std::invalid_argument(path + ": not a .vtk file");
    VtkCellData cells;
    read_vtk_with_cells(read_whole_file(path), path, &cells);
    return cells;
}

Mesh read_mesh(const std::string& path) {
    Mesh (*reader)(const std::string&, const std::string&) = nullptr;
    switch (mesh_format_from_path(path)) { // the writer's own rule; throws for other extensions
    case MeshFormat::Stl:
        reader = read_stl;
        break;
    case MeshFormat::Obj:
        reader = read_obj;
        break;
    case MeshFormat::Ply:
        reader = read_ply;
        break;
    case MeshFormat::Off:
        reader = read_off;
        break;
    case MeshFormat::Vtk:
        reader = read_vtk;
        break;
    case MeshFormat::Msh:
    case MeshFormat::Inp:
        // Read back by independent readers (meshio) in tests/cli/fe_formats_test.py.
        throw std::invalid_argument(path + ": read_mesh does not read the FE formats");
    }
    Mesh mesh = reader(read_whole_file(path), path);
    for (std::uint32_t i : mesh.indices)
        if (i >= mesh.positions.size())
            throw std::runtime_error(path + ": vertex index " + std::to_string(i) +
                                     " out of range (" + std::to_string(mesh.positions.size()) +
                                     " vertices)");
    return mesh;
}

} // namespace snert
