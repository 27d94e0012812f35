// Loading real volumes: every format from the shared test data (values checked against
// numbers decoded independently from the files' bytes and against the data's SOURCES.md),
// world geometry, and bad files that must fail with a clear one-line error and no crash.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include <zlib.h>

#include "core/volume_stats.h"
#include "io/load_volume.h"
#include "core/marching_cubes.h"
#include "core/mesh.h"
#include "io/volume_headers.h"

namespace fs = std::filesystem;
using namespace snert;

namespace {

const std::string kData = SNERT_DATA_DIR;

#define REQUIRE_DATA()                                                                             \
    if (!fs::is_directory(kData))                                                                  \
    GTEST_SKIP() << "test volumes not found in " << kData << " (set SNERT_DATA_DIR)"

std::string data(const std::string& relative) {
    return kData + "/" + relative;
}

// A fresh folder under the system's temporary directory, removed with everything in it.
struct TempDir {
    fs::path path;
    TempDir() {
        std::string pattern = (fs::temp_directory_path() / "snert-load-XXXXXX").string();
        path = ::mkdtemp(pattern.data());
    }
    ~TempDir() {
        std::error_code ignored;
        fs::remove_all(path, ignored);
    }
    std::string file(const std::string& name) const { return (path / name).string(); }
};

using Bytes = std::vector<std::uint8_t>;

Bytes read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return Bytes(std::istreambuf_iterator<char>(in), {});
}

void write_bytes(const std::string& path, const Bytes& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

Bytes text_bytes(const std::string& text) {
    return Bytes(text.begin(), text.end());
}

Bytes concat(Bytes a, const Bytes& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

// zlib with gzip framing (window bits 15 + 16).
Bytes gzip(const Bytes& in) {
    z_stream z{};
    deflateInit2(&z, 6, Z_DEFLATED, 31, 8, Z_DEFAULT_STRATEGY);
    Bytes out(deflateBound(&z, uLong(in.size())) + 64);
    z.next_in = const_cast<Bytef*>(in.data());
    z.avail_in = uInt(in.size());
    z.next_out = out.data();
    z.avail_out = uInt(out.size());
    deflate(&z, Z_FINISH);
    out.resize(z.total_out);
    deflateEnd(&z);
    return out;
}

Bytes gunzip(const Bytes& in) {
    z_stream z{};
    inflateInit2(&z, 15 + 32);
    Bytes out;
    unsigned char chunk[1 << 16];
    z.next_in = const_cast<Bytef*>(in.data());
    z.avail_in = uInt(in.size());
    int status = Z_OK;
    while (status == Z_OK) {
        z.next_out = chunk;
        z.avail_out = sizeof chunk;
        status = inflate(&z, Z_NO_FLUSH);
        out.insert(out.end(), chunk, chunk + (sizeof chunk - z.avail_out));
    }
    inflateEnd(&z);
    return out;
}

template <class T> T load_le(const Bytes& b, std::size_t offset) {
    T v;
    std::memcpy(&v, b.data() + offset, sizeof v);
    return v;
}

template <class T> Bytes as_bytes(const std::vector<T>& values) {
    Bytes b(values.size() * sizeof(T));
    std::memcpy(b.data(), values.data(), b.size());
    return b;
}

// The message of the exception `f` throws (E or a subclass); a test failure when none.
template <class E = std::exception> std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const E& e) {
        return e.what();
    }
    ADD_FAILURE() << "expected an exception";
    return "";
}

// A clear error: one line, starting with the file it is about, saying `what`.
void expect_clear_error(const std::string& message, const std::string& file,
                        const std::string& what) {
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_EQ(message.rfind(file, 0), 0u)
        << "message should start with " << file << ": " << message;
    EXPECT_NE(message.find(what), std::string::npos)
        << "message should say '" << what << "': " << message;
}

double sum_of(const Volume& v) {
    return std::accumulate(v.samples.begin(), v.samples.end(), 0.0);
}

void expect_vec3_near(glm::vec3 actual, glm::vec3 expected, float tolerance) {
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(actual[a], expected[a], tolerance) << "axis " << a;
}

std::string nrrd_header(const std::string& type, const std::string& sizes,
                        const std::string& encoding, const std::string& extra = "") {
    return "NRRD0004\ntype: " + type + "\ndimension: 3\nsizes: " + sizes +
           "\nendian: little\nencoding: " + encoding + "\n" + extra + "\n";
}

} // namespace

// ---- Each format, real files -------------------------------------------------------------------

TEST(LoadVolume, NrrdFlairKeepsObliqueGeometry) {
    REQUIRE_DATA();
    const LoadedVolume lv = open_volume(data("FLAIR.nrrd"));
    const Volume& v = lv.volume;
    EXPECT_EQ(lv.info.format, "NRRD");
    EXPECT_EQ(lv.info.scalar_type, "uint8");
    EXPECT_EQ(v.dims, glm::ivec3(124, 160, 140));
    expect_vec3_near(v.spacing, glm::vec3(1.0f), 1e-5f);
    expect_vec3_near(v.origin, {64.8982f, 110.431f, -27.9255f}, 1e-3f);
    // The header's `space directions` (LPS), unit length: kept, not snapped to the axes.
    expect_vec3_near(v.direction[0], {-0.993592f, 0.0497049f, -0.101510f}, 1e-5f);
    expect_vec3_near(v.direction[1], {-0.0160050f, -0.950937f, -0.308971f}, 1e-5f);
    expect_vec3_near(v.direction[2], {-0.111887f, -0.305367f, 0.945639f}, 1e-5f);
    EXPECT_EQ(v.at(62, 80, 70), 170.0f);
    EXPECT_EQ(v.at(0, 0, 0), 0.0f);
    EXPECT_EQ(v.at(63, 106, 55), 255.0f);
    EXPECT_EQ(sum_of(v), 115231646.0);
    EXPECT_EQ(lv.info.range.min, 0.0f);
    EXPECT_EQ(lv.info.range.max, 255.0f);
}

