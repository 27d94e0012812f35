// Files as bytes: stat, prefixes, extensions, folders.
#include "file_bytes.h"

#include <algorithm>
#include <fstream>
#include <stdexcept>

#include <sys/stat.h>

#include "header_text.h"

namespace snert::detail {

std::uint64_t file_size(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) throw std::runtime_error(path + ": no such file");
    if (!S_ISREG(st.st_mode)) throw std::runtime_error(path + ": not a regular file");
    return std::uint64_t(st.st_size);
}

std::vector<std::uint8_t> read_file_prefix(const std::string& path, std::size_t max_bytes) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(path + ": cannot open");
    std::vector<std::uint8_t> bytes;
    std::vector<char> chunk(std::min<std::size_t>(max_bytes, 1 << 16));
    while (bytes.size() < max_bytes && in) {
        const std::size_t want = std::min(chunk.size(), max_bytes - bytes.size());
        in.read(chunk.data(), std::streamsize(want));
        const auto got = std::size_t(in.gcount());
        bytes.insert(bytes.end(), chunk.begin(), chunk.begin() + std::ptrdiff_t(got));
        if (got < want) break;
    }
    return bytes;
}

std::string volume_extension(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    const std::string file = lower(slash == std::string::npos ? path : path.substr(slash + 1));
    std::size_t dot = file.find_last_of('.');
    if (dot == std::string::npos || dot == 0) return "";
    if (file.compare(dot, std::string::npos, ".gz") == 0 && dot > 0) {
        const std::size_t inner = file.find_last_of('.', dot - 1);
        if (inner != std::string::npos && inner > 0) return file.substr(inner);
    }
    return file.substr(dot);
}

std::string folder_of(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

} // namespace snert::detail
