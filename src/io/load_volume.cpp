// open_volume: which reader a path goes to, after the checks every path gets (it exists, is a
// folder or a readable non-empty file, a .gz is gzip). Folders and DICOM files go to the DICOM
// reader (dicom_series.cpp), everything else to ITK's ImageIO (itk_image_io.cpp).
#include "load_volume.h"

#include <stdexcept>

#include <sys/stat.h>
#include <unistd.h>

#include "dicom_series.h"
#include "file_bytes.h"
#include "gzip.h"
#include "itk_image_io.h"

namespace snert {

LoadedVolume open_volume(const std::string& path, const LoadOptions& options) {
    struct stat st {};
    if (path.empty() || ::stat(path.c_str(), &st) != 0)
        throw std::runtime_error(path + ": no such file or folder");
    if (S_ISDIR(st.st_mode)) return detail::open_dicom_folder(path, options);
    if (!S_ISREG(st.st_mode)) throw std::runtime_error(path + ": not a regular file");
    if (st.st_size == 0) throw std::runtime_error(path + ": empty file");
    if (::access(path.c_str(), R_OK) != 0) throw std::runtime_error(path + ": cannot be read");
    if (!options.dicom_series_uid.empty() && !detail::is_dicom_file(path))
        throw std::invalid_argument(path + ": a DICOM series UID was given, but this is not a "
                                           "DICOM folder or file");
    if (detail::is_dicom_file(path)) return detail::open_dicom_file(path, options);
    const std::string ext = detail::volume_extension(path);
    if (ext.size() > 3 && ext.compare(ext.size() - 3, 3, ".gz") == 0) {
        const auto magic = detail::read_file_prefix(path, 2);
        if (!detail::has_gzip_magic(magic.data(), magic.size()))
            throw std::runtime_error(path + ": named .gz but is not gzip data");
    }
    return detail::open_with_image_io(path, options);
}

Volume load_volume(const std::string& path, const LoadOptions& options) {
    return open_volume(path, options).volume;
}

} // namespace snert
