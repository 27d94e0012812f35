// Volume sampling and gradients.
#include "volume.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "mesh.h"
#include "parallel.h"

namespace snert {

Volume make_volume(glm::ivec3 dims, float value) {
    if (dims.x < 1 || dims.y < 1 || dims.z < 1)
        throw std::invalid_argument("volume dimensions must be at least 1");
    const std::size_t limit = std::numeric_limits<std::size_t>::max() / sizeof(float);
    std::size_t count = std::size_t(dims.x);
    for (int axis = 1; axis < 3; ++axis) {
        if (count > limit / std::size_t(dims[axis]))
            throw std::invalid_argument("volume dimensions overflow the sample count");
        count *= std::size_t(dims[axis]);
    }
    Volume volume;
    volume.dims = dims;
    volume.samples.assign(count, value);
    return volume;
}

glm::mat3 index_to_world_linear(const Volume& volume) {
    glm::mat3 m = volume.direction;
    for (int axis = 0; axis < 3; ++axis) m[axis] *= volume.spacing[axis];
    return m;
}

glm::vec3 index_to_world(const Volume& volume, glm::vec3 index_point) {
    return volume.origin + index_to_world_linear(volume) * index_point;
}

glm::vec3 world_to_index(const Volume& volume, glm::vec3 world_point) {
    return world_to_index_map(volume)(world_point);
}

namespace {

// Lower corner and fractions of the cell holding p, clamped to the grid.
struct Cell {
    glm::ivec3 base;
    glm::vec3 t;
};

// Inlined into every sampler (as is mix_corners): the accuracy's sample points mostly find their
// cell kept, and then the calls took a third of a sample's time.
[[gnu::always_inline]] inline Cell locate(glm::ivec3 dims, glm::vec3 p) {
    Cell cell;
    for (int a = 0; a < 3; ++a) {
        const float hi = float(dims[a] - 1);
        const float q = std::clamp(std::isfinite(p[a]) ? p[a] : 0.0f, 0.0f, hi);
        int b = std::min(int(q), std::max(dims[a] - 2, 0));
        cell.base[a] = b;
        cell.t[a] = dims[a] > 1 ? q - float(b) : 0.0f;
    }
    return cell;
}

template <class T, class Fetch> T trilinear(glm::ivec3 dims, glm::vec3 p, Fetch fetch) {
    const Cell c = locate(dims, p);
    const int x1 = std::min(c.base.x + 1, dims.x - 1);
    const int y1 = std::min(c.base.y + 1, dims.y - 1);
    const int z1 = std::min(c.base.z + 1, dims.z - 1);
    const int x0 = c.base.x, y0 = c.base.y, z0 = c.base.z;
    const T c00 = glm::mix(fetch(x0, y0, z0), fetch(x1, y0, z0), c.t.x);
    const T c10 = glm::mix(fetch(x0, y1, z0), fetch(x1, y1, z0), c.t.x);
    const T c01 = glm::mix(fetch(x0, y0, z1), fetch(x1, y0, z1), c.t.x);
    const T c11 = glm::mix(fetch(x0, y1, z1), fetch(x1, y1, z1), c.t.x);
    return glm::mix(glm::mix(c00, c10, c.t.y), glm::mix(c01, c11, c.t.y), c.t.z);
}

// Central difference at a sample, one-sided where a neighbour is missing.
glm::vec3 central_difference(const Volume& v, int x, int y, int z) {
    glm::vec3 g(0.0f);
    const glm::ivec3 p(x, y, z);
    for (int a = 0; a < 3; ++a) {
        glm::ivec3 lo = p, hi = p;
        lo[a] = std::max(p[a] - 1, 0);
        hi[a] = std::min(p[a] + 1, v.dims[a] - 1);
        const int span = hi[a] - lo[a];
        if (span > 0) g[a] = (v.at(hi.x, hi.y, hi.z) - v.at(lo.x, lo.y, lo.z)) / float(span);
    }
    return g;
}

} // namespace

float sample_trilinear(const Volume& volume, glm::vec3 p) {
    return trilinear<float>(volume.dims, p,
                            [&](int x, int y, int z) { return volume.at(x, y, z); });
}

glm::vec3 gradient_central(const Volume& volume, glm::vec3 p) {
    return trilinear<glm::vec3>(
        volume.dims, p, [&](int x, int y, int z) { return central_difference(volume, x, y, z); });
}

namespace {

// Along one axis, for the two corners of the cell at `base` (the second clamped to the grid as
// trilinear() clamps it): the sample offsets of the corner and of its central-difference
// neighbours (one-sided at the border), and the span between those, as central_difference()
// takes them. The span is 1 or 2, so a product with its inverse is exactly the quotient, at a
// fraction of its cost.
struct AxisOffsets {
    std::ptrdiff_t at[2], lo[2], hi[2];
    float span[2], inverse[2];
};

AxisOffsets axis_offsets(int base, int n, std::ptrdiff_t stride) {
    AxisOffsets o{};
    for (int c = 0; c < 2; ++c) {
        const int x = std::min(base + c, n - 1);
        const int lo = std::max(x - 1, 0), hi = std::min(x + 1, n - 1);
        o.at[c] = x * stride;
        o.lo[c] = lo * stride;
        o.hi[c] = hi * stride;
        o.span[c] = float(hi - lo);
        o.inverse[c] = hi - lo == 2 ? 0.5f : hi > lo ? 1.0f : 0.0f; // 1 / span, exactly
    }
    return o;
}

} // namespace

namespace {

// Every corner of a cell at least one sample in from each face has both neighbours on every axis:
// the differences are all (hi - lo) * 0.5, as the general path below takes them for a span of 2.
bool is_interior_cell(glm::ivec3 base, glm::ivec3 dims) {
    return base.x >= 1 && base.y >= 1 && base.z >= 1 && base.x + 3 <= dims.x &&
           base.y + 3 <= dims.y && base.z + 3 <= dims.z;
}

// One 16-byte store of a corner's four values: the mix reads each corner as one vector, and four
// separate stores just before that read would stall it (the processor cannot forward them).
void store_corner(float* corner, float value, float dx, float dy, float dz) {
#if defined(__SSE2__)
    _mm_store_ps(corner, _mm_setr_ps(value, dx, dy, dz));
#else
    corner[0] = value;
    corner[1] = dx;
    corner[2] = dy;
    corner[3] = dz;
#endif
}

void fill_cell_corners(const Volume& volume, glm::ivec3 base, CellCorners& out) {
    const std::ptrdiff_t row = volume.dims.x, plane = std::ptrdiff_t(volume.dims.x) * volume.dims.y;
    const float* s = volume.samples.data();
    out.base = base;
    if (is_interior_cell(base, volume.dims)) {
        const float* cell = s + base.x + base.y * row + base.z * plane;
        for (int k = 0; k < 8; ++k) {
            const float* q = cell + (k & 1) + (k >> 1 & 1) * row + (k >> 2) * plane;
            store_corner(out.corner[k], q[0], (q[1] - q[-1]) * 0.5f, (q[row] - q[-row]) * 0.5f,
                         (q[plane] - q[-plane]) * 0.5f);
        }
        return;
    }
    const AxisOffsets ax = axis_offsets(base.x, volume.dims.x, 1);
    const AxisOffsets ay = axis_offsets(base.y, volume.dims.y, row);
    const AxisOffsets az = axis_offsets(base.z, volume.dims.z, plane);
    for (int k = 0; k < 8; ++k) {
        const int x = k & 1, y = k >> 1 & 1, z = k >> 2;
        const std::ptrdiff_t yz = ay.at[y] + az.at[z], xz = ax.at[x] + az.at[z],
                             xy = ax.at[x] + ay.at[y];
        store_corner(
            out.corner[k], s[ax.at[x] + yz],
            ax.span[x] > 0.0f ? (s[ax.hi[x] + yz] - s[ax.lo[x] + yz]) * ax.inverse[x] : 0.0f,
            ay.span[y] > 0.0f ? (s[ay.hi[y] + xz] - s[ay.lo[y] + xz]) * ay.inverse[y] : 0.0f,
            az.span[z] > 0.0f ? (s[az.hi[z] + xy] - s[az.lo[z] + xy]) * az.inverse[z] : 0.0f);
    }
}

// glm::mix's x (1 - a) + y a for the four values of a corner at once.
[[gnu::always_inline]] inline void mix4(const float* x, const float* y, float a, float* out) {
    for (int i = 0; i < 4; ++i) out[i] = x[i] * (1.0f - a) + y[i] * a;
}

// The trilinear mix of a cell's corners at `t`, in trilinear()'s order of mixes, so that the
// value and the gradient equal the separate functions' bit for bit.
[[gnu::always_inline]] inline ValueGradient mix_corners(const CellCorners& cell, glm::vec3 t) {
    alignas(16) float c00[4], c10[4], c01[4], c11[4], c0[4], c1[4], r[4];
    mix4(cell.corner[0], cell.corner[1], t.x, c00);
    mix4(cell.corner[2], cell.corner[3], t.x, c10);
    mix4(cell.corner[4], cell.corner[5], t.x, c01);
    mix4(cell.corner[6], cell.corner[7], t.x, c11);
    mix4(c00, c10, t.y, c0);
    mix4(c01, c11, t.y, c1);
    mix4(c0, c1, t.z, r);
    return {r[0], {r[1], r[2], r[3]}};
}

} // namespace

ValueGradient sample_value_gradient(const Volume& volume, glm::vec3 p, CellCorners& kept) {
    const Cell cell = locate(volume.dims, p);
    if (cell.base != kept.base) fill_cell_corners(volume, cell.base, kept);
    return mix_corners(kept, cell.t);
}

ValueGradient sample_value_gradient(const Volume& volume, glm::vec3 p, CellCornerCache& kept) {
    const Cell cell = locate(volume.dims, p);
    const int parity = (cell.base.x & 1) | (cell.base.y & 1) << 1 | (cell.base.z & 1) << 2;
    CellCorners& corners = kept.by_parity[parity];
    if (cell.base != corners.base) fill_cell_corners(volume, cell.base, corners);
    return mix_corners(corners, cell.t);
}

ValueGradient sample_value_gradient(const Volume& volume, glm::vec3 p) {
    CellCorners corners;
    return sample_value_gradient(volume, p, corners);
}

ValueGradient sample_trilinear_with_gradient(const Volume& volume, glm::vec3 p) {
    const Cell c = locate(volume.dims, p);
    const int x1 = std::min(c.base.x + 1, volume.dims.x - 1);
    const int y1 = std::min(c.base.y + 1, volume.dims.y - 1);
    const int z1 = std::min(c.base.z + 1, volume.dims.z - 1);
    const int x0 = c.base.x, y0 = c.base.y, z0 = c.base.z;
    const float v000 = volume.at(x0, y0, z0), v100 = volume.at(x1, y0, z0);
    const float v010 = volume.at(x0, y1, z0), v110 = volume.at(x1, y1, z0);
    const float v001 = volume.at(x0, y0, z1), v101 = volume.at(x1, y0, z1);
    const float v011 = volume.at(x0, y1, z1), v111 = volume.at(x1, y1, z1);
    const glm::vec3 t = c.t;
    // The value: trilinear()'s order of mixes, so it equals sample_trilinear().
    const float c00 = glm::mix(v000, v100, t.x), c10 = glm::mix(v010, v110, t.x);
    const float c01 = glm::mix(v001, v101, t.x), c11 = glm::mix(v011, v111, t.x);
    const float c0 = glm::mix(c00, c10, t.y), c1 = glm::mix(c01, c11, t.y);
    ValueGradient out;
    out.value = glm::mix(c0, c1, t.z);
    // d/dz is the difference of the two bilinear faces; d/dy and d/dx the same one level down.
    out.gradient.z = c1 - c0;
    out.gradient.y = glm::mix(c10 - c00, c11 - c01, t.z);
    out.gradient.x = glm::mix(glm::mix(v100 - v000, v110 - v010, t.y),
                              glm::mix(v101 - v001, v111 - v011, t.y), t.z);
    return out;
}

void prefetch_cell(const Volume& volume, glm::vec3 p) {
    if (volume.samples.empty()) return;
    const Cell c = locate(volume.dims, p);
    const std::size_t row = std::size_t(volume.dims.x);
    const std::size_t plane = row * std::size_t(volume.dims.y);
    const std::size_t last = volume.samples.size() - 1;
    const std::size_t first = volume.index(c.base.x, c.base.y, c.base.z);
    // The second sample of a row can start the next cache line: a second hint for it.
    for (const std::size_t offset : {std::size_t(0), row, plane, plane + row}) {
        const float* sample = &volume.samples[std::min(first + offset, last)];
        __builtin_prefetch(sample);
        __builtin_prefetch(sample + 1);
    }
}

glm::vec3 sample_trilinear(const GradientField& field, glm::vec3 p) {
    return trilinear<glm::vec3>(field.dims, p, [&](int x, int y, int z) {
        return field.values[(std::size_t(z) * field.dims.y + y) * field.dims.x + x];
    });
}

GradientField gradient_field_central(const Volume& volume) {
    GradientField field{volume.dims, std::vector<glm::vec3>(volume.voxel_count())};
    for (int z = 0; z < volume.dims.z; ++z)
        for (int y = 0; y < volume.dims.y; ++y)
            for (int x = 0; x < volume.dims.x; ++x)
                field.values[volume.index(x, y, z)] = central_difference(volume, x, y, z);
    return field;
}

namespace {

// Convolves `in` along one axis with `kernel` (centred, radius = size / 2), clamping at the border.
void convolve_axis(const std::vector<float>& in, std::vector<float>& out, glm::ivec3 dims, int axis,
                   const std::vector<float>& kernel) {
    const int radius = int(kernel.size() / 2);
    const std::size_t stride = axis == 0   ? 1
                               : axis == 1 ? std::size_t(dims.x)
                                           : std::size_t(dims.x) * dims.y;
    const int n = dims[axis];
    for (int z = 0; z < dims.z; ++z)
        for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x) {
                const glm::ivec3 p(x, y, z);
                const std::size_t here = (std::size_t(z) * dims.y + y) * dims.x + x;
                const std::size_t line = here - std::size_t(p[axis]) * stride;
                float sum = 0.0f;
                for (std::size_t i = 0; i < kernel.size(); ++i) {
                    const int q = std::clamp(p[axis] + int(i) - radius, 0, n - 1);
                    sum += kernel[i] * in[line + std::size_t(q) * stride];
                }
                out[here] = sum;
            }
}

} // namespace