TEST(LoadVolume, MetaImageHeadMr) {
    REQUIRE_DATA();
    const LoadedVolume lv = open_volume(data("HeadMRVolume.mhd"));
    const Volume& v = lv.volume;
    EXPECT_EQ(lv.info.format, "MetaImage");
    EXPECT_EQ(lv.info.scalar_type, "uint8");
    EXPECT_EQ(v.dims, glm::ivec3(48, 62, 42));
    expect_vec3_near(v.spacing, glm::vec3(4.0f), 0.0f);
    expect_vec3_near(v.origin, glm::vec3(0.0f), 0.0f);
    EXPECT_EQ(v.direction, glm::mat3(1.0f));
    EXPECT_EQ(v.at(0, 0, 0), 1.0f);
    EXPECT_EQ(v.at(24, 31, 21), 79.0f);
    EXPECT_EQ(v.at(16, 41, 10), 86.0f);
    EXPECT_EQ(v.at(28, 39, 22), 255.0f);
    EXPECT_EQ(sum_of(v), 3058332.0);
    // Every sample equals the byte in the .raw file (uint8, no header).
    const Bytes raw = read_bytes(data("HeadMRVolume.raw"));
    ASSERT_EQ(raw.size(), v.samples.size());
    for (std::size_t i = 0; i < raw.size(); ++i) ASSERT_EQ(v.samples[i], float(raw[i])) << i;
}

TEST(LoadVolume, VtkCarotid) {
    REQUIRE_DATA();
    const LoadedVolume lv = open_volume(data("carotid.vtk"));
    const Volume& v = lv.volume;
    EXPECT_EQ(lv.info.format, "VTK");
    EXPECT_EQ(lv.info.scalar_type, "float32");
    EXPECT_EQ(v.dims, glm::ivec3(76, 49, 45));
    expect_vec3_near(v.spacing, glm::vec3(1.0f), 0.0f);
    expect_vec3_near(v.origin, {100.0f, 80.0f, 1.0f}, 0.0f);
    EXPECT_EQ(v.at(0, 0, 0), 57.0f);
    EXPECT_EQ(v.at(38, 24, 22), 162.0f);
    EXPECT_EQ(v.at(25, 32, 11), 81.0f);
    EXPECT_EQ(v.at(75, 48, 44), 128.0f);
    EXPECT_EQ(v.at(50, 6, 22), 580.0f);
    EXPECT_EQ(sum_of(v), 16598647.0);
    EXPECT_EQ(lv.info.range.max, 580.0f);
    EXPECT_EQ(lv.info.nonfinite, 0u);
}

TEST(LoadVolume, NiftiCtAbdomenInLps) {
    REQUIRE_DATA();
    const LoadedVolume lv = open_volume(data("totalseg_ct_abdomen/example_ct_sm.nii.gz"));
    const Volume& v = lv.volume;
    EXPECT_EQ(lv.info.format, "NIfTI");
    EXPECT_EQ(lv.info.scalar_type, "int16");
    EXPECT_EQ(v.dims, glm::ivec3(122, 101, 30));
    expect_vec3_near(v.spacing, glm::vec3(3.0f), 0.0f);
    // sform (RAS) translation (-177.956, 11.319, 94.302) becomes LPS (177.956, -11.319, 94.302).
    expect_vec3_near(v.origin, {177.956f, -11.319f, 94.3018f}, 1e-3f);
    expect_vec3_near(v.direction[0], {-1, 0, 0}, 1e-6f);
    expect_vec3_near(v.direction[1], {0, -1, 0}, 1e-6f);
    expect_vec3_near(v.direction[2], {0, 0, 1}, 1e-6f);
    EXPECT_EQ(v.at(0, 0, 0), -1024.0f);
    EXPECT_EQ(v.at(61, 50, 15), 0.0f);
    EXPECT_EQ(v.at(40, 67, 7), -104.0f);
    EXPECT_EQ(v.at(121, 100, 29), -997.0f);
    EXPECT_EQ(v.at(63, 35, 2), 1207.0f);
    EXPECT_EQ(sum_of(v), -130894872.0);
    EXPECT_EQ(lv.info.range.min, -1100.0f);
    EXPECT_EQ(lv.info.range.max, 1207.0f);
}

TEST(LoadVolume, NiftiLabelMapWithHeaderExtension) {
    REQUIRE_DATA();
    // vox_offset 13168: the data starts after a 12.8 kB header extension.
    const Volume labels = load_volume(data("totalseg_ct_abdomen/example_seg.nii.gz"));
    EXPECT_EQ(labels.dims, glm::ivec3(122, 101, 30));
    EXPECT_EQ(segment_label(labels, 5).count_inside(), 38634u); // liver
    EXPECT_EQ(sum_of(labels), 2734697.0);
    const std::vector<int> present = labels_present(labels);
    EXPECT_EQ(present.size(), 42u); // 41 labels and the background
    EXPECT_EQ(present.front(), 0);
    EXPECT_EQ(present.back(), 117);
}

TEST(LoadVolume, DicomFolderReadsTheSeriesInSliceOrder) {
    REQUIRE_DATA();
    const LoadedVolume lv = open_volume(data("dicom_mr_head_t1_sag"));
    const Volume& v = lv.volume;
    EXPECT_EQ(lv.info.format, "DICOM");
    EXPECT_EQ(lv.info.scalar_type, "uint16");
    EXPECT_EQ(lv.info.files, 35u);
    EXPECT_FALSE(lv.info.series_uid.empty());
    EXPECT_EQ(v.dims, glm::ivec3(256, 256, 35));
    expect_vec3_near(v.spacing, {1.015625f, 1.015625f, 4.8f}, 1e-4f); // z from the positions
    expect_vec3_near(v.origin, {81.6f, -130.0f, 130.0f}, 1e-3f);
    expect_vec3_near(v.direction[0], {0, 1, 0}, 1e-6f);
    expect_vec3_near(v.direction[1], {0, 0, -1}, 1e-6f);
    expect_vec3_near(v.direction[2], {-1, 0, 0}, 1e-6f);
    EXPECT_EQ(v.at(128, 128, 17), 484.0f);
    EXPECT_EQ(v.at(85, 170, 8), 421.0f);
    EXPECT_EQ(v.at(187, 246, 22), 1948.0f);
    EXPECT_EQ(sum_of(v), 516841282.0);
    // Slice 0 is the file named 0035_* (x = +81.6): its pixel data ends the file, uint16 LE.
    std::string last_file;
    for (const auto& entry : fs::directory_iterator(data("dicom_mr_head_t1_sag")))
        if (entry.path().filename().string().rfind("0035_", 0) == 0)
            last_file = entry.path().string();
    const Bytes dcm = read_bytes(last_file);
    const std::size_t pixels = std::size_t(256) * 256;
    ASSERT_GE(dcm.size(), pixels * 2);
    for (std::size_t i = 0; i < pixels; i += 97)
        ASSERT_EQ(v.samples[i], float(load_le<std::uint16_t>(dcm, dcm.size() - pixels * 2 + 2 * i)))
            << i;
}

