// The angle between two vectors from the length of their cross product and their dot product,
// atan2(|u x w|, u . w): exact for needles too, where acos(u . w / (|u| |w|)) loses every digit.
// (Internal to snert_core.)
//
// Triangle quality, smoothness and the mesh guard take two or three such angles a triangle, a
// clinical mesh has millions, and the app measures every iteration's mesh: the C library's
// atan2 (correctly rounded, about 25 ns a call here) took a tenth of the app's processor time on
// a CT. Here the angle is reduced to atan(a), 0 <= a <= 1, and then to atan(c) + atan(t) with c
// the nearest multiple of 1/64 (a table) and |t| <= 1/128, where four terms of atan's series
// leave an error under 2^-58 of t: in half the time, within 2 units in the last place of
// std::atan2 (tests/core/test_vector_angle.cpp), the same on every machine and build.
#pragma once

#include <algorithm>
#include <cmath>

namespace snert::detail {

// atan(k / 64) for k = 0 .. 64, each rounded to the nearest double.
inline constexpr double kAtanOfSixtyFourths[65] = {
    0.0,
    0.015623728620476831,
    0.031239833430268277,
    0.046840712915969654,
    0.06241880999595735,
    0.0779666338315423,
    0.09347678115858947,
    0.10894195698986579,
    0.12435499454676144,
    0.13970887428916365,
    0.15499674192394097,
    0.1702119252854744,
    0.18534794999569476,
    0.2003985538258785,
    0.21535769969773805,
    0.23021958727684372,
    0.24497866312686414,
    0.2596296294082575,
    0.2741674511196588,
    0.2885873618940774,
    0.3028848683749714,
    0.31705575320914703,
    0.3310960767041321,
    0.34500217720710513,
    0.35877067027057225,
    0.3723984466767542,
    0.38588266939807375,
    0.39922076957525254,
    0.4124104415973873,
    0.42544963737004227,
    0.43833655985795783,
    0.4510696559885235,
    0.4636476090008061,
    0.4760693303227612,
    0.48833395105640554,
    0.5004408131472942,
    0.5123894603107377,
    0.5241796287829132,
    0.5358112379604637,
    0.5472843809874369,
    0.5585993153435624,
    0.5697564534829784,
    0.5807563535676704,
    0.5915997103351114,
    0.6022873461349642,
    0.6128202021652414,
    0.6231993299340659,
    0.6334258829691446,
    0.6435011087932844,
    0.6534263411807619,
    0.6632029927060933,
    0.6728325475937632,
    0.6823165548747481,
    0.6916566218531999,
    0.7008544078844502,
    0.7099116184635249,
    0.7188299996216245,
    0.7276113326265107,
    0.7362574289814281,
    0.7447701257160751,
    0.7531512809621944,
    0.7614027698055784,
    0.7695264804056583,
    0.7775243103733478,
    0.7853981633974483,
};

// The angle in [0, pi] whose sine and cosine are proportional to `cross_length` (>= 0) and
// `dot`: std::atan2(cross_length, dot), as above. NaN in, NaN out.
inline double vector_angle(double cross_length, double dot) {
    constexpr double kHalfPi = 1.5707963267948966, kPi = 3.141592653589793;
    const double along = std::abs(dot);
    if (!(cross_length > 0) || !std::isfinite(cross_length) || !std::isfinite(along)) {
        // Zero (atan2(+0, x) is 0 for x > 0 or +0, pi for x < 0 or -0), infinite or NaN input:
        // rare, so the library's answer.
        return std::atan2(cross_length, dot);
    }
    // atan(a), a = small / large in (0, 1]; the angle is then pi/2 - that where the cross
    // product is the larger, and pi - the angle where the dot product is negative.
    const bool steep = cross_length > along;
    const double a = std::min(cross_length, along) / std::max(cross_length, along);
    // The nearest k, 0 .. 64 (a >= 0; where the sum rounds up at a tie, either k will do).
    const int k = int(a * 64.0 + 0.5); // NOLINT(bugprone-incorrect-roundings)
    const double c = double(k) * (1.0 / 64.0);
    // atan(a) = atan(c) + atan(t), t = (a - c) / (1 + a c), |t| <= 1/128.
    const double t = (a - c) / (1.0 + a * c);
    const double t2 = t * t;
    const double series = t - t * t2 * (1.0 / 3.0 - t2 * (1.0 / 5.0 - t2 * (1.0 / 7.0)));
    // Selected, not branched to: on a mesh's corners both conditions come as they please.
    const double flat = kAtanOfSixtyFourths[k] + series;
    const double angle = steep ? kHalfPi - flat : flat;
    return std::signbit(dot) ? kPi - angle : angle;
}

} // namespace snert::detail
