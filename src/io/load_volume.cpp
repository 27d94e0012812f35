// The only translation unit that includes ITK: file formats through ITK's ImageIO classes, and
// DICOM series through GDCM in a child process.
//
// This work is based on:
//  - ITK 5.2 ImageIO (ImageIOBase::ReadImageInformation, then Read into a caller's buffer),
//    which turns every format's geometry into ITK's LPS world frame;
//  - GDCM's series helper (itk::GDCMSeriesFileNames) for grouping and sorting DICOM slices by
//    their position along the slice normal.
//
// Two facts of Debian's ITK 5.2 / GDCM 3.0 shape this file:
//  - GDCM keeps its assert()s: a truncated .dcm can abort the process inside the folder scan
//    or the read. DICOM is therefore scanned and read in a forked child that streams slices
//    back through a pipe; a crash there becomes an error here.
//  - Truncated NIfTI / MetaImage / VTK / DICOM data is zero-filled silently, and a header's
//    size is allocated before anything is read. So the header is read first, sizes are checked
//    against the file (volume_headers.cpp) and the memory, and only then is the grid allocated.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <optional>
#include <stdexcept>

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <itkGDCMImageIO.h>
#include <itkGDCMSeriesFileNames.h>
#include <itkImage.h>
#include <itkImageFileReader.h>
#include <itkImageIOBase.h>
#include <itkImageIOFactory.h>
#include <itkImageSeriesReader.h>
#include <itkMetaDataObject.h>
#include <itkMetaImageIOFactory.h>
#include <itkMultiThreaderBase.h>
#include <itkNiftiImageIOFactory.h>
#include <itkNrrdImageIOFactory.h>
#include <itkVTKImageIOFactory.h>

#include "load_volume.h"
#include "volume_headers.h"