TEST(LoadVolume, DicomSeriesByFileAndByUid) {
    REQUIRE_DATA();
    const auto series = list_dicom_series(data("dicom_mr_head_t1_sag"));
    ASSERT_EQ(series.size(), 1u);
    EXPECT_EQ(series[0].files, 35u);
    LoadOptions options;
    options.dicom_series_uid = series[0].uid;
    const LoadedVolume by_uid = open_volume(data("dicom_mr_head_t1_sag"), options);
    EXPECT_EQ(by_uid.info.series_uid, series[0].uid);
    EXPECT_EQ(by_uid.volume.dims, glm::ivec3(256, 256, 35));
    // One file of the series names the whole series.
    std::string one_file;
    for (const auto& entry : fs::directory_iterator(data("dicom_mr_head_t1_sag")))
        if (entry.path().filename().string().rfind("0010_", 0) == 0)
            one_file = entry.path().string();
    const Volume by_file = load_volume(one_file);
    EXPECT_EQ(by_file.samples, by_uid.volume.samples);

    options.dicom_series_uid = "1.2.3.4";
    const std::string message = error_of<std::invalid_argument>(
        [&] { open_volume(data("dicom_mr_head_t1_sag"), options); });
    expect_clear_error(message, data("dicom_mr_head_t1_sag"), "no DICOM series 1.2.3.4");
    EXPECT_NE(message.find(series[0].uid), std::string::npos) << message;
}

TEST(LoadVolume, RawSliceSeriesHeadsq) {
    REQUIRE_DATA();
    RawOptions raw;
    raw.dims = {64, 64, 93};
    raw.type = ScalarType::UInt16;
    raw.spacing = {3.2f, 3.2f, 1.5f};
    const LoadedVolume lv = open_raw(data("headsq/quarter.1"), raw);
    const Volume& v = lv.volume;
    EXPECT_EQ(lv.info.format, "raw");
    EXPECT_EQ(lv.info.files, 93u);
    EXPECT_EQ(v.dims, glm::ivec3(64, 64, 93));
    expect_vec3_near(v.spacing, {3.2f, 3.2f, 1.5f}, 0.0f);
    EXPECT_EQ(v.at(32, 32, 46), 122.0f);
    EXPECT_EQ(v.at(21, 42, 23), 1075.0f);
    EXPECT_EQ(v.at(39, 24, 53), 3926.0f);
    EXPECT_EQ(sum_of(v), 193392317.0);
    EXPECT_EQ(lv.info.range.min, 0.0f);
    EXPECT_EQ(lv.info.range.max, 3926.0f);
}

TEST(LoadVolume, RawSingleFileAndBigEndianMatchTheSeries) {
    REQUIRE_DATA();
    RawOptions raw;
    raw.dims = {64, 64, 93};
    raw.type = ScalarType::UInt16;
    const Volume series = load_raw(data("headsq/quarter.1"), raw);
    Bytes little, big;
    for (int k = 1; k <= 93; ++k)
        little = concat(little, read_bytes(data("headsq/quarter." + std::to_string(k))));
    big = little;
    for (std::size_t i = 0; i + 1 < big.size(); i += 2) std::swap(big[i], big[i + 1]);
    TempDir dir;
    write_bytes(dir.file("head.raw"), little);
    write_bytes(dir.file("head_be.raw"), big);
    EXPECT_EQ(load_raw(dir.file("head.raw"), raw).samples, series.samples);
    raw.endian = Endian::Big;
    EXPECT_EQ(load_raw(dir.file("head_be.raw"), raw).samples, series.samples);
}

TEST(LoadVolume, RawZeroPaddedSeriesAndFloat64) {
    TempDir dir;
    // Three slices of 2x2 float64, big-endian, named s001.f64 .. s003.f64.
    for (int k = 1; k <= 3; ++k) {
        Bytes slice;
        for (int i = 0; i < 4; ++i) {
            const double value = k * 10.0 + i + 0.5;
            std::uint8_t b[8];
            std::memcpy(b, &value, 8);
            for (int j = 7; j >= 0; --j) slice.push_back(b[j]);
        }
        write_bytes(dir.file("s00" + std::to_string(k) + ".f64"), slice);
    }
    RawOptions raw;
    raw.dims = {2, 2, 3};
    raw.type = ScalarType::Float64;
    raw.endian = Endian::Big;
    const Volume v = load_raw(dir.file("s001.f64"), raw);
    EXPECT_EQ(v.at(0, 0, 0), 10.5f);
    EXPECT_EQ(v.at(1, 1, 2), 33.5f);
    EXPECT_EQ(v.at(1, 0, 1), 21.5f);
}

TEST(LoadVolume, OtsuSuggestionMatchesSources) {
    REQUIRE_DATA();
    // SOURCES.md's Otsu thresholds, each within 1.5 bins of a 256-bin histogram.
    struct Case {
        std::string path;
        float otsu;
    };
    const Case cases[] = {{"HeadMRVolume.mhd", 41},
                          {"carotid.vtk", 80},
                          {"FLAIR.nrrd", 60},
                          {"totalseg_ct_abdomen/example_ct_sm.nii.gz", -492},
                          {"dicom_mr_head_t1_sag", 354}};
    for (const auto& c : cases) {
        const Volume v = load_volume(data(c.path));
        const Histogram h = make_histogram(v, 256);
        EXPECT_EQ(h.total(), v.voxel_count());
        EXPECT_NEAR(suggest_iso(v), c.otsu, 1.5 * h.bin_width()) << c.path;
    }
    RawOptions raw;
    raw.dims = {64, 64, 93};
    raw.type = ScalarType::UInt16;
    const Volume head = load_raw(data("headsq/quarter.1"), raw);
    EXPECT_NEAR(suggest_iso(head), 636.0, 1.5 * make_histogram(head).bin_width());
}

