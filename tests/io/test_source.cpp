// The input model (io/source.h): phantoms, files, raw data, label maps with their names, and
// the accuracy reference that owns what it reads.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

#include "core/phantom.h"
#include "io/nifti_label_names.h"
#include "io/source.h"
#include "support/expect_error.h"
#include "support/real_data.h"
#include "support/temp_folder.h"

namespace snert {
namespace {

using test::expect_error;

TEST(Source, PhantomHasExactReferenceAndHistogram) {
    SourceSpec spec;
    spec.input = "phantom:sphere";
    spec.phantom_size = 32;
    const Source s = open_source(spec);
    ASSERT_TRUE(s.volume);
    EXPECT_EQ(s.volume->dims, glm::ivec3(32));
    EXPECT_TRUE(spec.is_phantom());
    EXPECT_FALSE(s.info.has_value());
    EXPECT_FALSE(s.mask);
    EXPECT_EQ(s.suggested_iso, 0.0f);
    EXPECT_FALSE(s.iso_reason.empty());
    EXPECT_NE(s.title.find("sphere"), std::string::npos);
    EXPECT_EQ(s.histogram.counts.size(), 128u);
    EXPECT_EQ(s.histogram.total(), s.volume->voxel_count());
    ASSERT_TRUE(s.exact_reference.distance);
    EXPECT_TRUE(s.exact_reference.analytic);
    EXPECT_GT(s.exact_reference.volume, 0.0);

    const AccuracyReference own = accuracy_reference(s, s.suggested_iso);
    EXPECT_TRUE(own.analytic);
    const AccuracyReference other = accuracy_reference(s, 2.0f);
    EXPECT_FALSE(other.analytic);
    ASSERT_TRUE(other.distance);
    // On the sphere's distance map |I - 2| / |grad I| is about 2 at the centre... of the shell.
    EXPECT_GE(other.distance(glm::vec3(16.0f)), 0.0f);
}

TEST(Source, PhantomRefusesFileOptions) {
    SourceSpec spec;
    spec.input = "phantom:sphere";
    spec.labels = "labels.nii";
    spec.label = 1;
    expect_error<std::invalid_argument>([&] { open_source(spec); }, {"phantom:sphere", "label"});
    spec = {};
    spec.input = "phantom:sphere";
    spec.raw = RawOptions{};
    expect_error<std::invalid_argument>([&] { open_source(spec); }, {"phantom:sphere", "raw"});
    spec = {};
    spec.input = "phantom:nothing";
    expect_error<std::invalid_argument>([&] { open_source(spec); }, {"nothing"});
    expect_error<std::invalid_argument>([&] { open_source(SourceSpec{}); }, {"no volume"});
}

// A 4x3x2 ramp along x, in a NRRD file and as raw bytes.
std::vector<std::uint8_t> ramp_bytes() {
    std::vector<std::uint8_t> bytes;
    for (int z = 0; z < 2; ++z)
        for (int y = 0; y < 3; ++y)
            for (int x = 0; x < 4; ++x) bytes.push_back(std::uint8_t(x * 50));
    return bytes;
}

TEST(Source, NrrdFileDescribedWithOtsu) {
    test::TempFolder folder;
    const std::string path = folder.file("ramp.nrrd");
    std::string text = "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 3 2\n"
                       "spacings: 1 2 3\nencoding: raw\n\n";
    const auto bytes = ramp_bytes();
    text.append(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    test::write_text(path, text);
    SourceSpec spec;
    spec.input = path;
    const Source s = open_source(spec);
    ASSERT_TRUE(s.info.has_value());
    EXPECT_EQ(s.title, "ramp.nrrd");
    EXPECT_NE(s.description.find("NRRD"), std::string::npos) << s.description;
    EXPECT_NE(s.description.find("4x3x2"), std::string::npos) << s.description;
    EXPECT_NE(s.iso_reason.find("Otsu"), std::string::npos) << s.iso_reason;
    EXPECT_GT(s.suggested_iso, 0.0f);
    EXPECT_LT(s.suggested_iso, 150.0f);
    EXPECT_TRUE(s.warnings.empty());
    EXPECT_FALSE(s.exact_reference.distance);
    EXPECT_TRUE(s.labels_present.empty());
}

TEST(Source, RawFile) {
    test::TempFolder folder;
    const std::string path = folder.file("ramp.raw");
    test::write_bytes(path, ramp_bytes());
    SourceSpec spec;
    spec.input = path;
    spec.raw = RawOptions{};
    spec.raw->dims = {4, 3, 2};
    spec.raw->type = ScalarType::UInt8;
    spec.raw->spacing = {0.5f, 0.5f, 2.0f};
    const Source s = open_source(spec);
    EXPECT_EQ(s.volume->dims, glm::ivec3(4, 3, 2));
    EXPECT_EQ(s.volume->spacing, glm::vec3(0.5f, 0.5f, 2.0f));
    EXPECT_EQ(s.info->format, "raw");
    spec.raw->dims = {4, 3, 3}; // more than the file holds
    expect_error([&] { open_source(spec); }, {path});
}

TEST(Source, LabelMapWithNames) {
    SNERT_REQUIRE_DATA();
    SourceSpec spec;
    spec.input = test::data_file("totalseg_ct_abdomen/example_ct_sm.nii.gz");
    spec.labels = test::data_file("totalseg_ct_abdomen/example_seg.nii.gz");
    spec.label = 5;
    const Source s = open_source(spec);
    ASSERT_TRUE(s.mask);
    EXPECT_EQ(s.mask->count_inside(), 38634u);
    EXPECT_EQ(s.labels_present.size(), 42u); // 41 labels and the background 0
    bool found = false;
    for (const LabelEntry& e : s.labels_present)
        if (e.value == 5) {
            found = true;
            EXPECT_EQ(e.name, "liver");
            EXPECT_EQ(e.voxels, 38634u);
        }
    EXPECT_TRUE(found);
    EXPECT_NE(s.iso_reason.find("liver"), std::string::npos) << s.iso_reason;
    EXPECT_NE(s.iso_reason.find("38634"), std::string::npos) << s.iso_reason;
    EXPECT_EQ(nifti_label_names(spec.labels).at(1), "spleen");
    EXPECT_TRUE(nifti_label_names(spec.input).empty()); // no extension

    spec.label = 21; // urinary bladder: named in the table, absent from this crop
    expect_error<std::invalid_argument>([&] { open_source(spec); },
                                        {spec.labels, "label 21 does not occur", "5 liver"});
}

TEST(Source, ReferenceOutlivesTheSource) {
    test::TempFolder folder;
    const std::string path = folder.file("ramp.raw");
    test::write_bytes(path, ramp_bytes());
    SourceSpec spec;
    spec.input = path;
    spec.raw = RawOptions{};
    spec.raw->dims = {4, 3, 2};
    AccuracyReference reference;
    {
        Source s = open_source(spec);
        const Source moved = std::move(s);
        reference = accuracy_reference(moved, 75.0f);
    }
    ASSERT_TRUE(reference.distance);
    EXPECT_FALSE(reference.analytic);
    // A ramp of 50 per voxel along x: iso 75 lies half-way between x = 1 and x = 2.
    EXPECT_NEAR(reference.distance(glm::vec3(1.5f, 1.0f, 0.5f)), 0.0f, 1e-4f);
    EXPECT_NEAR(reference.distance(glm::vec3(1.0f, 1.0f, 0.5f)), 0.5f, 1e-4f);
}

TEST(NiftiLabelNames, XmlAndMalformedFiles) {
    const auto names = label_names_from_xml(
        "<LabelTable><Label Key=\"3\" Red=\"1\">a &amp; b</Label>"
        "<Label Key='-2'><![CDATA[ minus ]]></Label><Label Key=\"x\">bad</Label>"
        "<Label Key=\"7\">unclosed");
    ASSERT_EQ(names.size(), 2u);
    EXPECT_EQ(names.at(3), "a & b");
    EXPECT_EQ(names.at(-2), "minus");

    test::TempFolder folder;
    EXPECT_TRUE(nifti_label_names(folder.file("missing.nii")).empty());
    // A NIfTI-1 header whose extension claims more bytes than there are.
    std::vector<std::uint8_t> bytes(352 + 16, 0);
    const std::int32_t size = 348, esize = 1 << 30, ecode = 30;
    const float vox_offset = 352 + 16;
    std::memcpy(bytes.data(), &size, 4);
    std::memcpy(bytes.data() + 108, &vox_offset, 4);
    std::memcpy(bytes.data() + 344, "n+1", 4);
    bytes[348] = 1;
    std::memcpy(bytes.data() + 352, &esize, 4);
    std::memcpy(bytes.data() + 356, &ecode, 4);
    test::write_bytes(folder.file("bad.nii"), bytes);
    EXPECT_TRUE(nifti_label_names(folder.file("bad.nii")).empty());
}

} // namespace
} // namespace snert