GradientField gradient_field_gaussian(const Volume& volume, float sigma) {
    if (!(sigma > 0.0f)) return gradient_field_central(volume);
    const int radius = std::max(1, int(std::ceil(3.0f * sigma)));
    std::vector<float> smooth(std::size_t(2 * radius + 1)), derivative(smooth.size());
    float sum = 0.0f, moment = 0.0f;
    for (std::size_t i = 0; i < smooth.size(); ++i) {
        const float k = float(int(i) - radius);
        smooth[i] = std::exp(-0.5f * k * k / (sigma * sigma));
        sum += smooth[i];
    }
    for (auto& w : smooth) w /= sum;
    // Derivative kernel k * G(k) / sum(k^2 G(k)): returns slope 1 on a unit ramp, since
    // convolve_axis sums kernel[k] * f(x + k) without flipping.
    for (std::size_t i = 0; i < smooth.size(); ++i) {
        const float k = float(int(i) - radius);
        derivative[i] = k * smooth[i];
        moment += k * k * smooth[i];
    }
    for (auto& w : derivative) w /= moment;

    GradientField field{volume.dims, std::vector<glm::vec3>(volume.voxel_count())};
    std::vector<float> a(volume.voxel_count()), b(volume.voxel_count());
    for (int axis = 0; axis < 3; ++axis) {
        const std::vector<float>* src = &volume.samples;
        std::vector<float>* bufs[2] = {&a, &b};
        int which = 0;
        for (int pass = 0; pass < 3; ++pass) {
            convolve_axis(*src, *bufs[which], volume.dims, pass,
                          pass == axis ? derivative : smooth);
            src = bufs[which];
            which ^= 1;
        }
        for (std::size_t i = 0; i < field.values.size(); ++i) field.values[i][axis] = (*src)[i];
    }
    return field;
}