// The same CT as NIfTI (RAS sform) and as NRRD written here from the NIfTI's bytes, once in
// LPS and once in RAS space: Marching Cubes meshes in world millimetres must coincide, and
// sit where the NIfTI's own sform (parsed here, not by ITK) puts them.
TEST(LoadVolume, NiftiAndNrrdMeshesCoincideInWorld) {
    REQUIRE_DATA();
    const std::string nifti = data("totalseg_ct_abdomen/example_ct_sm.nii.gz");
    const Bytes nii = gunzip(read_bytes(nifti));
    ASSERT_GE(nii.size(), 352u);
    glm::mat4 sform(1.0f); // column-major: sform[c][r]
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) sform[c][r] = load_le<float>(nii, 280 + 16 * r + 4 * c);
    const std::size_t offset = std::size_t(load_le<float>(nii, 108));
    const Bytes samples(nii.begin() + std::ptrdiff_t(offset), nii.end());

    auto vector_text = [](glm::vec3 v) {
        std::ostringstream out;
        out.precision(9);
        out << "(" << v.x << "," << v.y << "," << v.z << ")";
        return out.str();
    };
    auto write_nrrd = [&](const std::string& path, const std::string& space, glm::vec3 flip) {
        std::string extra = "space: " + space + "\nspace directions:";
        for (int c = 0; c < 3; ++c) extra += " " + vector_text(flip * glm::vec3(sform[c]));
        extra += "\nspace origin: " + vector_text(flip * glm::vec3(sform[3])) + "\n";
        write_bytes(path,
                    concat(text_bytes(nrrd_header("short", "122 101 30", "raw", extra)), samples));
    };
    TempDir dir;
    write_nrrd(dir.file("ct_lps.nrrd"), "left-posterior-superior", {-1, -1, 1});
    write_nrrd(dir.file("ct_ras.nrrd"), "right-anterior-superior", {1, 1, 1});

    const Volume from_nifti = load_volume(nifti);
    const MarchingCubesOptions mc{200.0f, InsideIs::Above};
    const Mesh index_mesh = marching_cubes(from_nifti, mc);
    ASSERT_GT(index_mesh.vertex_count(), 1000u);
    const Mesh world = mesh_to_world(index_mesh, from_nifti);
    for (const std::string name : {"ct_lps.nrrd", "ct_ras.nrrd"}) {
        const Volume from_nrrd = load_volume(dir.file(name));
        ASSERT_EQ(from_nrrd.samples, from_nifti.samples) << name;
        const Mesh other = mesh_to_world(marching_cubes(from_nrrd, mc), from_nrrd);
        ASSERT_EQ(other.vertex_count(), world.vertex_count()) << name;
        ASSERT_EQ(other.indices, world.indices) << name;
        float worst = 0.0f;
        for (std::size_t i = 0; i < world.vertex_count(); ++i)
            worst = std::max(worst, glm::length(other.positions[i] - world.positions[i]));
        EXPECT_LT(worst, 1e-3f) << name << ": largest distance between the meshes, mm";
    }
    // Where the scanner put them: LPS = diag(-1, -1, 1) * (sform * index).
    float worst = 0.0f;
    for (std::size_t i = 0; i < world.vertex_count(); ++i) {
        const glm::vec3 ras = glm::vec3(sform * glm::vec4(index_mesh.positions[i], 1.0f));
        worst = std::max(worst, glm::length(world.positions[i] - ras * glm::vec3(-1, -1, 1)));
    }
    EXPECT_LT(worst, 1e-3f) << "largest distance from the sform's positions, mm";
}

// ---- Bad files
// -----------------------------------------------------------------------------------

TEST(BadFiles, MissingEmptyAndUnknown) {
    TempDir dir;
    expect_clear_error(error_of([&] { load_volume(dir.file("none.nrrd")); }), dir.file("none.nrrd"),
                       "no such file");
    write_bytes(dir.file("empty.nrrd"), {});
    expect_clear_error(error_of([&] { load_volume(dir.file("empty.nrrd")); }),
                       dir.file("empty.nrrd"), "empty file");
    write_bytes(dir.file("empty.nii.gz"), {});
    expect_clear_error(error_of([&] { load_volume(dir.file("empty.nii.gz")); }),
                       dir.file("empty.nii.gz"), "empty file");
    Bytes noise(1000);
    for (std::size_t i = 0; i < noise.size(); ++i) noise[i] = std::uint8_t(i * 7919 % 251);
    write_bytes(dir.file("noise.xyz"), noise);
    expect_clear_error(error_of([&] { load_volume(dir.file("noise.xyz")); }), dir.file("noise.xyz"),
                       "not a volume format");
    write_bytes(dir.file("noise.nrrd"), noise);
    expect_clear_error(error_of([&] { load_volume(dir.file("noise.nrrd")); }),
                       dir.file("noise.nrrd"), "not a volume format");
}

TEST(BadFiles, GzipThatIsNotGzip) {
    TempDir dir;
    write_bytes(dir.file("fake.nii.gz"), text_bytes(std::string(600, 'x')));
    expect_clear_error(error_of([&] { load_volume(dir.file("fake.nii.gz")); }),
                       dir.file("fake.nii.gz"), "not gzip");
}

