// gzip / zlib streams, inflated only to count their bytes.
#include "gzip.h"

#include <algorithm>
#include <fstream>
#include <stdexcept>
#include <vector>

#include <zlib.h>

namespace snert::detail {

bool has_gzip_magic(const std::uint8_t* bytes, std::size_t size) {
    return size >= 2 && bytes[0] == 0x1f && bytes[1] == 0x8b;
}

InflateCounter::InflateCounter(std::string name, std::uint64_t enough)
    : name_(std::move(name)), enough_(enough), stream_(new z_stream{}) {
    auto* z = static_cast<z_stream*>(stream_);
    if (inflateInit2(z, 15 + 32) != Z_OK) { // 15 + 32: zlib or gzip, detected from the header
        delete z;
        throw std::runtime_error(name_ + ": cannot start zlib");
    }
}

InflateCounter::~InflateCounter() {
    auto* z = static_cast<z_stream*>(stream_);
    inflateEnd(z);
    delete z;
}

bool InflateCounter::feed(const std::uint8_t* bytes, std::size_t size) {
    auto* z = static_cast<z_stream*>(stream_);
    unsigned char scratch[1 << 14];
    while (!done_ && size > 0) {
        const std::size_t chunk = std::min<std::size_t>(size, 1u << 30);
        z->next_in = const_cast<unsigned char*>(bytes);
        z->avail_in = unsigned(chunk);
        while (!done_ && z->avail_in > 0) {
            z->next_out = scratch;
            z->avail_out = sizeof scratch;
            const int status = inflate(z, Z_NO_FLUSH);
            produced_ += sizeof scratch - z->avail_out;
            if (status == Z_STREAM_END || produced_ >= enough_)
                done_ = true;
            else if (status == Z_BUF_ERROR)
                break; // needs more input
            else if (status != Z_OK)
                throw std::runtime_error(name_ + ": corrupt compressed data (" +
                                         (z->msg ? z->msg : "zlib error") + ")");
        }
        const std::size_t used = chunk - z->avail_in;
        bytes += used;
        size -= used;
        if (used == 0) break;
    }
    return !done_;
}

std::uint64_t inflated_file_bytes(const std::string& path, std::uint64_t offset,
                                  std::uint64_t enough) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(path + ": cannot open");
    in.seekg(std::streamoff(offset));
    InflateCounter counter(path, enough);
    std::vector<std::uint8_t> chunk(1 << 16);
    while (in) {
        in.read(reinterpret_cast<char*>(chunk.data()), std::streamsize(chunk.size()));
        const auto got = std::size_t(in.gcount());
        if (got == 0 || !counter.feed(chunk.data(), got)) break;
    }
    return counter.produced();
}

} // namespace snert::detail
