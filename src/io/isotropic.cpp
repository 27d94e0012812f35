// Resampling to cubic voxels with ITK's ResampleImageFilter (identity transform, linear
// interpolation): the grid, the memory it needs, the grey values and a label's mask.
#include "isotropic.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <vector>

#include <itkIdentityTransform.h>
#include <itkImage.h>
#include <itkLinearInterpolateImageFunction.h>
#include <itkResampleImageFilter.h>

#include "core/parallel.h"
#include "itk_support.h"
#include "sizes.h"

namespace snert {

namespace {

using Image = itk::Image<float, 3>;

std::string number_text(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
}

std::string dims_text(glm::ivec3 d) {
    return std::to_string(d.x) + " x " + std::to_string(d.y) + " x " + std::to_string(d.z);
}

// "<name>: resampling to cubic voxels of E mm: X x Y x Z samples (spacing a x b x c mm)"
std::string what_text(const std::string& name, const Volume& volume, double edge) {
    return name + ": resampling to cubic voxels of " + number_text(edge) +
           " mm: " + dims_text(volume.dims) + " samples (spacing " + number_text(volume.spacing.x) +
           " x " + number_text(volume.spacing.y) + " x " + number_text(volume.spacing.z) + " mm)";
}

std::uint64_t saturating_product(std::uint64_t a, std::uint64_t b) {
    std::uint64_t product = 0;
    return __builtin_mul_overflow(a, b, &product) ? std::numeric_limits<std::uint64_t>::max()
                                                  : product;
}

std::uint64_t saturating_sum(std::uint64_t a, std::uint64_t b) {
    std::uint64_t sum = 0;
    return __builtin_add_overflow(a, b, &sum) ? std::numeric_limits<std::uint64_t>::max() : sum;
}

std::uint64_t sample_count(glm::ivec3 d) {
    return saturating_product(saturating_product(std::uint64_t(d.x), std::uint64_t(d.y)),
                              std::uint64_t(d.z));
}

// An ITK image over `samples` (not copied, not owned) with the geometry of `geometry`.
Image::Pointer wrap(const float* samples, const Volume& geometry) {
    Image::Pointer image = Image::New();
    Image::RegionType region;
    Image::SpacingType spacing;
    Image::PointType origin;
    Image::DirectionType direction;
    for (unsigned a = 0; a < 3; ++a) {
        region.SetSize(a, itk::SizeValueType(geometry.dims[int(a)]));
        spacing[a] = geometry.spacing[int(a)];
        origin[a] = geometry.origin[int(a)];
        for (unsigned b = 0; b < 3; ++b) direction(a, b) = geometry.direction[int(b)][int(a)];
    }
    image->SetRegions(region);
    image->SetSpacing(spacing);
    image->SetOrigin(origin);
    image->SetDirection(direction);
    Image::PixelContainer::Pointer container = Image::PixelContainer::New();
    container->SetImportPointer(const_cast<float*>(samples), geometry.voxel_count(), false);
    image->SetPixelContainer(container);
    return image;
}

// `input` resampled to `grid` by ITK: calls `take` with the output's samples (x fastest).
template <class Take>
void resample(const Image::Pointer& input, const IsotropicGrid& grid, const Take& take) {
    using Filter = itk::ResampleImageFilter<Image, Image, double>;
    Filter::Pointer filter = Filter::New();
    filter->SetInput(input);
    filter->SetTransform(itk::IdentityTransform<double, 3>::New());
    filter->SetInterpolator(itk::LinearInterpolateImageFunction<Image, double>::New());
    Image::SizeType size;
    Image::SpacingType spacing;
    Image::PointType origin;
    Image::DirectionType direction;
    for (unsigned a = 0; a < 3; ++a) {
        size[a] = itk::SizeValueType(grid.dims[int(a)]);
        spacing[a] = grid.edge;
        origin[a] = grid.origin[int(a)];
        for (unsigned b = 0; b < 3; ++b) direction(a, b) = grid.direction[int(b)][int(a)];
    }
    filter->SetSize(size);
    filter->SetOutputSpacing(spacing);
    filter->SetOutputOrigin(origin);
    filter->SetOutputDirection(direction);
    filter->SetDefaultPixelValue(0.0f); // never used: every output sample lies inside the input
    // As many threads as snert's own loops use here (a ThreadLimit holds for ITK too). The
    // result does not depend on them: ITK hands out whole rows, each sample computed alone.
    const unsigned threads = thread_budget();
    filter->GetMultiThreader()->SetMaximumNumberOfThreads(threads);
    filter->SetNumberOfWorkUnits(threads);
    try {
        filter->Update();
    } catch (const itk::ExceptionObject& e) {
        throw std::runtime_error("resampling to cubic voxels: " +
                                 detail::one_line(e.GetDescription()));
    }
    take(filter->GetOutput()->GetBufferPointer());
}

} // namespace

IsotropicGrid isotropic_grid(const std::string& name, const Volume& volume, float edge_mm) {
    const float smallest = std::min({volume.spacing.x, volume.spacing.y, volume.spacing.z});
    const double edge = edge_mm > 0.0f ? edge_mm : smallest;
    if (!(edge > 0.0) || !std::isfinite(edge) || !std::isfinite(edge_mm) || edge_mm < 0.0f)
        throw std::runtime_error(name + ": resampling to cubic voxels of " + number_text(edge_mm) +
                                 " mm: the edge must be a positive number of millimetres");
    IsotropicGrid grid;
    grid.edge = float(edge);
    grid.origin = volume.origin;
    grid.direction = volume.direction;
    for (int a = 0; a < 3; ++a) {
        // Steps of the new edge that fit in the stored extent. A count within a few float
        // roundings (of the spacing and the edge) of a whole number is that number, so an
        // extent that is a multiple of the edge keeps its last sample; ITK's interpolator reads
        // the border up to half a stored voxel beyond the last sample.
        const double steps = double(volume.dims[a] - 1) * double(volume.spacing[a]) / edge;
        if (!(steps < double(detail::max_axis_extent - 1)))
            throw std::runtime_error(what_text(name, volume, edge) + " would need more than " +
                                     std::to_string(detail::max_axis_extent) +
                                     " samples along an axis");
        const double whole = std::round(steps);
        const bool multiple = std::abs(steps - whole) <= 4e-7 * steps + 1e-6;
        grid.dims[a] = int(multiple ? whole : std::floor(steps)) + 1;
    }
    if (sample_count(grid.dims) > std::numeric_limits<std::size_t>::max() / (2 * sizeof(float)))
        throw std::runtime_error(what_text(name, volume, edge) + " would become " +
                                 dims_text(grid.dims) + ", more samples than snert can address");
    return grid;
}

bool on_grid(const Volume& volume, const IsotropicGrid& grid) {
    return volume.dims == grid.dims && volume.spacing == glm::vec3(grid.edge) &&
           volume.origin == grid.origin && volume.direction == grid.direction;
}

std::uint64_t isotropic_bytes_needed(const Volume& volume, const IsotropicGrid& grid,
                                     bool with_mask) {
    const std::uint64_t out = sample_count(grid.dims);
    const std::uint64_t out_floats = saturating_product(out, sizeof(float));
    std::uint64_t need = saturating_product(out_floats, 2); // the new grid and ITK's output
    if (with_mask) {
        const std::uint64_t in_floats =
            saturating_product(sample_count(volume.dims), sizeof(float));
        need = saturating_sum(need, in_floats);  // the stored mask as a 0/1 image
        need = saturating_sum(need, out_floats); // ITK's output
        need = saturating_sum(need, out);        // the new mask
    }
    return need;
}

void check_isotropic_memory(const std::string& name, const Volume& volume,
                            const IsotropicGrid& grid, bool with_mask, std::uint64_t limit_bytes) {
    const std::uint64_t need = isotropic_bytes_needed(volume, grid, with_mask);
    const bool explicit_limit = limit_bytes != 0;
    const std::uint64_t limit = explicit_limit ? limit_bytes : detail::available_memory_bytes();
    if (limit == 0 || need <= limit) return;
    throw std::runtime_error(
        what_text(name, volume, grid.edge) + " would become " + dims_text(grid.dims) +
        ", which need " + detail::format_bytes(need) +
        (explicit_limit ? ", above the memory limit of " + detail::format_bytes(limit)
                        : ", but only " + detail::format_bytes(limit) + " of memory is available"));
}

Volume resample_linear(const Volume& volume, const IsotropicGrid& grid) {
    Volume out = make_volume(grid.dims);
    out.spacing = glm::vec3(grid.edge);
    out.origin = grid.origin;
    out.direction = grid.direction;
    resample(wrap(volume.samples.data(), volume), grid, [&](const float* samples) {
        std::copy_n(samples, out.samples.size(), out.samples.data());
    });
    return out;
}

Segmentation resample_mask(const Segmentation& mask, const Volume& geometry,
                           const IsotropicGrid& grid) {
    Volume shape; // the geometry alone
    shape.dims = mask.dims;
    shape.spacing = geometry.spacing;
    shape.origin = geometry.origin;
    shape.direction = geometry.direction;
    std::vector<float> ones(mask.inside.size());
    std::transform(mask.inside.begin(), mask.inside.end(), ones.begin(),
                   [](std::uint8_t v) { return v ? 1.0f : 0.0f; });
    Segmentation out;
    out.dims = grid.dims;
    out.inside.resize(sample_count(grid.dims));
    resample(wrap(ones.data(), shape), grid, [&](const float* samples) {
        std::transform(samples, samples + out.inside.size(), out.inside.begin(),
                       [](float v) { return std::uint8_t(v >= 0.5f ? 1 : 0); });
    });
    return out;
}

} // namespace snert