TEST(BadFiles, TruncatedNiftiGzAndNii) {
    REQUIRE_DATA();
    TempDir dir;
    const Bytes gz = read_bytes(data("totalseg_ct_abdomen/example_ct_sm.nii.gz"));
    // Cut the compressed stream in half: ITK would zero-fill the missing samples.
    write_bytes(dir.file("half.nii.gz"),
                Bytes(gz.begin(), gz.begin() + std::ptrdiff_t(gz.size() / 2)));
    expect_clear_error(error_of([&] { load_volume(dir.file("half.nii.gz")); }),
                       dir.file("half.nii.gz"), "truncated");
    // Only the header and 1000 bytes of samples, uncompressed.
    const Bytes nii = gunzip(gz);
    write_bytes(dir.file("short.nii"), Bytes(nii.begin(), nii.begin() + 1352));
    const std::string message = error_of([&] { load_volume(dir.file("short.nii")); });
    expect_clear_error(message, dir.file("short.nii"), "truncated NIfTI");
    EXPECT_NE(message.find("739320"), std::string::npos) << message; // 122*101*30*2 bytes
    // The whole header but no sample at all, gzip again.
    write_bytes(dir.file("header.nii.gz"), gzip(Bytes(nii.begin(), nii.begin() + 352)));
    expect_clear_error(error_of([&] { load_volume(dir.file("header.nii.gz")); }),
                       dir.file("header.nii.gz"), "truncated");
}

TEST(BadFiles, TruncatedMetaImageVtkNrrdAndRaw) {
    REQUIRE_DATA();
    TempDir dir;
    // MetaImage: header intact, .raw missing its last 1000 bytes.
    fs::copy_file(data("HeadMRVolume.mhd"), dir.file("head.mhd"));
    const Bytes raw = read_bytes(data("HeadMRVolume.raw"));
    write_bytes(dir.file("HeadMRVolume.raw"), Bytes(raw.begin(), raw.end() - 1000));
    expect_clear_error(error_of([&] { load_volume(dir.file("head.mhd")); }), dir.file("head.mhd"),
                       "truncated MetaImage");
    // VTK legacy binary, cut inside the samples.
    const Bytes vtk = read_bytes(data("carotid.vtk"));
    write_bytes(dir.file("carotid.vtk"), Bytes(vtk.begin(), vtk.begin() + 300000));
    expect_clear_error(error_of([&] { load_volume(dir.file("carotid.vtk")); }),
                       dir.file("carotid.vtk"), "truncated VTK");
    // NRRD with gzip encoding, cut: the stream inflates to fewer bytes than promised.
    const Bytes nrrd = read_bytes(data("FLAIR.nrrd"));
    write_bytes(dir.file("flair.nrrd"), Bytes(nrrd.begin(), nrrd.begin() + 500000));
    expect_clear_error(error_of([&] { load_volume(dir.file("flair.nrrd")); }),
                       dir.file("flair.nrrd"), "truncated NRRD: the header promises 2777600 bytes");
    // Raw: one slice file short of a byte.
    RawOptions options;
    options.dims = {64, 64, 93};
    options.type = ScalarType::UInt16;
    write_bytes(dir.file("head.raw"), Bytes(64 * 64 * 93 * 2 - 1));
    expect_clear_error(error_of([&] { load_raw(dir.file("head.raw"), options); }),
                       dir.file("head.raw"), "need 761856 bytes");
    // A slice series with a missing file.
    for (int k = 1; k <= 3; ++k) write_bytes(dir.file("sl." + std::to_string(k)), Bytes(8));
    options.dims = {2, 2, 4};
    expect_clear_error(error_of([&] { load_raw(dir.file("sl.1"), options); }), dir.file("sl.1"),
                       "sl.4 is missing");
}

TEST(BadFiles, HeaderThatLiesAboutSize) {
    TempDir dir;
    // MetaImage claiming 100^3 shorts next to 1000 bytes.
    write_bytes(dir.file("lie.mhd"),
                text_bytes("ObjectType = Image\nNDims = 3\nDimSize = 100 100 100\n"
                           "ElementType = MET_SHORT\nElementDataFile = lie.raw\n"));
    write_bytes(dir.file("lie.raw"), Bytes(1000));
    expect_clear_error(error_of([&] { load_volume(dir.file("lie.mhd")); }), dir.file("lie.mhd"),
                       "promises 2000000 bytes");
    // .mha with LOCAL data.
    write_bytes(dir.file("lie.mha"),
                concat(text_bytes("NDims = 3\nDimSize = 64 64 64\nElementType = MET_UCHAR\n"
                                  "ElementDataFile = LOCAL\n"),
                       Bytes(4096)));
    expect_clear_error(error_of([&] { load_volume(dir.file("lie.mha")); }), dir.file("lie.mha"),
                       "truncated MetaImage");
    // NRRD claiming 64^3 shorts, raw encoding, 100 bytes present.
    write_bytes(dir.file("lie.nrrd"),
                concat(text_bytes(nrrd_header("short", "64 64 64", "raw")), Bytes(100)));
    expect_clear_error(error_of([&] { load_volume(dir.file("lie.nrrd")); }), dir.file("lie.nrrd"),
                       "promises 524288 bytes of samples, the file holds 100");
    // VTK whose POINT_DATA disagrees with DIMENSIONS.
    write_bytes(dir.file("lie.vtk"),
                concat(text_bytes("# vtk DataFile Version 3.0\nx\nBINARY\nDATASET "
                                  "STRUCTURED_POINTS\nDIMENSIONS 4 4 4\nSPACING 1 1 1\nORIGIN 0 "
                                  "0 0\nPOINT_DATA 8\nSCALARS s unsigned_char 1\nLOOKUP_TABLE "
                                  "default\n"),
                       Bytes(64)));
    expect_clear_error(error_of([&] { load_volume(dir.file("lie.vtk")); }), dir.file("lie.vtk"),
                       "POINT_DATA 8 does not match");
}