namespace snert {

namespace {

using detail::checked_dims;

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

// ITK messages span lines and name source files and object addresses; keep what they say.
// Drops each "itk::ERROR: ClassName(0x55d0...): " prefix and folds all white space.
std::string one_line(const std::string& text) {
    std::string cleaned;
    for (std::size_t pos = 0; pos < text.size();) {
        for (const std::string marker : {"ITK ERROR: ", "itk::ERROR: "}) {
            if (text.compare(pos, marker.size(), marker) != 0) continue;
            const std::size_t open = text.find("(0x", pos + marker.size());
            const std::size_t close = open == std::string::npos ? open : text.find("):", open);
            if (close != std::string::npos && close - pos < 100) {
                pos = close + 2;
                break;
            }
        }
        if (pos < text.size()) cleaned += text[pos++];
    }
    std::string folded;
    for (char c : cleaned) {
        const bool space = std::isspace(static_cast<unsigned char>(c)) != 0;
        if (space && (folded.empty() || folded.back() == ' ')) continue;
        folded += space ? ' ' : c;
    }
    while (!folded.empty() && folded.back() == ' ') folded.pop_back();
    if (folded.size() > 400) folded = folded.substr(0, 397) + "...";
    return folded;
}

[[noreturn]] void throw_itk(const std::string& path, const itk::ExceptionObject& error) {
    throw std::runtime_error(path + ": " + one_line(error.GetDescription()));
}

std::optional<ScalarType> scalar_type_of(itk::IOComponentEnum component) {
    using C = itk::IOComponentEnum;
    switch (component) {
    case C::UCHAR:
        return ScalarType::UInt8;
    case C::CHAR:
        return ScalarType::Int8;
    case C::USHORT:
        return ScalarType::UInt16;
    case C::SHORT:
        return ScalarType::Int16;
    case C::UINT:
        return ScalarType::UInt32;
    case C::INT:
        return ScalarType::Int32;
    case C::ULONG:
        return sizeof(unsigned long) == 8 ? ScalarType::UInt64 : ScalarType::UInt32;
    case C::LONG:
        return sizeof(long) == 8 ? ScalarType::Int64 : ScalarType::Int32;
    case C::ULONGLONG:
        return ScalarType::UInt64;
    case C::LONGLONG:
        return ScalarType::Int64;
    case C::FLOAT:
        return ScalarType::Float32;
    case C::DOUBLE:
        return ScalarType::Float64;
    default:
        return std::nullopt;
    }
}

bool is_float(ScalarType type) {
    return type == ScalarType::Float32 || type == ScalarType::Float64;
}

// Geometry that the file states, checked: positive finite spacing, invertible direction.
struct Geometry {
    glm::vec3 spacing{1.0f};
    glm::vec3 origin{0.0f};
    glm::mat3 direction{1.0f};
};

void check_geometry(const std::string& path, const Geometry& g) {
    for (int a = 0; a < 3; ++a)
        if (!(g.spacing[a] > 0.0f) || !std::isfinite(g.spacing[a]))
            throw std::runtime_error(path + ": invalid spacing " + std::to_string(g.spacing[a]) +
                                     " along axis " + std::to_string(a));
    for (int a = 0; a < 3; ++a)
        if (!std::isfinite(g.origin[a]))
            throw std::runtime_error(path + ": invalid (non-finite) origin");
    const float det = glm::determinant(g.direction);
    if (!std::isfinite(det) || std::abs(det) < 1e-6f)
        throw std::runtime_error(path + ": invalid direction cosines (not invertible)");
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

// The float32 grid of a volume whose geometry has been read; checks the geometry first.
Volume allocate_volume(const std::string& path, glm::ivec3 dims, const Geometry& g) {
    check_geometry(path, g);
    Volume v;
    v.dims = dims;
    v.spacing = g.spacing;
    v.origin = g.origin;
    v.direction = g.direction;
    v.samples.resize(v.voxel_count());
    return v;
}

VolumeInfo make_info(const std::string& path, const std::string& format, ScalarType type,
                     const Volume& volume) {
    VolumeInfo info;
    info.path = path;
    info.format = format;
    info.scalar_type = scalar_type_name(type);
    info.dims = volume.dims;
    info.spacing = volume.spacing;
    info.origin = volume.origin;
    info.direction = volume.direction;
    return info;
}

// Applies the NaN policy (float types only) and fills the value range.
void finish(LoadedVolume& loaded, ScalarType type, const LoadOptions& options) {
    if (is_float(type))
        loaded.info.nonfinite =
            apply_nonfinite_policy(loaded.volume, options.nonfinite, loaded.info.path).total();
    loaded.info.range = value_range(loaded.volume);
    options.progress.update(1.0f);
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
        io.Read(detail::stored_tail(out, count, h.type));
        detail::convert_in_place(out, count, h.type, detail::native_endian());
    } else {
        std::vector<unsigned char> stored(count * scalar_type_size(h.type));
        io.Read(stored.data());
        detail::convert_samples(stored.data(), count, h.type, detail::native_endian(), out);
    }
}

LoadedVolume open_nifti(const std::string& path, itk::ImageIOBase& io, const LoadOptions& options);

LoadedVolume open_with_imageio(const std::string& path, itk::ImageIOBase& io,
                               const LoadOptions& options) {
    const std::string format = format_name(io);
    const std::string ext = detail::volume_extension(path);
    if (format == "NIfTI" && (ext == ".nii" || ext == ".nii.gz")) {
        // Single-file NIfTI is read by snert itself (straight into the grid, size-checked);
        // Analyze and .hdr/.img pairs go through ITK below.
        if (detail::read_nifti_header(path).single_file) return open_nifti(path, io, options);
    }
    // snert's own checks first: ITK would allocate whatever the header claims, zero-fill what is
    // missing, and report absurd sizes in its parser's words.
    if (format == "NRRD") detail::check_nrrd_data(path, options.memory_limit_bytes);
    if (format == "MetaImage") detail::check_metaimage_data(path, options.memory_limit_bytes);
    if (format == "VTK") detail::check_vtk_data(path, options.memory_limit_bytes);
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
    detail::check_memory(path, h.dims, size > sizeof(float) ? voxels * size : 0,
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
    finish(loaded, h.type, options);
    return loaded;
}

LoadedVolume open_nifti(const std::string& path, itk::ImageIOBase& io, const LoadOptions& options) {
    const detail::NiftiHeader nh = detail::read_nifti_header(path);
    if (!nh.type)
        throw std::runtime_error(path + ": unsupported NIfTI datatype " +
                                 std::to_string(nh.datatype) + " (" +
                                 detail::nifti_datatype_name(nh.datatype) +
                                 "); snert reads scalar integer and float volumes");
    if (nh.volumes() > 1)
        throw std::runtime_error(path + ": is a " + std::to_string(nh.dim[0]) +
                                 "-D NIfTI holding " + std::to_string(nh.volumes()) +
                                 " volumes; snert reads one 3-D volume");
    const glm::ivec3 dims =
        checked_dims(path, std::uint64_t(nh.dim[1]), std::uint64_t(nh.dim[0] >= 2 ? nh.dim[2] : 1),
                     std::uint64_t(nh.dim[0] >= 3 ? nh.dim[3] : 1));
    detail::check_memory(path, dims, 0, options.memory_limit_bytes);
    try {
        io.SetFileName(path);
        io.ReadImageInformation(); // geometry: ITK turns qform / sform (RAS) into LPS
    } catch (const itk::ExceptionObject& e) {
        throw_itk(path, e);
    }
    const Header h = checked_header(path, io);
    if (h.dims != dims) throw std::runtime_error(path + ": inconsistent NIfTI header dimensions");
    const std::uint64_t data_bytes = nh.voxels() * scalar_type_size(*nh.type);
    if (detail::volume_extension(path) == ".nii") {
        // Uncompressed: the size is known before anything is allocated.
        const std::uint64_t size = detail::file_size(path);
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
    detail::read_nifti_samples(path, nh, v.samples.data(), options.progress);
    loaded.info = make_info(path, "NIfTI", *nh.type, v);
    // Rescaled integers become floats; the policy still applies to the stored type's meaning.
    finish(loaded, nh.rescales() ? ScalarType::Float32 : *nh.type, options);
    return loaded;
}

// ---- DICOM in a child process ------------------------------------------------------------------
//
// Protocol on the pipe from child to parent: messages of a tag byte, a 64-bit length and the
// payload. 'H' header (WireHeader + series UID), 'D' samples of whole slices, in order, 'L' a
// series list ("uid\tfiles\n" lines), 'E' an error message, 'K' done.

struct WireHeader {
    std::int64_t dims[3];
    double spacing[3];
    double origin[3];
    double direction[9]; // column-major: direction[3 * c + r]
    std::int32_t type;   // ScalarType stored in the files
    std::int64_t files;
};

struct DicomRequest {
    std::string folder;
    std::string uid;  // wanted series; empty: largest (or the one holding `file`)
    std::string file; // a .dcm the user named; its series is read
    bool list_only = false;
};

bool write_all(int fd, const void* data, std::size_t size) {
    const auto* p = static_cast<const char*>(data);
    while (size > 0) {
        const ssize_t n = ::write(fd, p, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        p += n;
        size -= std::size_t(n);
    }
    return true;
}

bool send_message(int fd, char tag, const void* data, std::uint64_t size) {
    return write_all(fd, &tag, 1) && write_all(fd, &size, sizeof size) &&
           write_all(fd, data, std::size_t(size));
}

bool send_text(int fd, char tag, const std::string& text) {
    return send_message(fd, tag, text.data(), text.size());
}

std::string real_path(const std::string& path) {
    char buffer[PATH_MAX];
    return ::realpath(path.c_str(), buffer) ? std::string(buffer) : path;
}

bool uncompressed_syntax(const std::string& uid, bool& big_endian) {
    std::string clean = uid;
    while (!clean.empty() && (clean.back() == '\0' || clean.back() == ' ')) clean.pop_back();
    big_endian = clean == "1.2.840.10008.1.2.2";
    return clean == "1.2.840.10008.1.2" || clean == "1.2.840.10008.1.2.1" || big_endian;
}

// Refuses a file whose Pixel Data is cut short (GDCM would zero-fill it silently).
void check_slice_file(const std::string& file, std::uint64_t expected,
                      const std::string& transfer_syntax) {
    bool big_endian = false;
    const bool uncompressed = uncompressed_syntax(transfer_syntax, big_endian);
    const auto bytes = detail::read_file_prefix(file, std::size_t(detail::file_size(file)));
    const auto check =
        detail::check_dicom_pixel_data(bytes.data(), bytes.size(), expected, big_endian);
    if (check.state == detail::PixelDataCheck::Truncated)
        throw std::runtime_error(file + ": truncated DICOM: the pixel data needs " +
                                 std::to_string(expected) + " bytes, the file holds " +
                                 std::to_string(check.available));
    if (check.state == detail::PixelDataCheck::NotFound && uncompressed)
        throw std::runtime_error(file + ": damaged DICOM: no complete Pixel Data element of " +
                                 std::to_string(expected) + " bytes");
}

std::string dictionary_text(const itk::MetaDataDictionary& dict, const std::string& key) {
    std::string value;
    itk::ExposeMetaData<std::string>(dict, key, value);
    return value;
}

std::string trimmed(std::string text) {
    while (!text.empty() && (text.back() == '\0' || text.back() == ' ')) text.pop_back();
    return text;
}

// One series found by GDCM: its grouping identifier (SeriesInstanceUID plus details such as
// orientation and size), the files in slice order, and what its first file says.
struct SeriesEntry {
    std::string id;
    std::vector<std::string> files;
    std::string uid, description;
};

std::vector<SeriesEntry> scan_series(const std::string& folder) {
    auto names = itk::GDCMSeriesFileNames::New();
    names->SetUseSeriesDetails(true);
    names->SetDirectory(folder); // may abort on a damaged file: we are the child
    std::vector<SeriesEntry> entries;
    for (const auto& id : names->GetSeriesUIDs()) {
        SeriesEntry e;
        e.id = id;
        e.files = names->GetFileNames(id);
        if (e.files.empty()) continue;
        auto io = itk::GDCMImageIO::New();
        io->SetFileName(e.files.front());
        io->ReadImageInformation();
        e.uid = trimmed(dictionary_text(io->GetMetaDataDictionary(), "0020|000e"));
        e.description = trimmed(dictionary_text(io->GetMetaDataDictionary(), "0008|103e"));
        if (e.uid.empty()) e.uid = id;
        entries.push_back(std::move(e));
    }
    // Largest first; ties keep GDCM's order.
    std::stable_sort(entries.begin(), entries.end(),
                     [](const auto& a, const auto& b) { return a.files.size() > b.files.size(); });
    return entries;
}

std::string describe_series(const std::vector<SeriesEntry>& entries) {
    std::string text;
    for (const auto& e : entries)
        text += (text.empty() ? "" : ", ") + e.uid + " (" + std::to_string(e.files.size()) +
                " files" + (e.description.empty() ? "" : ", " + e.description) + ")";
    return text;
}

const SeriesEntry& choose_series(const std::vector<SeriesEntry>& entries,
                                 const DicomRequest& request) {
    if (entries.empty())
        throw std::runtime_error(request.folder +
                                 ": no DICOM series found in this folder (a folder is read as "
                                 "a DICOM series)");
    if (!request.uid.empty()) {
        for (const auto& e : entries) // largest first: the biggest part of a split series
            if (e.uid == request.uid || e.id == request.uid) return e;
        throw std::invalid_argument(request.folder + ": no DICOM series " + request.uid +
                                    "; the folder holds " + describe_series(entries));
    }
    if (!request.file.empty()) {
        const std::string wanted = real_path(request.file);
        for (const auto& e : entries)
            for (const auto& f : e.files)
                if (real_path(f) == wanted) return e;
        throw std::runtime_error(request.file + ": not part of a readable DICOM series");
    }
    return entries.front();
}

// Refuses a series whose slice k does not lie k slice spacings from the first: a missing or
// skipped (damaged) file would otherwise stretch the volume silently.
void check_slice_position(const std::string& file, std::size_t k, const itk::Image<float, 3>& first,
                          const itk::Image<float, 3>& slice) {
    const auto& o0 = first.GetOrigin();
    const auto& ok = slice.GetOrigin();
    const double step = first.GetSpacing()[2];
    double deviation = 0.0;
    for (unsigned r = 0; r < 3; ++r) {
        const double expected = o0[r] + double(k) * step * first.GetDirection()(r, 2);
        deviation = std::max(deviation, std::abs(ok[r] - expected));
    }
    if (deviation > 0.1 * step + 1e-3)
        throw std::runtime_error(file + ": slice " + std::to_string(k) + " lies " +
                                 std::to_string(deviation) +
                                 " mm from where a uniform spacing of " + std::to_string(step) +
                                 " mm puts it (missing, damaged or unevenly spaced slices)");
}

// Runs in the child: scan, pick the series, send its header, then every slice.
void dicom_child_work(int fd, const DicomRequest& request) {
    const std::vector<SeriesEntry> entries = scan_series(request.folder);
    if (request.list_only) {
        std::string list;
        for (const auto& e : entries)
            list += e.uid + "\t" + std::to_string(e.files.size()) + "\t" + e.description + "\n";
        send_text(fd, 'L', list);
        return;
    }
    const SeriesEntry& chosen = choose_series(entries, request);
    const std::vector<std::string>& files = chosen.files;

    using Image = itk::Image<float, 3>;
    auto series = itk::ImageSeriesReader<Image>::New();
    auto series_io = itk::GDCMImageIO::New();
    series->SetImageIO(series_io);
    series->SetFileNames(files);
    series->UpdateOutputInformation();
    const Image* image = series->GetOutput();
    const auto size = image->GetLargestPossibleRegion().GetSize();
    const auto type = scalar_type_of(series_io->GetInternalComponentType());
    if (series_io->GetNumberOfComponents() != 1)
        throw std::runtime_error(files.front() + ": has " +
                                 std::to_string(series_io->GetNumberOfComponents()) +
                                 " components per pixel; snert reads scalar volumes");
    if (!type) throw std::runtime_error(files.front() + ": unsupported DICOM pixel type");
    WireHeader wire{};
    for (unsigned a = 0; a < 3; ++a) {
        wire.dims[a] = std::int64_t(size[a]);
        wire.spacing[a] = image->GetSpacing()[a];
        wire.origin[a] = image->GetOrigin()[a];
        for (unsigned r = 0; r < 3; ++r) wire.direction[3 * a + r] = image->GetDirection()(r, a);
    }
    wire.type = std::int32_t(*type);
    wire.files = std::int64_t(files.size());
    std::string header(reinterpret_cast<const char*>(&wire), sizeof wire);
    if (!send_text(fd, 'H', header + chosen.uid)) return;

    const std::uint64_t frames = files.size() == 1 ? size[2] : 1;
    const std::uint64_t slice_bytes =
        std::uint64_t(size[0]) * size[1] * frames * scalar_type_size(*type);
    const std::string syntax = dictionary_text(series_io->GetMetaDataDictionary(), "0002|0010");
    itk::Image<float, 3>::Pointer first;
    for (std::size_t k = 0; k < files.size(); ++k) {
        const std::string& file = files[k];
        check_slice_file(file, slice_bytes, syntax);
        auto reader = itk::ImageFileReader<Image>::New();
        reader->SetImageIO(itk::GDCMImageIO::New());
        reader->SetFileName(file);
        reader->Update();
        const auto got = reader->GetOutput()->GetLargestPossibleRegion().GetSize();
        if (got[0] != size[0] || got[1] != size[1] || got[2] != frames)
            throw std::runtime_error(file + ": slice of " + std::to_string(got[0]) + " x " +
                                     std::to_string(got[1]) + " pixels in a series of " +
                                     std::to_string(size[0]) + " x " + std::to_string(size[1]));
        if (k == 0)
            first = reader->GetOutput();
        else
            check_slice_position(file, k, *first, *reader->GetOutput());
        const std::uint64_t count = std::uint64_t(got[0]) * got[1] * got[2];
        if (!send_message(fd, 'D', reader->GetOutput()->GetBufferPointer(), count * sizeof(float)))
            return; // the parent stopped listening
    }
    send_text(fd, 'K', "");
}

[[noreturn]] void dicom_child(int fd, const DicomRequest& request) {
    // Threads of the parent do not exist here: run ITK single-threaded, on fresh threads only.
    itk::MultiThreaderBase::SetGlobalDefaultThreader(
        itk::MultiThreaderBase::ThreaderEnum::Platform);
    itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(1);
    int code = 0;
    try {
        dicom_child_work(fd, request);
    } catch (const itk::ExceptionObject& e) {
        send_text(fd, 'E', request.folder + ": " + one_line(e.GetDescription()));
        code = 1;
    } catch (const std::invalid_argument& e) {
        send_text(fd, 'I', e.what());
        code = 1;
    } catch (const std::exception& e) {
        send_text(fd, 'E', e.what());
        code = 1;
    }
    ::close(fd);
    ::_exit(code); // no atexit handlers, no flushing of the parent's stdio buffers
}

// The parent's end: the child's pid, the pipe, and the file that holds the child's stderr.
class DicomChild {
  public:
    static constexpr int kSilenceLimitMs = 120000;

    explicit DicomChild(const DicomRequest& request) : folder_(request.folder) {
        int fds[2];
        if (::pipe(fds) != 0) throw std::runtime_error(folder_ + ": cannot create a pipe");
        errors_ = std::tmpfile();
        std::fflush(nullptr);
        pid_ = ::fork();
        if (pid_ < 0) {
            ::close(fds[0]);
            ::close(fds[1]);
            if (errors_) std::fclose(errors_);
            throw std::runtime_error(folder_ + ": cannot start the DICOM reader process");
        }
        if (pid_ == 0) {
            ::close(fds[0]);
            if (errors_) ::dup2(::fileno(errors_), STDERR_FILENO);
            std::signal(SIGPIPE, SIG_DFL);
            dicom_child(fds[1], request);
        }
        ::close(fds[1]);
        fd_ = fds[0];
    }
    ~DicomChild() {
        if (fd_ >= 0) ::close(fd_);
        if (pid_ > 0) {
            ::kill(pid_, SIGKILL);
            int status = 0;
            while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
            }
        }
        if (errors_) std::fclose(errors_);
    }
    DicomChild(const DicomChild&) = delete;
    DicomChild& operator=(const DicomChild&) = delete;

    // Reads exactly `size` bytes; false at end of stream. A child that sends nothing for
    // kSilenceLimitMs is taken for hung (a loop in a damaged file), killed and reported.
    bool read(void* into, std::size_t size) {
        auto* p = static_cast<char*>(into);
        while (size > 0) {
            pollfd ready{fd_, POLLIN, 0};
            const int polled = ::poll(&ready, 1, kSilenceLimitMs);
            if (polled < 0 && errno == EINTR) continue;
            if (polled == 0) {
                ::kill(pid_, SIGKILL);
                throw std::runtime_error(folder_ +
                                         ": the DICOM reader stopped responding (no data for " +
                                         std::to_string(kSilenceLimitMs / 1000) + " s)");
            }
            const ssize_t n = ::read(fd_, p, size);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) return false;
            p += n;
            size -= std::size_t(n);
        }
        return true;
    }

    struct Message {
        char tag = 0;
        std::uint64_t size = 0;
    };
    // The next message's tag and size; a child that died is reported as an error here.
    Message next() {
        Message m;
        if (!read(&m.tag, 1) || !read(&m.size, sizeof m.size)) fail();
        return m;
    }
    std::string text(std::uint64_t size) {
        if (size > (1u << 24)) fail();
        std::string s(std::size_t(size), '\0');
        if (!read(s.data(), s.size())) fail();
        return s;
    }
    // Waits for a clean exit after 'K'.
    void finish() {
        ::close(fd_);
        fd_ = -1;
        int status = 0;
        while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
        }
        pid_ = -1;
    }

    // Throws, saying how the child ended (the pipe closed early).
    [[noreturn]] void fail() {
        ::close(fd_);
        fd_ = -1;
        int status = 0;
        while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
        }
        pid_ = -1;
        std::string message = folder_ + ": the DICOM reader ";
        if (WIFSIGNALED(status))
            message += "crashed (signal " + std::to_string(WTERMSIG(status)) + ", " +
                       strsignal(WTERMSIG(status)) + ") on a damaged file";
        else
            message +=
                "stopped unexpectedly (exit code " + std::to_string(WEXITSTATUS(status)) + ")";
        const std::string last = last_error_line();
        if (!last.empty()) message += ": " + last;
        throw std::runtime_error(message);
    }