namespace {

// The least and greatest finite values of v[0 .. n), folded into lo and hi.
void fold_finite_range(const float* v, std::size_t n, float& lo, float& hi) {
    constexpr float kInf = std::numeric_limits<float>::infinity();
    std::size_t i = 0;
#if defined(__SSE2__)
    // Four lanes at a time: a sample is finite exactly when v - v is 0 (NaN for NaN and the
    // infinities); others enter as the identity of min and max. The compiler leaves the scalar
    // loop unvectorised (min and max of floats are not associative for it).
    const __m128 inf = _mm_set1_ps(kInf), zero = _mm_setzero_ps();
    __m128 lo4 = inf, hi4 = _mm_sub_ps(zero, inf);
    for (; i + 4 <= n; i += 4) {
        const __m128 x = _mm_loadu_ps(v + i);
        const __m128 finite = _mm_cmpeq_ps(_mm_sub_ps(x, x), zero);
        lo4 = _mm_min_ps(lo4, _mm_or_ps(_mm_and_ps(finite, x), _mm_andnot_ps(finite, inf)));
        hi4 = _mm_max_ps(
            hi4, _mm_or_ps(_mm_and_ps(finite, x), _mm_andnot_ps(finite, _mm_sub_ps(zero, inf))));
    }
    alignas(16) float lanes_lo[4], lanes_hi[4];
    _mm_store_ps(lanes_lo, lo4);
    _mm_store_ps(lanes_hi, hi4);
    for (int k = 0; k < 4; ++k) {
        lo = std::min(lo, lanes_lo[k]);
        hi = std::max(hi, lanes_hi[k]);
    }
#endif
    for (; i < n; ++i) {
        if (!std::isfinite(v[i])) continue;
        lo = std::min(lo, v[i]);
        hi = std::max(hi, v[i]);
    }
}

} // namespace

ValueRange value_range(const Volume& volume) {
    // In chunks on every thread (every loader and the app's volume statistics read a clinical
    // CT's 420 MB here, 30-40 ms on one thread), combined in chunk order.
    constexpr std::size_t kChunk = std::size_t(1) << 22;
    constexpr float kInf = std::numeric_limits<float>::infinity();
    const std::size_t n = volume.samples.size();
    std::vector<ValueRange> parts(chunk_count(n, kChunk), ValueRange{kInf, -kInf});
    for_each_chunk(n, kChunk, [&](std::size_t chunk, std::size_t first, std::size_t end) {
        ValueRange part{kInf, -kInf};
        fold_finite_range(volume.samples.data() + first, end - first, part.min, part.max);
        parts[chunk] = part;
    });
    float lo = kInf, hi = -kInf;
    for (const ValueRange& part : parts) {
        lo = std::min(lo, part.min);
        hi = std::max(hi, part.max);
    }
    if (!(lo <= hi)) return ValueRange{}; // no finite sample
    return ValueRange{lo, hi};
}

} // namespace snert