TEST(BadFiles, AbsurdDimensionsAreRefusedBeforeAllocating) {
    TempDir dir;
    const std::string huge = "2147483648 2147483648 2147483648"; // 2^31 per axis
    write_bytes(dir.file("huge.nrrd"),
                concat(text_bytes(nrrd_header("unsigned char", huge, "raw")), Bytes(16)));
    expect_clear_error(error_of([&] { load_volume(dir.file("huge.nrrd")); }), dir.file("huge.nrrd"),
                       "absurd dimensions 2147483648 x 2147483648");
    write_bytes(dir.file("huge.mhd"),
                text_bytes("NDims = 3\nDimSize = " + huge +
                           "\nElementType = MET_UCHAR\nElementDataFile = huge.raw\n"));
    write_bytes(dir.file("huge.raw"), Bytes(16));
    expect_clear_error(error_of([&] { load_volume(dir.file("huge.mhd")); }), dir.file("huge.mhd"),
                       "absurd dimensions");
    // Large but representable: refused by the memory check, with the sizes.
    write_bytes(
        dir.file("big.nrrd"),
        concat(text_bytes(nrrd_header("unsigned char", "200000 200000 200000", "raw")), Bytes(16)));
    const std::string message = error_of([&] { load_volume(dir.file("big.nrrd")); });
    expect_clear_error(message, dir.file("big.nrrd"), "200000 x 200000 x 200000 samples need");
    EXPECT_NE(message.find("PiB as float32"), std::string::npos) << message;
    EXPECT_NE(message.find("of memory is available"), std::string::npos) << message;
    RawOptions raw;
    raw.dims = {0, 64, 64};
    EXPECT_THROW(load_raw(dir.file("huge.raw"), raw), std::invalid_argument);
}

TEST(BadFiles, MemoryLimitNamesBothSizes) {
    REQUIRE_DATA();
    LoadOptions options;
    options.memory_limit_bytes = 10u << 20; // FLAIR needs 124*160*140*4 = 10.6 MiB
    const std::string message = error_of([&] { load_volume(data("FLAIR.nrrd"), options); });
    expect_clear_error(message, data("FLAIR.nrrd"), "124 x 160 x 140 samples need 10.6 MiB");
    EXPECT_NE(message.find("memory limit of 10.0 MiB"), std::string::npos) << message;
    options.memory_limit_bytes = 11u << 20;
    EXPECT_EQ(load_volume(data("FLAIR.nrrd"), options).dims, glm::ivec3(124, 160, 140));
}

TEST(BadFiles, UnknownSampleTypes) {
    TempDir dir;
    write_bytes(dir.file("block.nrrd"),
                concat(text_bytes("NRRD0004\ntype: block\nblock size: 3\ndimension: 3\nsizes: 2 2 "
                                  "2\nencoding: raw\n\n"),
                       Bytes(24)));
    expect_clear_error(error_of([&] { load_volume(dir.file("block.nrrd")); }),
                       dir.file("block.nrrd"), "unsupported NRRD type 'block'");
    write_bytes(dir.file("string.mhd"),
                text_bytes("NDims = 3\nDimSize = 2 2 2\nElementType = MET_STRING\n"
                           "ElementDataFile = string.raw\n"));
    write_bytes(dir.file("string.raw"), Bytes(8));
    expect_clear_error(error_of([&] { load_volume(dir.file("string.mhd")); }),
                       dir.file("string.mhd"), "unsupported MetaImage ElementType MET_STRING");
    // NIfTI-1 with datatype 128 (RGB24).
    Bytes header(352);
    const auto put16 = [&](std::size_t at, std::int16_t v) { std::memcpy(&header[at], &v, 2); };
    const std::int32_t sizeof_hdr = 348;
    std::memcpy(&header[0], &sizeof_hdr, 4);
    put16(40, 3);
    put16(42, 2);
    put16(44, 2);
    put16(46, 2);
    put16(70, 128);
    put16(72, 24);
    const float vox_offset = 352.0f, one = 1.0f;
    std::memcpy(&header[108], &vox_offset, 4);
    for (int i = 0; i < 4; ++i) std::memcpy(&header[76 + 4 * i], &one, 4);
    std::memcpy(&header[344], "n+1\0", 4);
    write_bytes(dir.file("rgb.nii"), concat(header, Bytes(24)));
    expect_clear_error(error_of([&] { load_volume(dir.file("rgb.nii")); }), dir.file("rgb.nii"),
                       "unsupported NIfTI datatype 128 (RGB24)");
    EXPECT_THROW(parse_scalar_type("int128"), std::invalid_argument);
}

// A copy of the DICOM series with one file damaged.
struct DamagedDicom {
    TempDir dir;
    std::string damaged;
    explicit DamagedDicom(std::uintmax_t keep_bytes) {
        for (const auto& entry : fs::directory_iterator(data("dicom_mr_head_t1_sag"))) {
            const fs::path to = dir.path / entry.path().filename();
            fs::copy_file(entry.path(), to);
            fs::permissions(to, fs::perms::owner_read | fs::perms::owner_write);
            if (entry.path().filename().string().rfind("0010_", 0) == 0) damaged = to.string();
        }
        fs::resize_file(damaged, keep_bytes);
    }
};

TEST(BadFiles, TruncatedDicomHeaderDoesNotAbortTheProcess) {
    REQUIRE_DATA();
    // Cut inside the header: GDCM's assert fires (SIGABRT) in the reader's child process.
    DamagedDicom dicom(2000);
    const std::string folder = dicom.dir.path.string();
    const std::string message = error_of([&] { load_volume(folder); });
    expect_clear_error(message, folder, "the DICOM reader crashed");
    // This process is alive, and the intact series still loads.
    EXPECT_EQ(load_volume(data("dicom_mr_head_t1_sag")).dims, glm::ivec3(256, 256, 35));
}

TEST(BadFiles, TruncatedDicomPixelDataAndMissingSlice) {
    REQUIRE_DATA();
    {
        DamagedDicom dicom(265114 - 1000); // the pixel data is short of 1000 bytes
        const std::string message = error_of([&] { load_volume(dicom.dir.path.string()); });
        expect_clear_error(message, dicom.damaged, "truncated DICOM");
    }
    {
        DamagedDicom dicom(1000); // GDCM skips this file: the series has a gap
        const std::string message = error_of([&] { load_volume(dicom.dir.path.string()); });
        EXPECT_NE(message.find("missing, damaged or unevenly spaced slices"), std::string::npos)
            << message;
    }
}

TEST(BadFiles, FolderWithoutDicom) {
    TempDir dir;
    write_bytes(dir.file("notes.txt"), text_bytes("no images here\n"));
    expect_clear_error(error_of([&] { load_volume(dir.path.string()); }), dir.path.string(),
                       "no DICOM series found");
    EXPECT_TRUE(list_dicom_series(dir.path.string()).empty());
}

// ---- NaN / infinity policy ---------------------------------------------------------------------

