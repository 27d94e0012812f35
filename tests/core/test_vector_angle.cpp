// vector_angle (core/vector_angle.h) against the C library's atan2, which it stands in for.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

#include "core/vector_angle.h"

namespace snert::detail {
namespace {

// Doubles between two finite values of the same sign, in units in the last place.
std::int64_t ulps_apart(double a, double b) {
    const std::int64_t ia = std::bit_cast<std::int64_t>(a), ib = std::bit_cast<std::int64_t>(b);
    return ia > ib ? ia - ib : ib - ia;
}

TEST(VectorAngle, TableIsAtanOfSixtyFourths) {
    for (int k = 0; k <= 64; ++k)
        EXPECT_LE(ulps_apart(kAtanOfSixtyFourths[k], std::atan(k / 64.0)), 1) << "k = " << k;
}

TEST(VectorAngle, SpecialValuesAsAtan2) {
    const double inf = std::numeric_limits<double>::infinity();
    const double cases[][2] = {{0.0, 1.0},    {0.0, -1.0},     {0.0, 0.0},  {0.0, -0.0},
                               {1.0, 0.0},    {1.0, -0.0},     {1.0, 1.0},  {1.0, -1.0},
                               {inf, 1.0},    {1.0, inf},      {1.0, -inf}, {1e-300, 1.0},
                               {1.0, 1e-300}, {1e300, -1e300}, {3.0, 4.0},  {4.0, -3.0}};
    for (const auto& c : cases)
        EXPECT_LE(ulps_apart(vector_angle(c[0], c[1]), std::atan2(c[0], c[1])), 1)
            << "atan2(" << c[0] << ", " << c[1] << ")";
    EXPECT_EQ(vector_angle(0.0, 1.0), 0.0);
    EXPECT_EQ(vector_angle(0.0, -0.0), std::atan2(0.0, -0.0)); // pi: a corner folded flat
    EXPECT_TRUE(std::isnan(vector_angle(std::nan(""), 1.0)));
    EXPECT_TRUE(std::isnan(vector_angle(1.0, std::nan(""))));
}

// Random directions over 60 binary orders of magnitude, needles and near-flat corners among
// them: measured at most 2 units in the last place from the correctly rounded atan2, three in
// four exactly equal. A term of the series less, or a wrong table entry, is hundreds off.
TEST(VectorAngle, WithinTwoUnitsInTheLastPlace) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> unit(-1.0, 1.0), exponent(-30.0, 30.0);
    std::int64_t worst = 0;
    int exact = 0;
    constexpr int kCount = 1 << 20;
    for (int i = 0; i < kCount; ++i) {
        const double scale = std::exp2(exponent(rng));
        const double y = std::abs(unit(rng)) * scale * (i % 7 == 0 ? 1e-9 : 1.0);
        const double x = unit(rng) * scale * (i % 11 == 0 ? 1e-9 : 1.0);
        const std::int64_t apart = ulps_apart(vector_angle(y, x), std::atan2(y, x));
        worst = std::max(worst, apart);
        exact += apart == 0;
    }
    EXPECT_LE(worst, 2);
    EXPECT_GT(exact, kCount / 2);
}

} // namespace
} // namespace snert::detail
