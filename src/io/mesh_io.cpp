// Mesh files: binary STL, Wavefront OBJ, binary PLY, OFF, legacy VTK polydata, Gmsh MSH 4.1 and
// Abaqus INP, written atomically.
//
// This work is based on the published format descriptions: the binary STL layout (80-byte
// header, uint32 count, 50 bytes per facet), Paul Bourke's PLY and OFF notes, the Wavefront OBJ
// appendix, the VTK file formats document (legacy 3.0 polydata), the Gmsh reference manual's
// "MSH file format" (version 4.1) and the Abaqus keywords reference (*NODE, *ELEMENT). Numbers are
// written with std::to_chars, the shortest text that reads back to the same float, so text formats
// round-trip exactly and independently of the locale. (The tests read the files back with
// tests/support/read_mesh.h.)
#include "mesh_io.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "atomic_file.h"
#include "core/metrics.h"

namespace snert {
namespace {

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

// ---------------------------------------------------------------------------------------------
// Writing.

void check_mesh_for_writing(const Mesh& mesh, const std::string& path) {
    if (mesh.indices.size() % 3 != 0)
        throw std::invalid_argument(path + ": mesh index count is not a multiple of 3");
    if (const auto i = first_index_out_of_range(mesh))
        throw std::invalid_argument(path + ": mesh index " + std::to_string(*i) +
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

// Float values as one VTK cell array (SCALARS with the default lookup table), 9 to a line.
void write_vtk_cell_array(TextOut& out, std::string_view name, const std::vector<float>& values) {
    out << "SCALARS " << name << " float 1\nLOOKUP_TABLE default\n";
    for (std::size_t t = 0; t < values.size(); ++t)
        out << values[t] << ((t % 9 == 8 || t + 1 == values.size()) ? '\n' : ' ');
}

// Legacy 3.0 layout (POLYGONS with counts inline), which every VTK version and ParaView reads,
// with per-triangle cell data for ParaView to colour by.
void write_vtk(std::ostream& os, const Mesh& mesh, const MeshWriteOptions& options,
               const std::string& name) {
    TextOut out(os);
    out << "# vtk DataFile Version 3.0\nsnert mesh " << name << "\nASCII\nDATASET POLYDATA\n"
        << "POINTS " << mesh.positions.size() << " float\n";
    for (const glm::vec3& p : mesh.positions) out << p << '\n';
    out << "POLYGONS " << mesh.triangle_count() << ' ' << 4 * mesh.triangle_count() << '\n';
    write_counted_triangles(out, mesh.indices);
    if (mesh.triangle_count() == 0) return;
    const TriangleMeasures fields = triangle_measures(mesh);
    out << "CELL_DATA " << mesh.triangle_count() << '\n';
    write_vtk_cell_array(out, "quality", fields.quality);
    write_vtk_cell_array(out, "min_angle", fields.min_angle);
    write_vtk_cell_array(out, "max_angle", fields.max_angle);
    if (!options.distance.empty()) write_vtk_cell_array(out, "distance", options.distance);
}

// Gmsh 4.1: every node on one discrete surface (entity 2/1) carrying physical group 1, the
// triangles (element type 2) in one block on it, so Gmsh can classify the surface and fill it.
void write_msh(std::ostream& os, const Mesh& mesh, const std::string& name) {
    TextOut out(os);
    const std::size_t nodes = mesh.positions.size(), triangles = mesh.triangle_count();
    const Bounds box = mesh_bounds(mesh);
    out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
        << "$PhysicalNames\n1\n2 1 \"" << name << "\"\n$EndPhysicalNames\n"
        << "$Entities\n0 0 1 0\n1 " << double(box.min.x) << ' ' << double(box.min.y) << ' '
        << double(box.min.z) << ' ' << double(box.max.x) << ' ' << double(box.max.y) << ' '
        << double(box.max.z) << " 1 1 0\n$EndEntities\n";
    // numEntityBlocks numNodes minNodeTag maxNodeTag, then the block header and the tags.
    out << "$Nodes\n"
        << std::size_t(nodes > 0) << ' ' << nodes << ' ' << std::size_t(nodes > 0) << ' ' << nodes
        << '\n';
    if (nodes) {
        out << "2 1 0 " << nodes << '\n';
        for (std::size_t v = 1; v <= nodes; ++v) out << v << '\n';
        for (const glm::vec3& p : mesh.positions)
            out << double(p.x) << ' ' << double(p.y) << ' ' << double(p.z) << '\n';
    }
    out << "$EndNodes\n$Elements\n"
        << std::size_t(triangles > 0) << ' ' << triangles << ' ' << std::size_t(triangles > 0)
        << ' ' << triangles << '\n';
    if (triangles) {
        out << "2 1 2 " << triangles << '\n';
        const std::vector<std::uint32_t>& i = mesh.indices;
        for (std::size_t t = 0; t < triangles; ++t) // tags count from 1
            out << t + 1 << ' ' << i[3 * t] + 1ull << ' ' << i[3 * t + 1] + 1ull << ' '
                << i[3 * t + 2] + 1ull << '\n';
    }
    out << "$EndElements\n";
}

// Abaqus input without parts (a flat model): nodes and elements numbered from 1, the triangles
// in one element set. Lines stay far under Abaqus' 256 characters.
void write_inp(std::ostream& os, const Mesh& mesh, const MeshWriteOptions& options,
               const std::string& name) {
    TextOut out(os);
    out << "*HEADING\nsurface mesh " << name << " written by snert\n*NODE\n";
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const glm::vec3 p = mesh.positions[v];
        out << v + 1 << ", " << double(p.x) << ", " << double(p.y) << ", " << double(p.z) << '\n';
    }
    const std::string type = options.abaqus_element == AbaqusElement::S3 ? "S3" : "SFM3D3";
    out << "*ELEMENT, TYPE=" << type << ", ELSET=" << name << '\n';
    const std::vector<std::uint32_t>& i = mesh.indices;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t)
        out << t + 1 << ", " << i[3 * t] + 1ull << ", " << i[3 * t + 1] + 1ull << ", "
            << i[3 * t + 2] + 1ull << '\n';
}

// A name every format accepts unquoted: a letter first, then letters, digits and '_'.
std::string format_safe_name(const std::string& name) {
    if (name.empty()) return "surface";
    std::string safe = std::isalpha((unsigned char)name.front()) ? "" : "surface_";
    for (char c : name) safe.push_back(std::isalnum((unsigned char)c) || c == '_' ? c : '_');
    return safe;
}

std::string lower_extension(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    const std::size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
    std::string ext = path.substr(dot);
    for (char& c : ext) c = char(std::tolower((unsigned char)c));
    return ext;
}

} // namespace

namespace {
constexpr Named<AbaqusElement> kAbaqusElements[] = {
    {AbaqusElement::S3, "s3", "S3 (shell)"},
    {AbaqusElement::Sfm3d3, "sfm3d3", "SFM3D3 (surface)"},
};
} // namespace

std::span<const Named<AbaqusElement>> name_table(AbaqusElement) {
    return kAbaqusElements;
}

const std::vector<std::string> kMeshExtensions = {".stl", ".obj", ".ply", ".off",
                                                  ".vtk", ".msh", ".inp"};

MeshFormat mesh_format_from_path(const std::string& path) {
    const std::string ext = lower_extension(path);
    for (std::size_t k = 0; k < kMeshExtensions.size(); ++k)
        if (ext == kMeshExtensions[k]) return MeshFormat(k);
    std::string choices;
    for (std::size_t k = 0; k < kMeshExtensions.size(); ++k) {
        choices.append(k == 0 ? "" : k + 1 == kMeshExtensions.size() ? " or " : ", ");
        choices.append(kMeshExtensions[k]);
    }
    throw std::invalid_argument(path + ": unknown mesh format " +
                                (ext.empty() ? std::string("(no extension)") : "'" + ext + "'") +
                                "; use " + choices);
}

void write_mesh(const Mesh& mesh, const std::string& path, const MeshWriteOptions& options) {
    write_mesh(mesh, path, mesh_format_from_path(path), options);
}

void write_mesh(const Mesh& mesh, const std::string& path, MeshFormat format,
                const MeshWriteOptions& options) {
    check_mesh_for_writing(mesh, path);
    if (!options.distance.empty() && options.distance.size() != mesh.triangle_count())
        throw std::invalid_argument(path + ": " + std::to_string(options.distance.size()) +
                                    " distances for " + std::to_string(mesh.triangle_count()) +
                                    " triangles");
    const std::string name = format_safe_name(options.name);
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
            write_vtk(os, mesh, options, name);
            break;
        case MeshFormat::Msh:
            write_msh(os, mesh, name);
            break;
        case MeshFormat::Inp:
            write_inp(os, mesh, options, name);
            break;
        }
    });
}

} // namespace snert