TEST(NonFinite, ReplacedByTheFiniteRangeOrRefused) {
    TempDir dir;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    const std::vector<float> values = {1, nan, 5, -inf, 3, inf, 2, 4};
    write_bytes(dir.file("f.raw"), as_bytes(values));
    RawOptions raw;
    raw.dims = {2, 2, 2};
    raw.type = ScalarType::Float32;
    const LoadedVolume lv = open_raw(dir.file("f.raw"), raw);
    EXPECT_EQ(lv.info.nonfinite, 3u);
    EXPECT_EQ(lv.volume.samples, (std::vector<float>{1, 1, 5, 1, 3, 5, 2, 4}));
    EXPECT_EQ(lv.info.range.min, 1.0f);
    EXPECT_EQ(lv.info.range.max, 5.0f);

    LoadOptions refuse;
    refuse.nonfinite = NonFinitePolicy::Refuse;
    expect_clear_error(error_of([&] { open_raw(dir.file("f.raw"), raw, refuse); }),
                       dir.file("f.raw"), "1 NaN and 2 infinite samples");

    write_bytes(dir.file("nan.raw"), as_bytes(std::vector<float>(8, nan)));
    expect_clear_error(error_of([&] { open_raw(dir.file("nan.raw"), raw); }), dir.file("nan.raw"),
                       "no finite sample");

    // The same policy through ITK (NRRD float).
    write_bytes(dir.file("f.nrrd"),
                concat(text_bytes(nrrd_header("float", "2 2 2", "raw")), as_bytes(values)));
    const LoadedVolume nrrd = open_volume(dir.file("f.nrrd"));
    EXPECT_EQ(nrrd.info.nonfinite, 3u);
    EXPECT_EQ(nrrd.volume.samples, lv.volume.samples);
}

// ---- Label maps
// ------------------------------------------------------------------------------------

TEST(LabelMaps, GridMismatchIsNamed) {
    REQUIRE_DATA();
    const std::string ct = data("totalseg_ct_abdomen/example_ct_sm.nii.gz");
    const Volume grey = load_volume(ct);
    const Volume labels = load_volume(data("totalseg_ct_abdomen/example_seg.nii.gz"));
    EXPECT_NO_THROW(check_same_grid(grey, ct, labels, "seg"));
    TempDir dir;
    write_bytes(dir.file("small.nrrd"),
                concat(text_bytes(nrrd_header("unsigned char", "10 10 10", "raw")), Bytes(1000)));
    const Volume small = load_volume(dir.file("small.nrrd"));
    const std::string message = error_of<std::invalid_argument>(
        [&] { check_same_grid(grey, ct, small, dir.file("small.nrrd")); });
    expect_clear_error(message, dir.file("small.nrrd"), "dimensions differ");
    EXPECT_NE(message.find("dims 10x10x10"), std::string::npos) << message;
    EXPECT_NE(message.find("dims 122x101x30"), std::string::npos) << message;
    Volume shifted = labels;
    shifted.origin.x += 1.5f; // half a voxel
    expect_clear_error(
        error_of<std::invalid_argument>([&] { check_same_grid(grey, ct, shifted, "shifted"); }),
        "shifted", "origin differ");
}

TEST(LabelMaps, BoundaryIsoOfTheLiver) {
    REQUIRE_DATA();
    const Volume grey = load_volume(data("totalseg_ct_abdomen/example_ct_sm.nii.gz"));
    const Volume labels = load_volume(data("totalseg_ct_abdomen/example_seg.nii.gz"));
    const BoundaryIso b = boundary_iso(grey, segment_label(labels, 5));
    // Reference values computed independently from the files' bytes.
    EXPECT_EQ(b.pairs, 10095u);
    EXPECT_NEAR(b.inside_mean, 33.018227, 1e-4);
    EXPECT_NEAR(b.outside_mean, -25.927093, 1e-4);
    EXPECT_NEAR(b.iso, 3.545567f, 1e-4f);
    EXPECT_EQ(b.inside, InsideIs::Above);
}

TEST(LabelMaps, BoundaryIsoSynthetic) {
    Volume grey = make_volume({6, 6, 6}, 10.0f);
    Segmentation mask{grey.dims, std::vector<std::uint8_t>(grey.voxel_count(), 0)};
    for (int z = 2; z < 4; ++z)
        for (int y = 2; y < 4; ++y)
            for (int x = 2; x < 4; ++x) {
                mask.inside[mask.index(x, y, z)] = 1;
                grey.samples[grey.index(x, y, z)] = 90.0f;
            }
    BoundaryIso b = boundary_iso(grey, mask);
    EXPECT_EQ(b.pairs, 24u); // a 2x2x2 cube: 6 faces of 4 voxel pairs
    EXPECT_FLOAT_EQ(b.iso, 50.0f);
    EXPECT_EQ(b.inside, InsideIs::Above);
    for (auto& v : grey.samples) v = 100.0f - v; // dark object
    b = boundary_iso(grey, mask);
    EXPECT_FLOAT_EQ(b.iso, 50.0f);
    EXPECT_EQ(b.inside, InsideIs::Below);
    Segmentation empty{grey.dims, std::vector<std::uint8_t>(grey.voxel_count(), 0)};
    EXPECT_THROW(boundary_iso(grey, empty), std::invalid_argument);
}

// ---- Histogram, Otsu ---------------------------------------------------------------------------

TEST(Histogram, CountsAndTwoValuedOtsu) {
    Volume v = make_volume({10, 10, 10}, 20.0f);
    for (std::size_t i = 0; i < 300; ++i) v.samples[i] = 100.0f;
    v.samples[500] = std::numeric_limits<float>::quiet_NaN();
    const Histogram h = make_histogram(v, 16);
    EXPECT_EQ(h.lo, 20.0f);
    EXPECT_EQ(h.hi, 100.0f);
    EXPECT_EQ(h.total(), 999u); // the NaN is not counted
    EXPECT_EQ(h.counts.front(), 699u);
    EXPECT_EQ(h.counts.back(), 300u);
    EXPECT_DOUBLE_EQ(h.bin_width(), 5.0);
    // Two values: every split between them is equally good; Otsu takes the middle one.
    EXPECT_FLOAT_EQ(otsu_threshold(h), 60.0f);
    EXPECT_EQ(otsu_threshold(make_histogram(make_volume({2, 2, 2}, 7.0f))), 7.0f);
}

