// NRRD, NIfTI, MetaImage and VTK legacy files through ITK's ImageIO classes.
//
// This work is based on ITK 5.2 ImageIO (ImageIOBase::ReadImageInformation, then Read into a
// caller's buffer), which turns every format's geometry into ITK's LPS world frame.
//
// ITK 5.2 zero-fills truncated NIfTI / MetaImage / VTK data silently, and allocates a
// header's size before anything is read. So the header is read first, sizes are checked
// against the file (nrrd.cpp, metaimage.cpp, vtk_legacy.cpp, nifti.cpp) and the memory
// (sizes.cpp), and only then is the grid allocated and ITK asked for the samples.
#include "itk_image_io.h"

#include <algorithm>
#include <mutex>
#include <stdexcept>
#include <vector>

#include <itkImageIOBase.h>
#include <itkImageIOFactory.h>
#include <itkMetaImageIOFactory.h>
#include <itkNiftiImageIOFactory.h>
#include <itkNrrdImageIOFactory.h>
#include <itkVTKImageIOFactory.h>

#include "file_bytes.h"
#include "itk_support.h"
#include "metaimage.h"
#include "nifti.h"
#include "nrrd.h"
#include "sizes.h"
#include "volume_result.h"
#include "vtk_legacy.h"

namespace snert::detail {

namespace {

// The four file-format factories, registered once by hand (no generated ITK registration
// header). GDCM is deliberately not registered: DICOM is only ever touched in a child.
void register_factories() {
    static std::once_flag once;
    std::call_once(once, [] {
        itk::NrrdImageIOFactory::RegisterOneFactory();
        itk::NiftiImageIOFactory::RegisterOneFactory();
        itk::MetaImageIOFactory::RegisterOneFactory();
        itk::VTKImageIOFactory::RegisterOneFactory();
        // Our own checks report problems; ITK's warnings would only repeat them on stderr.
        itk::Object::GlobalWarningDisplayOff();
    });
}

Geometry geometry_of(const itk::ImageIOBase& io) {
    Geometry g;
    const unsigned axes = std::min(io.GetNumberOfDimensions(), 3u);
    for (unsigned a = 0; a < axes; ++a) {
        g.spacing[int(a)] = float(io.GetSpacing(a));
        g.origin[int(a)] = float(io.GetOrigin(a));
        const std::vector<double> column = io.GetDirection(a);
        glm::vec3 d(0.0f); // a 2-D image's axes lie in the z = 0 plane
        for (std::size_t r = 0; r < std::min<std::size_t>(column.size(), 3); ++r)
            d[int(r)] = float(column[r]);
        g.direction[int(a)] = d;
    }
    return g;
}

std::string format_name(const itk::ImageIOBase& io) {
    const std::string name = io.GetNameOfClass();
    if (name == "NrrdImageIO") return "NRRD";
    if (name == "NiftiImageIO") return "NIfTI";
    if (name == "MetaImageIO") return "MetaImage";
    if (name == "VTKImageIO") return "VTK";
    return name;
}

// ---- Files read through ImageIO ---------------------------------------------------------------

struct Header {
    glm::ivec3 dims{0};
    ScalarType type = ScalarType::UInt8;
    std::vector<itk::SizeValueType> size; // per ITK axis
};

Header checked_header(const std::string& path, const itk::ImageIOBase& io) {
    if (io.GetNumberOfComponents() != 1)
        throw std::runtime_error(path + ": has " + std::to_string(io.GetNumberOfComponents()) +
                                 " components per voxel (" +
                                 itk::ImageIOBase::GetPixelTypeAsString(io.GetPixelType()) +
                                 "); snert reads scalar volumes");
    Header h;
    const auto type = scalar_type_of(io.GetComponentType());
    if (!type)
        throw std::runtime_error(path + ": unsupported sample type " +
                                 itk::ImageIOBase::GetComponentTypeAsString(io.GetComponentType()));
    h.type = *type;
    const unsigned axes = io.GetNumberOfDimensions();
    std::uint64_t d[3] = {1, 1, 1};
    for (unsigned a = 0; a < axes; ++a) {
        h.size.push_back(io.GetDimensions(a));
        if (a < 3)
            d[a] = io.GetDimensions(a);
        else if (io.GetDimensions(a) != 1)
            throw std::runtime_error(path + ": is a " + std::to_string(axes) + "-D image with " +
                                     std::to_string(io.GetDimensions(a)) + " entries along axis " +
                                     std::to_string(a + 1) + "; snert reads one 3-D volume");
    }
    if (axes == 0) throw std::runtime_error(path + ": the header gives no dimensions");
    h.dims = checked_dims(path, d[0], d[1], d[2]);
    return h;
}

// Reads all samples through io->Read: into the grid's tail and widened in place for types of
// up to 4 bytes (no second full-size copy), through one temporary buffer for 8-byte types.
void read_through_imageio(itk::ImageIOBase& io, const Header& h, Volume& volume) {
    itk::ImageIORegion region(unsigned(h.size.size()));
    for (unsigned a = 0; a < h.size.size(); ++a) {
        region.SetIndex(a, 0);
        region.SetSize(a, h.size[a]);
    }
    io.SetIORegion(region);
    const std::size_t count = volume.voxel_count();
    float* out = volume.samples.data();
    if (scalar_type_size(h.type) <= sizeof(float)) {
        io.Read(stored_tail(out, count, h.type));
        convert_in_place(out, count, h.type, native_endian());
    } else {
        std::vector<unsigned char> stored(count * scalar_type_size(h.type));
        io.Read(stored.data());
        convert_samples(stored.data(), count, h.type, native_endian(), out);
    }
}

LoadedVolume open_nifti(const std::string& path, itk::ImageIOBase& io, const LoadOptions& options);

LoadedVolume open_with_imageio(const std::string& path, itk::ImageIOBase& io,
                               const LoadOptions& options) {
    const std::string format = format_name(io);
    const std::string ext = volume_extension(path);
    if (format == "NIfTI" && (ext == ".nii" || ext == ".nii.gz")) {
        // Single-file NIfTI is read by snert itself (straight into the grid, size-checked);
        // Analyze and .hdr/.img pairs go through ITK below.
        if (read_nifti_header(path).single_file) return open_nifti(path, io, options);
    }
    // snert's own checks first: ITK would allocate whatever the header claims, zero-fill what is
    // missing, and report absurd sizes in its parser's words.
    if (format == "NRRD") check_nrrd_data(path, options.memory_limit_bytes);
    if (format == "MetaImage") check_metaimage_data(path, options.memory_limit_bytes);
    if (format == "VTK") check_vtk_data(path, options.memory_limit_bytes);
    try {
        io.SetFileName(path);
        io.ReadImageInformation();
    } catch (const itk::ExceptionObject& e) {
        throw_itk(path, e);
    }
    const Header h = checked_header(path, io);
    const std::size_t size = scalar_type_size(h.type);
    const std::uint64_t voxels =
        std::uint64_t(h.dims.x) * std::uint64_t(h.dims.y) * std::uint64_t(h.dims.z);
    check_memory(path, h.dims, size > sizeof(float) ? voxels * size : 0,
                 options.memory_limit_bytes);
    Geometry g = geometry_of(io);
    LoadedVolume loaded;
    loaded.volume = allocate_volume(path, h.dims, g);
    Volume& v = loaded.volume;
    options.progress.update(0.0f);
    try {
        read_through_imageio(io, h, v);
    } catch (const itk::ExceptionObject& e) {
        throw_itk(path, e);
    }
    loaded.info = make_info(path, format, h.type, v);
    finish_volume(loaded, h.type, options);
    return loaded;
}

LoadedVolume open_nifti(const std::string& path, itk::ImageIOBase& io, const LoadOptions& options) {
    const NiftiHeader nh = read_nifti_header(path);
    if (!nh.type)
        throw std::runtime_error(
            path + ": unsupported NIfTI datatype " + std::to_string(nh.datatype) + " (" +
            nifti_datatype_name(nh.datatype) + "); snert reads scalar integer and float volumes");
    if (nh.volumes() > 1)
        throw std::runtime_error(path + ": is a " + std::to_string(nh.dim[0]) +
                                 "-D NIfTI holding " + std::to_string(nh.volumes()) +
                                 " volumes; snert reads one 3-D volume");
    const glm::ivec3 dims =
        checked_dims(path, std::uint64_t(nh.dim[1]), std::uint64_t(nh.dim[0] >= 2 ? nh.dim[2] : 1),
                     std::uint64_t(nh.dim[0] >= 3 ? nh.dim[3] : 1));
    check_memory(path, dims, 0, options.memory_limit_bytes);
    try {
        io.SetFileName(path);
        io.ReadImageInformation(); // geometry: ITK turns qform / sform (RAS) into LPS
    } catch (const itk::ExceptionObject& e) {
        throw_itk(path, e);
    }
    const Header h = checked_header(path, io);
    if (h.dims != dims) throw std::runtime_error(path + ": inconsistent NIfTI header dimensions");
    const std::uint64_t data_bytes = nh.voxels() * scalar_type_size(*nh.type);
    if (volume_extension(path) == ".nii") {
        // Uncompressed: the size is known before anything is allocated.
        const std::uint64_t size = file_size(path);
        const std::uint64_t have = size > nh.vox_offset ? size - nh.vox_offset : 0;
        if (have < data_bytes)
            throw std::runtime_error(path + ": truncated NIfTI: the header promises " +
                                     std::to_string(data_bytes) + " data bytes from offset " +
                                     std::to_string(nh.vox_offset) + ", the file holds " +
                                     std::to_string(have));
    }
    Geometry g = geometry_of(io);
    LoadedVolume loaded;
    loaded.volume = allocate_volume(path, h.dims, g);
    Volume& v = loaded.volume;
    options.progress.update(0.0f);
    read_nifti_samples(path, nh, v.samples.data(), options.progress);
    loaded.info = make_info(path, "NIfTI", *nh.type, v);
    // Rescaled integers become floats; the policy still applies to the stored type's meaning.
    finish_volume(loaded, nh.rescales() ? ScalarType::Float32 : *nh.type, options);
    return loaded;
}

} // namespace

LoadedVolume open_with_image_io(const std::string& path, const LoadOptions& options) {
    register_factories();
    itk::ImageIOBase::Pointer io;
    try {
        io = itk::ImageIOFactory::CreateImageIO(path.c_str(), itk::IOFileModeEnum::ReadMode);
    } catch (const itk::ExceptionObject& e) {
        throw_itk(path, e);
    }
    if (!io)
        throw std::runtime_error(path + ": not a volume format snert reads (NRRD, NIfTI, "
                                        "MetaImage, VTK legacy, DICOM; headerless data needs "
                                        "the raw options)");
    return open_with_imageio(path, *io, options);
}

} // namespace snert::detail

#if defined(__SANITIZE_ADDRESS__)
// ITK's NRRD reader does not free its error text and state when it throws (NrrdImageIO::Read,
// "would be nice to free(err)"); LeakSanitizer would turn every refused NRRD into a failure.
// Only leaks whose stack passes through ITK's NrrdIO library are suppressed.
extern "C" const char* __lsan_default_suppressions() {
    return "leak:libITKNrrdIO\n";
}
#endif