  private:
    std::string last_error_line() {
        if (!errors_) return "";
        std::fflush(errors_);
        std::rewind(errors_);
        std::string all;
        char chunk[4096];
        std::size_t n;
        while ((n = std::fread(chunk, 1, sizeof chunk, errors_)) > 0) all.append(chunk, n);
        std::string last;
        std::size_t pos = 0;
        while (pos < all.size()) {
            std::size_t end = all.find('\n', pos);
            if (end == std::string::npos) end = all.size();
            const std::string line = one_line(all.substr(pos, end - pos));
            if (!line.empty()) last = line;
            pos = end + 1;
        }
        return last.size() > 300 ? last.substr(0, 297) + "..." : last;
    }

    std::string folder_;
    pid_t pid_ = -1;
    int fd_ = -1;
    std::FILE* errors_ = nullptr;
};

[[noreturn]] void child_error(char tag, const std::string& message) {
    if (tag == 'I') throw std::invalid_argument(message);
    throw std::runtime_error(message);
}

LoadedVolume open_dicom(const DicomRequest& request, const std::string& path,
                        const LoadOptions& options) {
    DicomChild child(request);
    auto m = child.next();
    if (m.tag == 'E' || m.tag == 'I') child_error(m.tag, child.text(m.size));
    if (m.tag != 'H' || m.size < sizeof(WireHeader))
        throw std::runtime_error(path + ": unexpected reply from the DICOM reader");
    const std::string header = child.text(m.size);
    WireHeader wire;
    std::memcpy(&wire, header.data(), sizeof wire);
    const std::string uid = header.substr(sizeof wire);
    for (auto d : wire.dims)
        if (d < 1) throw std::runtime_error(path + ": DICOM series with an empty dimension");
    const glm::ivec3 dims = checked_dims(path, std::uint64_t(wire.dims[0]),
                                         std::uint64_t(wire.dims[1]), std::uint64_t(wire.dims[2]));
    detail::check_memory(path, dims, 0, options.memory_limit_bytes);
    if (wire.type < 0 || wire.type > int(ScalarType::Float64))
        throw std::runtime_error(path + ": unexpected reply from the DICOM reader");
    Geometry g;
    for (int a = 0; a < 3; ++a) {
        g.spacing[a] = float(wire.spacing[a]);
        g.origin[a] = float(wire.origin[a]);
        for (int r = 0; r < 3; ++r) g.direction[a][r] = float(wire.direction[3 * a + r]);
    }
    LoadedVolume loaded;
    loaded.volume = allocate_volume(path, dims, g);
    Volume& v = loaded.volume;
    const std::uint64_t total_bytes = v.voxel_count() * sizeof(float);
    std::uint64_t filled = 0;
    for (;;) {
        m = child.next();
        if (m.tag == 'E' || m.tag == 'I') child_error(m.tag, child.text(m.size));
        if (m.tag == 'K') break;
        if (m.tag != 'D' || m.size > total_bytes - filled || m.size % sizeof(float) != 0)
            throw std::runtime_error(path + ": unexpected reply from the DICOM reader");
        if (!child.read(reinterpret_cast<char*>(v.samples.data()) + filled, std::size_t(m.size)))
            child.fail();
        filled += m.size;
        options.progress.update(0.95f * float(filled) / float(total_bytes));
    }
    if (filled != total_bytes)
        throw std::runtime_error(path + ": the DICOM series delivered " +
                                 std::to_string(filled / sizeof(float)) + " of " +
                                 std::to_string(v.voxel_count()) + " samples");
    child.finish();
    const ScalarType type = ScalarType(wire.type);
    loaded.info = make_info(path, "DICOM", type, v);
    loaded.info.files = std::size_t(wire.files);
    loaded.info.series_uid = uid;
    // Rescaled DICOM arrives as floats; the policy is cheap, so apply it to every series.
    finish(loaded, ScalarType::Float32, options);
    loaded.info.scalar_type = scalar_type_name(type);
    return loaded;
}

std::string folder_of(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    if (slash == std::string::npos) return ".";
    return slash == 0 ? "/" : path.substr(0, slash);
}

bool is_dicom_file(const std::string& path) {
    const std::string ext = detail::volume_extension(path);
    if (ext == ".dcm" || ext == ".ima" || ext == ".dicom") return true;
    const auto prefix = detail::read_file_prefix(path, 132);
    return prefix.size() == 132 && std::memcmp(prefix.data() + 128, "DICM", 4) == 0;
}

} // namespace