// ---- snert's own header handling (also fuzzed in tests/fuzz)
// -------------------------------------

TEST(VolumeHeaders, ConvertInPlaceEveryType) {
    const auto check = [](ScalarType type, auto sample_values) {
        using T = typename decltype(sample_values)::value_type;
        for (Endian endian : {Endian::Little, Endian::Big}) {
            std::vector<float> buffer(sample_values.size());
            auto* tail = static_cast<unsigned char*>(
                detail::stored_tail(buffer.data(), buffer.size(), type));
            for (std::size_t i = 0; i < sample_values.size(); ++i) {
                unsigned char b[sizeof(T)];
                std::memcpy(b, &sample_values[i], sizeof(T));
                if (endian != detail::native_endian()) std::reverse(b, b + sizeof(T));
                std::memcpy(tail + i * sizeof(T), b, sizeof(T));
            }
            detail::convert_in_place(buffer.data(), buffer.size(), type, endian);
            for (std::size_t i = 0; i < sample_values.size(); ++i)
                EXPECT_EQ(buffer[i], float(sample_values[i])) << scalar_type_name(type) << " " << i;
        }
    };
    check(ScalarType::UInt8, std::vector<std::uint8_t>{0, 1, 127, 200, 255, 3, 4});
    check(ScalarType::Int8, std::vector<std::int8_t>{-128, -1, 0, 1, 127});
    check(ScalarType::UInt16, std::vector<std::uint16_t>{0, 1, 4095, 65535, 300});
    check(ScalarType::Int16, std::vector<std::int16_t>{-32768, -1024, 0, 1207, 32767});
    check(ScalarType::UInt32, std::vector<std::uint32_t>{0, 16777216, 7});
    check(ScalarType::Int32, std::vector<std::int32_t>{-16777216, 0, 5});
    check(ScalarType::Float32, std::vector<float>{-1.5f, 0.0f, 3.25e7f});
    std::vector<float> out(2);
    const double doubles[2] = {-2.5, 1e10};
    detail::convert_samples(doubles, 2, ScalarType::Float64, detail::native_endian(), out.data());
    EXPECT_EQ(out, (std::vector<float>{-2.5f, 1e10f}));
}

TEST(VolumeHeaders, NumberedNames) {
    auto n = detail::parse_numbered_name("dir9/quarter.1");
    ASSERT_TRUE(n);
    EXPECT_EQ(detail::numbered_path(*n, 93), "dir9/quarter.93");
    n = detail::parse_numbered_name("IM-0009.raw");
    ASSERT_TRUE(n);
    EXPECT_EQ(n->width, 4u);
    EXPECT_EQ(detail::numbered_path(*n, 10), "IM-0010.raw");
    EXPECT_FALSE(detail::parse_numbered_name("dir9/slices"));
    n = detail::parse_numbered_name("s001.f64"); // the number before the extension first
    ASSERT_TRUE(n);
    EXPECT_EQ(detail::numbered_path(*n, 2), "s002.f64");
    EXPECT_EQ(detail::numbered_name_candidates("head5.1").size(), 2u);
}

TEST(VolumeHeaders, ParsersRejectNonsense) {
    const Bytes zeros(600);
    EXPECT_THROW(detail::parse_nifti_header(zeros.data(), zeros.size(), "z"), std::runtime_error);
    EXPECT_THROW(detail::parse_nifti_header(zeros.data(), 100, "z"), std::runtime_error);
    EXPECT_THROW(detail::parse_metaimage_header("NDims = 3\nDimSize = 2 2\n"
                                                "ElementDataFile = x\n",
                                                "m"),
                 std::runtime_error);
    const auto meta = detail::parse_metaimage_header(
        "NDims = 3\nDimSize = 4 5 6\nElementType = MET_SHORT\nElementDataFile = LOCAL\nXYZ", "m");
    EXPECT_EQ(meta.data_bytes(), 240u);
    EXPECT_EQ(meta.local_offset, 74u);
    const Bytes vtk =
        text_bytes("# vtk DataFile Version 3.0\nt\nBINARY\nDATASET STRUCTURED_POINTS\n"
                   "DIMENSIONS 2 3 4\nPOINT_DATA 24\nSCALARS s short\n"
                   "LOOKUP_TABLE default\n");
    const auto h = detail::parse_vtk_header(vtk.data(), vtk.size(), "v");
    ASSERT_TRUE(h);
    EXPECT_EQ(h->data_bytes(), 48u);
    EXPECT_EQ(h->data_offset, vtk.size());
    EXPECT_EQ(detail::parse_meminfo_available("MemTotal: 10 kB\nMemAvailable:   2048 kB\n"),
              2048u * 1024u);
    EXPECT_EQ(detail::parse_meminfo_available("MemAvailable: lots\n"), 0u);
    EXPECT_THROW(detail::checked_dims("d", 0, 1, 1), std::runtime_error);
    EXPECT_EQ(detail::checked_dims("d", 2147483647, 1, 1), glm::ivec3(2147483647, 1, 1));
}

TEST(VolumeHeaders, DicomPixelDataCheck) {
    // Explicit VR little endian: tag, "OW", 2 reserved bytes, 32-bit length, then the value.
    Bytes file(200, 0);
    const std::uint8_t element[] = {0xE0, 0x7F, 0x10, 0x00, 'O', 'W', 0, 0, 8, 0, 0, 0};
    std::memcpy(&file[100], element, sizeof element);
    auto check = detail::check_dicom_pixel_data(file.data(), 120, 8, false);
    EXPECT_EQ(check.state, detail::PixelDataCheck::Complete);
    EXPECT_EQ(check.value_offset, 112u);
    check = detail::check_dicom_pixel_data(file.data(), 115, 8, false);
    EXPECT_EQ(check.state, detail::PixelDataCheck::Truncated);
    EXPECT_EQ(check.available, 3u);
    check = detail::check_dicom_pixel_data(file.data(), 120, 16, false);
    EXPECT_EQ(check.state, detail::PixelDataCheck::NotFound);
}
