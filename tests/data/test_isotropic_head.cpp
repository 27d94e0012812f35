// The DICOM head's 1 x 1 x 4.8 mm voxels resampled to cubic ones (io/isotropic.h, the CLI's
// --isotropic): the net's cells are no longer stretched, and SNERT's mean triangle quality
// rises from 0.45 on the stored grid to 0.56 (the issue asks for at least 0.5).
#include <gtest/gtest.h>

#include "core/pipeline.h"
#include "io/source.h"
#include "support/real_data.h"

namespace snert {
namespace {

TEST(IsotropicHead, SnertMeanQualityReachesHalfOnCubicVoxels) {
    SNERT_REQUIRE_DATA();
    if (SNERT_LARGE_VOLUMES == 0)
        GTEST_SKIP() << "the DICOM head is too slow under the sanitizers; `make test` runs it in "
                        "an optimized build";
    SourceSpec spec;
    spec.input = test::data_file("dicom_mr_head_t1_sag");
    spec.isotropic = 0.0f; // the smallest spacing, 1.016 mm
    const Source source = open_source(spec);
    ASSERT_TRUE(source.volume);
    EXPECT_EQ(source.volume->dims, glm::ivec3(256, 256, 161));
    EXPECT_FLOAT_EQ(source.volume->spacing.z, source.volume->spacing.x);

    // What `snert compare VOLUME --iso 200 --isotropic --mode snert` runs.
    PipelineOptions options;
    options.iso = 200.0f;
    options.relax.iso = 200.0f;
    options.relax.mode = RelaxMode::Snert;
    const MethodResult r = run_method(Method::Snert, *source.volume, nullptr, options, {});
    // Measured 0.5612 (0.4482 on the stored grid).
    EXPECT_GE(r.metrics.quality.mean, 0.5);
    EXPECT_NEAR(r.metrics.quality.mean, 0.561, 0.005);
    EXPECT_EQ(r.metrics.quality.degenerate, 0u);
}

} // namespace
} // namespace snert