// ---- Public entry points ----------------------------------------------------------------------

std::vector<DicomSeries> list_dicom_series(const std::string& folder) {
    struct stat st {};
    if (::stat(folder.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
        throw std::invalid_argument(folder + ": not a folder");
    DicomRequest request;
    request.folder = folder;
    request.list_only = true;
    DicomChild child(request);
    auto m = child.next();
    if (m.tag == 'E' || m.tag == 'I') child_error(m.tag, child.text(m.size));
    if (m.tag != 'L') throw std::runtime_error(folder + ": unexpected reply from the DICOM reader");
    const std::string list = child.text(m.size);
    child.finish();
    std::vector<DicomSeries> series;
    std::size_t pos = 0;
    while (pos < list.size()) {
        const std::size_t end = list.find('\n', pos);
        const std::string line = list.substr(pos, end - pos);
        pos = end == std::string::npos ? list.size() : end + 1;
        const std::size_t tab = line.find('\t'), tab2 = line.find('\t', tab + 1);
        if (tab == std::string::npos || tab2 == std::string::npos) continue;
        series.push_back({line.substr(0, tab),
                          std::size_t(std::stoull(line.substr(tab + 1, tab2 - tab - 1))),
                          line.substr(tab2 + 1)});
    }
    return series;
}

LoadedVolume open_volume(const std::string& path, const LoadOptions& options) {
    struct stat st {};
    if (path.empty() || ::stat(path.c_str(), &st) != 0)
        throw std::runtime_error(path + ": no such file or folder");
    if (S_ISDIR(st.st_mode)) {
        DicomRequest request;
        request.folder = path;
        request.uid = options.dicom_series_uid;
        return open_dicom(request, path, options);
    }
    if (!S_ISREG(st.st_mode)) throw std::runtime_error(path + ": not a regular file");
    if (st.st_size == 0) throw std::runtime_error(path + ": empty file");
    if (::access(path.c_str(), R_OK) != 0) throw std::runtime_error(path + ": cannot be read");
    if (!options.dicom_series_uid.empty() && !is_dicom_file(path))
        throw std::invalid_argument(path + ": a DICOM series UID was given, but this is not a "
                                           "DICOM folder or file");
    if (is_dicom_file(path)) {
        DicomRequest request;
        request.folder = folder_of(path);
        request.uid = options.dicom_series_uid;
        request.file = path;
        return open_dicom(request, path, options);
    }
    const std::string ext = detail::volume_extension(path);
    if (ext.size() > 3 && ext.compare(ext.size() - 3, 3, ".gz") == 0) {
        const auto magic = detail::read_file_prefix(path, 2);
        if (!detail::has_gzip_magic(magic.data(), magic.size()))
            throw std::runtime_error(path + ": named .gz but is not gzip data");
    }
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

Volume load_volume(const std::string& path, const LoadOptions& options) {
    return open_volume(path, options).volume;
}

} // namespace snert

#if defined(__SANITIZE_ADDRESS__)
// ITK's NRRD reader does not free its error text and state when it throws (NrrdImageIO::Read,
// "would be nice to free(err)"); LeakSanitizer would turn every refused NRRD into a failure.
// Only leaks whose stack passes through ITK's NrrdIO library are suppressed.
extern "C" const char* __lsan_default_suppressions() {
    return "leak:libITKNrrdIO\n";
}
#endif
