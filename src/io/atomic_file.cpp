// Atomic file writing: temporary file beside the target, checked writes, fsync, rename.
//
// This work is based on the POSIX guarantee that rename(2) within one file system replaces the
// target atomically: a reader sees either the old file or the complete new one. The stream
// writes straight to a file descriptor (not through std::ofstream) so that the reason of a
// failed write (ENOSPC, EIO) is known and can be reported.
#include "atomic_file.h"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <streambuf>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace snert {
namespace {

std::string errno_text(int error) {
    return std::strerror(error);
}

// "dir/name.ext" -> "dir/.name.tmp-PID-N.ext". The extension is kept because some producers
// (image and volume libraries) choose the format from it; the leading dot hides the file from
// plain listings while it is being written.
std::string temporary_path_for(const std::string& path) {
    static std::atomic<unsigned long> counter{0};
    const std::size_t slash = path.find_last_of('/');
    const std::size_t name_begin = slash == std::string::npos ? 0 : slash + 1;
    std::size_t ext_begin = path.find('.', name_begin + 1);
    if (ext_begin == std::string::npos) ext_begin = path.size();
    return path.substr(0, name_begin) + "." + path.substr(name_begin, ext_begin - name_begin) +
           ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) +
           path.substr(ext_begin);
}

// Creates the temporary file exclusively (the name is ours alone); the errno of a failure says
// why the folder cannot take the file (missing, not a folder, not writable).
int create_exclusive(const std::string& path, const std::string& temporary) {
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) throw std::runtime_error(path + ": cannot create file: " + errno_text(errno));
    return fd;
}

// write(2) until everything is written; false (errno set) on failure.
bool write_all(int fd, const char* data, std::size_t size) {
    while (size > 0) {
        const ssize_t written = ::write(fd, data, size);
        if (written < 0) {
            if (errno == EINTR) continue;
            return false;
        }
        data += written;
        size -= static_cast<std::size_t>(written);
    }
    return true;
}

// A buffered output stream buffer over a file descriptor that remembers the first errno.
class DescriptorBuffer : public std::streambuf {
  public:
    explicit DescriptorBuffer(int fd) : fd_(fd), buffer_(1 << 16) {
        // One slot is kept back so overflow() can store its character before flushing.
        setp(buffer_.data(), buffer_.data() + buffer_.size() - 1);
    }
    int error() const { return error_; }

  protected:
    int_type overflow(int_type ch) override {
        if (!traits_type::eq_int_type(ch, traits_type::eof())) {
            *pptr() = traits_type::to_char_type(ch);
            pbump(1);
        }
        return flush_buffer() ? traits_type::not_eof(ch) : traits_type::eof();
    }
    int sync() override { return flush_buffer() ? 0 : -1; }
    std::streamsize xsputn(const char* data, std::streamsize size) override {
        // Large blocks (binary meshes) skip the copy into the buffer.
        if (size < static_cast<std::streamsize>(buffer_.size() / 2))
            return std::streambuf::xsputn(data, size);
        if (!flush_buffer() || !write_checked(data, static_cast<std::size_t>(size))) return 0;
        return size;
    }

  private:
    bool flush_buffer() {
        const std::size_t pending = static_cast<std::size_t>(pptr() - pbase());
        setp(buffer_.data(), buffer_.data() + buffer_.size() - 1);
        return write_checked(buffer_.data(), pending);
    }
    bool write_checked(const char* data, std::size_t size) {
        if (error_ != 0) return false;
        if (!write_all(fd_, data, size)) error_ = errno != 0 ? errno : EIO;
        return error_ == 0;
    }

    int fd_;
    int error_ = 0;
    std::vector<char> buffer_;
};

// Closes the descriptor, then renames; both after fsync so that the renamed file is complete
// on disk even if the machine stops right after. Throws with the reason; the caller removes
// the temporary file.
void commit(const std::string& path, const std::string& temporary, int fd) {
    if (::fsync(fd) != 0 && errno != EINVAL) { // EINVAL: file system without fsync
        const int error = errno;
        ::close(fd);
        throw std::runtime_error(path + ": cannot write file: " + errno_text(error));
    }
    if (::close(fd) != 0)
        throw std::runtime_error(path + ": cannot write file: " + errno_text(errno));
    if (::rename(temporary.c_str(), path.c_str()) != 0)
        throw std::runtime_error(path + ": cannot replace file: " + errno_text(errno));
}

} // namespace

void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write) {
    const std::string temporary = temporary_path_for(path);
    const int fd = create_exclusive(path, temporary);
    bool fd_open = true;
    try {
        DescriptorBuffer buffer(fd);
        std::ostream stream(&buffer);
        stream.exceptions(std::ios::goodbit); // failures are read from the state below
        write(stream);
        stream.flush();
        if (!stream) {
            const int error = buffer.error();
            throw std::runtime_error(
                path + ": cannot write file: " + (error != 0 ? errno_text(error) : "stream error"));
        }
        fd_open = false; // commit() closes it, also when it throws
        commit(path, temporary, fd);
    } catch (...) {
        if (fd_open) ::close(fd);
        ::unlink(temporary.c_str());
        throw;
    }
}

void write_path_atomically(const std::string& path,
                           const std::function<void(const std::string& temporary_path)>& write) {
    const std::string temporary = temporary_path_for(path);
    // Reserving the name first gives a precise error for a missing or read-only folder before
    // the producer runs, and keeps two writers from ever sharing a temporary file.
    ::close(create_exclusive(path, temporary));
    try {
        write(temporary);
        struct stat info {};
        if (::stat(temporary.c_str(), &info) != 0)
            throw std::runtime_error(path + ": the writer left no file");
        if (!S_ISREG(info.st_mode) || info.st_size == 0)
            throw std::runtime_error(path + ": the writer produced an empty file");
        const int fd = ::open(temporary.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0) throw std::runtime_error(path + ": cannot reopen file: " + errno_text(errno));
        commit(path, temporary, fd);
    } catch (...) {
        ::unlink(temporary.c_str());
        throw;
    }
}

void check_writable(const std::string& path) {
    if (path.empty()) throw std::runtime_error("empty output path");
    const std::size_t slash = path.find_last_of('/');
    const std::string folder =
        slash == std::string::npos ? "." : (slash == 0 ? "/" : path.substr(0, slash));
    struct stat info {};
    if (::stat(folder.c_str(), &info) != 0)
        throw std::runtime_error(path + ": the folder " + folder + " does not exist (" +
                                 errno_text(errno) + ")");
    if (!S_ISDIR(info.st_mode)) throw std::runtime_error(path + ": " + folder + " is not a folder");
    if (::access(folder.c_str(), W_OK | X_OK) != 0)
        throw std::runtime_error(path + ": the folder " + folder + " is not writable (" +
                                 errno_text(errno) + ")");
    if (slash + 1 == path.size() || (::stat(path.c_str(), &info) == 0 && S_ISDIR(info.st_mode)))
        throw std::runtime_error(path + ": is a folder, not a file");
}

} // namespace snert
