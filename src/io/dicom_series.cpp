// DICOM series through GDCM in a child process: the scan and the read in the child, the
// protocol on the pipe, and the parent that turns what arrives (or how the child died) into a
// volume or an error.
//
// This work is based on GDCM's series helper (itk::GDCMSeriesFileNames) for grouping and
// sorting DICOM slices by their position along the slice normal, read through ITK 5.2's
// GDCMImageIO.
#include "dicom_series.h"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include <poll.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <itkGDCMImageIO.h>
#include <itkGDCMSeriesFileNames.h>
#include <itkImage.h>
#include <itkImageFileReader.h>
#include <itkImageSeriesReader.h>
#include <itkMetaDataObject.h>
#include <itkMultiThreaderBase.h>

#include "dicom_pixel_data.h"
#include "file_bytes.h"
#include "itk_support.h"
#include "sizes.h"
#include "volume_result.h"

namespace snert {

namespace {

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
    const auto type = detail::scalar_type_of(series_io->GetInternalComponentType());
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
        send_text(fd, 'E', request.folder + ": " + detail::one_line(e.GetDescription()));
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
            const std::string line = detail::one_line(all.substr(pos, end - pos));
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
    const glm::ivec3 dims =
        detail::checked_dims(path, std::uint64_t(wire.dims[0]), std::uint64_t(wire.dims[1]),
                             std::uint64_t(wire.dims[2]));
    detail::check_memory(path, dims, 0, options.memory_limit_bytes);
    if (wire.type < 0 || wire.type > int(ScalarType::Float64))
        throw std::runtime_error(path + ": unexpected reply from the DICOM reader");
    detail::Geometry g;
    for (int a = 0; a < 3; ++a) {
        g.spacing[a] = float(wire.spacing[a]);
        g.origin[a] = float(wire.origin[a]);
        for (int r = 0; r < 3; ++r) g.direction[a][r] = float(wire.direction[3 * a + r]);
    }
    LoadedVolume loaded;
    loaded.volume = detail::allocate_volume(path, dims, g);
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
    loaded.info = detail::make_info(path, "DICOM", type, v);
    loaded.info.files = std::size_t(wire.files);
    loaded.info.series_uid = uid;
    // Rescaled DICOM arrives as floats; the policy is cheap, so apply it to every series.
    detail::finish_volume(loaded, ScalarType::Float32, options);
    loaded.info.scalar_type = scalar_type_name(type);
    return loaded;
}

// The folder holding `path` ("." for a bare file name).
std::string folder_containing(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    if (slash == std::string::npos) return ".";
    return slash == 0 ? "/" : path.substr(0, slash);
}

} // namespace

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

namespace detail {

bool is_dicom_file(const std::string& path) {
    const std::string ext = detail::volume_extension(path);
    if (ext == ".dcm" || ext == ".ima" || ext == ".dicom") return true;
    const auto prefix = detail::read_file_prefix(path, 132);
    return prefix.size() == 132 && std::memcmp(prefix.data() + 128, "DICM", 4) == 0;
}

LoadedVolume open_dicom_folder(const std::string& folder, const LoadOptions& options) {
    DicomRequest request;
    request.folder = folder;
    request.uid = options.dicom_series_uid;
    return open_dicom(request, folder, options);
}

LoadedVolume open_dicom_file(const std::string& file, const LoadOptions& options) {
    DicomRequest request;
    request.folder = folder_containing(file);
    request.uid = options.dicom_series_uid;
    request.file = file;
    return open_dicom(request, file, options);
}

} // namespace detail
} // namespace snert
