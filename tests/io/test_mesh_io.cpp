// Atomic writing and mesh files: success and every failure leave either the complete new file
// or the untouched old one and no temporary files; every mesh format round-trips exactly
// through tests/support/read_mesh.h, which refuses truncated and lying files naming the file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

#include "io/atomic_file.h"
#include "core/metrics.h"
#include "core/triangle_fields.h"
#include "io/mesh_io.h"
#include "support/read_mesh.h"

namespace snert {
namespace {

namespace fs = std::filesystem;

// A fresh folder per test, removed afterwards (tests run in parallel processes).
class TempFolder : public ::testing::Test {
  protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        folder_ =
            fs::temp_directory_path() / ("snert-" + std::string(info->test_suite_name()) + "-" +
                                         info->name() + "-" + std::to_string(::getpid()));
        fs::remove_all(folder_);
        fs::create_directories(folder_);
    }
    void TearDown() override {
        std::error_code ignored;
        fs::permissions(folder_, fs::perms::owner_all, fs::perm_options::add, ignored);
        fs::remove_all(folder_, ignored);
    }
    std::string path(const std::string& name) const { return (folder_ / name).string(); }
    std::vector<std::string> files() const {
        std::vector<std::string> names;
        for (const auto& entry : fs::directory_iterator(folder_))
            names.push_back(entry.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    }
    static std::string read_text(const std::string& file) {
        std::ifstream in(file, std::ios::binary);
        return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    }
    static void write_text(const std::string& file, const std::string& text) {
        std::ofstream(file, std::ios::binary) << text;
    }

    fs::path folder_;
};

// Expects `call` to throw E whose message contains every one of `parts`.
template <class E, class F> void expect_error(F&& call, std::initializer_list<std::string> parts) {
    try {
        call();
        ADD_FAILURE() << "no exception";
    } catch (const E& e) {
        for (const std::string& part : parts)
            EXPECT_NE(std::string(e.what()).find(part), std::string::npos)
                << "'" << e.what() << "' lacks '" << part << "'";
    }
}

// --- Atomic files ---------------------------------------------------------------------------

using AtomicFile = TempFolder;

TEST_F(AtomicFile, WritesAndReplaces) {
    const std::string target = path("out.txt");
    write_file_atomically(target, [](std::ostream& os) { os << "first"; });
    EXPECT_EQ(read_text(target), "first");
    write_file_atomically(target, [](std::ostream& os) { os << "second"; });
    EXPECT_EQ(read_text(target), "second");
    EXPECT_EQ(files(), std::vector<std::string>{"out.txt"});
}

TEST_F(AtomicFile, LargeBinaryContent) {
    std::string big(3 << 20, '\0');
    for (std::size_t i = 0; i < big.size(); ++i) big[i] = char(i * 7 + i / 1000);
    write_file_atomically(path("big.bin"), [&](std::ostream& os) {
        os.write(big.data(), 1000);                                      // buffered
        os.write(big.data() + 1000, std::streamsize(big.size() - 1000)); // direct
    });
    EXPECT_EQ(read_text(path("big.bin")), big);
}

TEST_F(AtomicFile, MissingFolder) {
    const std::string target = path("missing/out.txt");
    expect_error<std::runtime_error>(
        [&] { write_file_atomically(target, [](std::ostream& os) { os << "x"; }); },
        {target, std::strerror(ENOENT)});
    EXPECT_TRUE(files().empty());
}

TEST_F(AtomicFile, ParentIsAFile) {
    write_text(path("plain"), "not a folder");
    const std::string target = path("plain/out.txt");
    expect_error<std::runtime_error>(
        [&] { write_file_atomically(target, [](std::ostream& os) { os << "x"; }); },
        {target, std::strerror(ENOTDIR)});
    EXPECT_EQ(files(), std::vector<std::string>{"plain"});
}

TEST_F(AtomicFile, ReadOnlyFolder) {
    if (::geteuid() == 0) GTEST_SKIP() << "root may write into read-only folders";
    fs::permissions(folder_, fs::perms::owner_read | fs::perms::owner_exec);
    const std::string target = path("out.txt");
    expect_error<std::runtime_error>(
        [&] { write_file_atomically(target, [](std::ostream& os) { os << "x"; }); },
        {target, std::strerror(EACCES)});
    fs::permissions(folder_, fs::perms::owner_all);
    EXPECT_TRUE(files().empty());
}

TEST_F(AtomicFile, ThrowingWriterKeepsOldTarget) {
    const std::string target = path("out.txt");
    write_text(target, "old");
    EXPECT_THROW(write_file_atomically(target,
                                       [](std::ostream& os) {
                                           os << "partial new content";
                                           throw std::logic_error("writer failed");
                                       }),
                 std::logic_error);
    EXPECT_EQ(read_text(target), "old");
    EXPECT_EQ(files(), std::vector<std::string>{"out.txt"});
}

TEST_F(AtomicFile, FailedStreamIsAnError) {
    const std::string target = path("out.txt");
    write_text(target, "old");
    expect_error<std::runtime_error>(
        [&] {
            write_file_atomically(target, [](std::ostream& os) {
                os << "x";
                os.setstate(std::ios::badbit);
            });
        },
        {target});
    EXPECT_EQ(read_text(target), "old");
    EXPECT_EQ(files(), std::vector<std::string>{"out.txt"});
}

TEST_F(AtomicFile, TargetIsAFolder) {
    fs::create_directory(path("taken"));
    const std::string target = path("taken");
    expect_error<std::runtime_error>(
        [&] { write_file_atomically(target, [](std::ostream& os) { os << "x"; }); }, {target});
    EXPECT_EQ(files(), std::vector<std::string>{"taken"});
}

TEST_F(AtomicFile, PathProducerKeepsExtension) {
    const std::string target = path("image.png");
    std::string seen;
    write_path_atomically(target, [&](const std::string& temporary) {
        seen = temporary;
        std::ofstream(temporary, std::ios::binary) << "PNG bytes";
    });
    EXPECT_EQ(read_text(target), "PNG bytes");
    EXPECT_NE(seen, target);
    EXPECT_EQ(fs::path(seen).parent_path(), folder_);
    EXPECT_EQ(fs::path(seen).extension(), ".png");
    EXPECT_EQ(files(), std::vector<std::string>{"image.png"});
}

TEST_F(AtomicFile, PathProducerFailures) {
    const std::string target = path("image.png");
    write_text(target, "old");
    // Writes nothing (a C library that failed and only returned 0).
    expect_error<std::runtime_error>(
        [&] { write_path_atomically(target, [](const std::string&) {}); }, {target, "empty"});
    // Removes its file.
    expect_error<std::runtime_error>(
        [&] { write_path_atomically(target, [](const std::string& t) { fs::remove(t); }); },
        {target});
    // Throws after writing half.
    EXPECT_THROW(write_path_atomically(target,
                                       [](const std::string& t) {
                                           std::ofstream(t) << "half";
                                           throw std::runtime_error("encoder failed");
                                       }),
                 std::runtime_error);
    EXPECT_EQ(read_text(target), "old");
    EXPECT_EQ(files(), std::vector<std::string>{"image.png"});
    expect_error<std::runtime_error>(
        [&] {
            write_path_atomically(path("no/such/folder.png"),
                                  [](const std::string& t) { std::ofstream(t) << "x"; });
        },
        {path("no/such/folder.png"), std::strerror(ENOENT)});
}

// --- Mesh formats ---------------------------------------------------------------------------

// An octahedron with coordinates that need every digit: fractions, tiny and large values,
// negative zero. Outward wound.
Mesh awkward_octahedron() {
    Mesh m;
    const float s = 1.0f / 3.0f;
    m.positions = {{1.0f + 1e-7f, s, 0.0f}, {-1.0f, -0.0f, 1e-30f}, {s, 123456.78f, -s},
                   {0.1f, -2.5e5f, 0.2f},   {1e-3f, 0.0f, 7.25f},   {-0.3f, 1e-6f, -7.5f}};
    const std::uint32_t faces[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                       {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    for (const auto& f : faces) m.indices.insert(m.indices.end(), {f[0], f[1], f[2]});
    return m;
}

Mesh grid_mesh(int n) {
    Mesh m;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x)
            m.positions.push_back({x * 0.37f, y * 1.13f, std::sin(float(x + y)) * 0.5f});
    auto id = [n](int x, int y) { return std::uint32_t(y * (n + 1) + x); };
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            m.indices.insert(m.indices.end(), {id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y),
                                               id(x + 1, y + 1), id(x, y + 1)});
    return m;
}

// Same triangles with bit-identical corner positions (STL re-indexes the vertices).
void expect_same_triangles(const Mesh& expected, const Mesh& got) {
    ASSERT_EQ(got.indices.size(), expected.indices.size());
    for (std::size_t c = 0; c < expected.indices.size(); ++c) {
        const glm::vec3 a = expected.positions[expected.indices[c]];
        const glm::vec3 b = got.positions[got.indices[c]];
        ASSERT_TRUE(a == b || (a + 0.0f) == (b + 0.0f)) << "corner " << c;
    }
}

struct FormatCase {
    const char* extension;
    bool indexed; // keeps the vertex list as it is (all but STL)
};
constexpr FormatCase kFormats[] = {
    {".stl", false}, {".obj", true}, {".ply", true}, {".off", true}, {".vtk", true}};

using MeshIo = TempFolder;

TEST(MeshFormat, FromExtension) {
    EXPECT_EQ(mesh_format_from_path("a.stl"), MeshFormat::Stl);
    EXPECT_EQ(mesh_format_from_path("dir.x/A.STL"), MeshFormat::Stl);
    EXPECT_EQ(mesh_format_from_path("m.Obj"), MeshFormat::Obj);
    EXPECT_EQ(mesh_format_from_path("m.tar.ply"), MeshFormat::Ply);
    EXPECT_EQ(mesh_format_from_path("m.off"), MeshFormat::Off);
    EXPECT_EQ(mesh_format_from_path("m.VTK"), MeshFormat::Vtk);
    EXPECT_EQ(mesh_format_from_path("fe/m.msh"), MeshFormat::Msh);
    EXPECT_EQ(mesh_format_from_path("m.INP"), MeshFormat::Inp);
    expect_error<std::invalid_argument>([] { mesh_format_from_path("shape.stp"); },
                                        {"shape.stp", ".stp", ".stl", ".vtk, .msh or .inp"});
    expect_error<std::invalid_argument>([] { mesh_format_from_path("dir.stl/shape"); },
                                        {"dir.stl/shape", "no extension"});
}

TEST_F(MeshIo, RoundTripEveryFormat) {
    for (const Mesh& mesh : {awkward_octahedron(), grid_mesh(70)}) // 9800 triangles: batches
        for (const FormatCase& format : kFormats) {
            SCOPED_TRACE(format.extension);
            const std::string file = path(std::string("mesh") + format.extension);
            write_mesh(mesh, file);
            const Mesh back = read_mesh(file);
            if (format.indexed) {
                ASSERT_EQ(back.positions.size(), mesh.positions.size());
                for (std::size_t v = 0; v < mesh.positions.size(); ++v)
                    ASSERT_EQ(back.positions[v], mesh.positions[v]) << "vertex " << v;
                EXPECT_EQ(back.indices, mesh.indices);
            } else {
                EXPECT_EQ(back.positions.size(), mesh.positions.size()); // welded again
                expect_same_triangles(mesh, back);
            }
            EXPECT_EQ(files().size(), 1u);
            fs::remove(file);
        }
}

TEST_F(MeshIo, StlRoundTripIsWatertightAgain) {
    const std::string file = path("closed.stl");
    write_mesh(awkward_octahedron(), file);
    const Topology t = topology(read_mesh(file));
    EXPECT_TRUE(t.watertight);
    EXPECT_TRUE(t.oriented);
    EXPECT_EQ(t.euler, 2);
}

TEST_F(MeshIo, BinaryLayouts) {
    Mesh m;
    m.positions = {{0, 0, 0}, {2, 0, 0}, {0, 3, 0}};
    m.indices = {0, 1, 2};
    write_mesh(m, path("t.stl"));
    const std::string stl = read_text(path("t.stl"));
    ASSERT_EQ(stl.size(), 84u + 50u);
    EXPECT_NE(stl.rfind("solid", 0), 0u); // would mark ASCII STL
    auto f32 = [&](std::size_t at) {
        float v;
        std::memcpy(&v, stl.data() + at, 4);
        return v;
    };
    EXPECT_EQ(stl[80], 1);         // little-endian count
    EXPECT_EQ(f32(84 + 8), 1.0f);  // unit normal +z
    EXPECT_EQ(f32(84 + 24), 2.0f); // second corner x

    write_mesh(m, path("t.ply"));
    const std::string ply = read_text(path("t.ply"));
    EXPECT_EQ(ply.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);
    const std::size_t body = ply.find("end_header\n") + 11;
    EXPECT_EQ(ply.size(), body + 3 * 12 + 13);
    EXPECT_EQ(ply[body + 36], 3); // uchar vertex count of the face
}

TEST_F(MeshIo, TruncatedFilesFail) {
    const Mesh mesh = grid_mesh(6);
    for (const FormatCase& format : kFormats) {
        if (std::string(format.extension) == ".obj") continue; // no counts: see LyingObj
        SCOPED_TRACE(format.extension);
        const std::string file = path(std::string("cut") + format.extension);
        write_mesh(mesh, file);
        const std::string whole = read_text(file);
        for (double keep : {0.0, 0.1, 0.5, 0.8}) {
            SCOPED_TRACE(keep);
            write_text(file, whole.substr(0, std::size_t(double(whole.size()) * keep)));
            expect_error<std::runtime_error>([&] { read_mesh(file); }, {file});
        }
        write_text(file, whole.substr(0, whole.size() - 20));
        expect_error<std::runtime_error>([&] { read_mesh(file); }, {file});
    }
}

TEST_F(MeshIo, LyingCountsFailBeforeAllocating) {
    std::string stl(84 + 50, '\0');
    stl[80] = stl[81] = stl[82] = char(0xff); // 16 million triangles announced
    write_text(path("lie.stl"), stl);
    expect_error<std::runtime_error>([&] { read_mesh(path("lie.stl")); },
                                     {path("lie.stl"), "16777215"});
    write_text(path("lie.ply"), "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
                                "property float x\nproperty float y\nproperty float z\n"
                                "end_header\n0123456789");
    expect_error<std::runtime_error>([&] { read_mesh(path("lie.ply")); },
                                     {path("lie.ply"), "4000000000"});
    write_text(path("lie.off"), "OFF\n1000000000 1 0\n0 0 0\n");
    expect_error<std::runtime_error>([&] { read_mesh(path("lie.off")); }, {path("lie.off")});
    write_text(path("lie.vtk"), "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\n"
                                "POINTS 3 float\n0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n3 0 1 7\n");
    expect_error<std::runtime_error>([&] { read_mesh(path("lie.vtk")); },
                                     {path("lie.vtk"), "line 8", "7 out of range"});
}

TEST_F(MeshIo, LyingObj) {
    write_text(path("bad.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n");
    expect_error<std::runtime_error>([&] { read_mesh(path("bad.obj")); },
                                     {path("bad.obj"), "line 5", "index 4"});
    write_text(path("bad.obj"), "v 0 0 0\nv 1 zero 0\n");
    expect_error<std::runtime_error>([&] { read_mesh(path("bad.obj")); }, {"line 2", "zero"});
    write_text(path("bad.obj"), "v 0 0 0\nv 1 0 0\nf 1 2\n");
    expect_error<std::runtime_error>([&] { read_mesh(path("bad.obj")); }, {"fewer than 3"});
}

TEST_F(MeshIo, GarbageAndMissingFiles) {
    for (const char* name : {"g.stl", "g.ply", "g.off", "g.vtk"}) {
        write_text(path(name), "\x01\x02 this is not a mesh at all \xff\n");
        expect_error<std::runtime_error>([&] { read_mesh(path(name)); }, {path(name)});
    }
    expect_error<std::runtime_error>([&] { read_mesh(path("none.obj")); },
                                     {path("none.obj"), std::strerror(ENOENT)});
    fs::create_directory(path("folder.stl"));
    expect_error<std::runtime_error>([&] { read_mesh(path("folder.stl")); },
                                     {path("folder.stl"), "not a regular file"});
}

TEST_F(MeshIo, WriteFailuresLeaveNothing) {
    const Mesh mesh = awkward_octahedron();
    expect_error<std::runtime_error>([&] { write_mesh(mesh, path("missing/m.stl")); },
                                     {path("missing/m.stl")});
    Mesh bad = mesh;
    bad.indices.back() = 99;
    expect_error<std::invalid_argument>([&] { write_mesh(bad, path("bad.obj")); },
                                        {path("bad.obj"), "99"});
    expect_error<std::invalid_argument>([&] { write_mesh(mesh, path("m.xyz")); }, {"m.xyz"});
    EXPECT_TRUE(files().empty());
}

// --- The FE formats ---------------------------------------------------------------------------

// Two triangles whose text is known: one coordinate (0.1f) is not a short double.
Mesh two_triangles() {
    Mesh m;
    m.positions = {{0, 0, 0}, {2, 0, 0}, {0, 3, 0}, {0.1f, 0, 1}};
    m.indices = {0, 1, 2, 0, 3, 1};
    return m;
}

TEST_F(MeshIo, GmshLayout) {
    MeshWriteOptions options;
    options.name = "snert";
    write_mesh(two_triangles(), path("m.msh"), options);
    EXPECT_EQ(read_text(path("m.msh")), "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
                                        "$PhysicalNames\n1\n2 1 \"snert\"\n$EndPhysicalNames\n"
                                        "$Entities\n0 0 1 0\n1 0 0 0 2 3 1 1 1 0\n$EndEntities\n"
                                        "$Nodes\n1 4 1 4\n2 1 0 4\n1\n2\n3\n4\n"
                                        "0 0 0\n2 0 0\n0 3 0\n0.10000000149011612 0 1\n"
                                        "$EndNodes\n$Elements\n1 2 1 2\n2 1 2 2\n"
                                        "1 1 2 3\n2 1 4 2\n$EndElements\n");
    // No triangles: empty blocks, still a file Gmsh reads.
    write_mesh(Mesh{}, path("empty.msh"));
    const std::string empty = read_text(path("empty.msh"));
    EXPECT_NE(empty.find("$Nodes\n0 0 0 0\n$EndNodes\n$Elements\n0 0 0 0\n$EndElements\n"),
              std::string::npos);
}

TEST_F(MeshIo, AbaqusLayoutAndElementType) {
    MeshWriteOptions options;
    options.name = "mc";
    write_mesh(two_triangles(), path("s3.inp"), options);
    const std::string s3 = read_text(path("s3.inp"));
    EXPECT_EQ(s3, "*HEADING\nsurface mesh mc written by snert\n*NODE\n"
                  "1, 0, 0, 0\n2, 2, 0, 0\n3, 0, 3, 0\n4, 0.10000000149011612, 0, 1\n"
                  "*ELEMENT, TYPE=S3, ELSET=mc\n1, 1, 2, 3\n2, 1, 4, 2\n");
    options.abaqus_element = AbaqusElement::Sfm3d3;
    write_mesh(two_triangles(), path("sfm.inp"), options);
    std::string expected = s3;
    expected.replace(expected.find("TYPE=S3"), 7, "TYPE=SFM3D3");
    EXPECT_EQ(read_text(path("sfm.inp")), expected); // only the element type differs
    EXPECT_EQ(parse_name<AbaqusElement>("sfm3d3"), AbaqusElement::Sfm3d3);
    EXPECT_EQ(name_of(AbaqusElement::S3), "s3");
}

TEST_F(MeshIo, SurfaceNamesAreMadeSafe) {
    MeshWriteOptions options;
    for (const auto& [given, written] :
         {std::pair<std::string, std::string>{"my part-1", "my_part_1"},
          {"3d", "surface_3d"},
          {"", "surface"}}) {
        options.name = given;
        write_mesh(two_triangles(), path("n.inp"), options);
        EXPECT_NE(read_text(path("n.inp")).find("ELSET=" + written + "\n"), std::string::npos)
            << given;
    }
}

TEST_F(MeshIo, VtkCellDataForParaView) {
    const Mesh mesh = grid_mesh(70); // several output buffers
    MeshWriteOptions options;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t)
        options.distance.push_back(0.001f * float(t % 997));
    write_mesh(mesh, path("c.vtk"), options);
    const VtkCellData cells = read_vtk_cell_data(path("c.vtk"));
    const TriangleMeasures fields = triangle_measures(mesh);
    ASSERT_EQ(cells.size(), 4u);
    EXPECT_EQ(cells.at("quality"), fields.quality); // exact: shortest float text
    EXPECT_EQ(cells.at("min_angle"), fields.min_angle);
    EXPECT_EQ(cells.at("max_angle"), fields.max_angle);
    EXPECT_EQ(cells.at("distance"), options.distance);
    EXPECT_EQ(read_mesh(path("c.vtk")).indices, mesh.indices);

    write_mesh(mesh, path("plain.vtk")); // no distance given: no such array
    EXPECT_EQ(read_vtk_cell_data(path("plain.vtk")).count("distance"), 0u);
    EXPECT_EQ(read_vtk_cell_data(path("plain.vtk")).size(), 3u);

    options.distance.pop_back();
    expect_error<std::invalid_argument>([&] { write_mesh(mesh, path("short.vtk"), options); },
                                        {path("short.vtk"), "distances for"});
    EXPECT_FALSE(fs::exists(path("short.vtk")));
}

TEST_F(MeshIo, FeFormatsFailAtomically) {
    const Mesh mesh = awkward_octahedron();
    for (const char* name : {"m.msh", "m.inp", "m.vtk"}) {
        expect_error<std::runtime_error>(
            [&] { write_mesh(mesh, path(std::string("missing/") + name)); },
            {path(std::string("missing/") + name)});
        fs::create_directory(path(std::string("dir-") + name));
        expect_error<std::runtime_error>(
            [&] { write_mesh(mesh, path(std::string("dir-") + name)); },
            {path(std::string("dir-") + name)});
        // An old file stays as it was when the new one cannot be written.
        write_text(path(name), "old");
        Mesh bad = mesh;
        bad.indices.back() = 99;
        expect_error<std::invalid_argument>([&] { write_mesh(bad, path(name)); }, {"99"});
        EXPECT_EQ(read_text(path(name)), "old");
    }
    // Only what the test made: the three folders and the three old files, no temporary file.
    EXPECT_EQ(files().size(), 6u);
}

// read_mesh reads what snert writes and nothing else: files from other tools are refused, not
// misread.
TEST_F(MeshIo, OtherWritersVariantsAreRefused) {
    write_text(path("a.stl"), "solid two\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                              "vertex 1 0 0\nvertex 1 1 0\nendloop\nendfacet\nendsolid two\n");
    expect_error<std::runtime_error>([&] { read_mesh(path("a.stl")); },
                                     {path("a.stl"), "not a valid binary STL"});
    write_text(path("a.ply"), "ply\nformat ascii 1.0\nelement vertex 0\nend_header\n");
    expect_error<std::runtime_error>([&] { read_mesh(path("a.ply")); },
                                     {path("a.ply"), "only binary_little_endian"});
    write_text(path("q.off"), "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n");
    expect_error<std::runtime_error>([&] { read_mesh(path("q.off")); },
                                     {path("q.off"), "line 7", "snert writes triangles"});
    write_text(path("n.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n");
    expect_error<std::runtime_error>([&] { read_mesh(path("n.obj")); }, {"line 4", "-3"});
}

} // namespace
} // namespace snert
