// gzip / zlib streams of untrusted files: is it gzip, and how much does it inflate to?
//
// A compressed file's size says nothing about what it holds, so the size checks of compressed
// NRRD and MetaImage data inflate the stream and count, without keeping the bytes, and stop
// once the header's promise is met.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace snert::detail {

// The two gzip magic bytes 1f 8b at the start of `bytes`.
bool has_gzip_magic(const std::uint8_t* bytes, std::size_t size);

// Counts the bytes a zlib or gzip stream inflates to, stopping once `enough` are produced.
// Throws std::runtime_error "<name>: corrupt compressed data" for a stream that is not zlib /
// gzip or is damaged; a stream cut short returns what it produced.
class InflateCounter {
  public:
    InflateCounter(std::string name, std::uint64_t enough);
    ~InflateCounter();
    InflateCounter(const InflateCounter&) = delete;
    InflateCounter& operator=(const InflateCounter&) = delete;
    // Feeds the next compressed bytes; returns false once done (enough bytes or end of stream).
    bool feed(const std::uint8_t* bytes, std::size_t size);
    std::uint64_t produced() const { return produced_; }

  private:
    std::string name_;
    std::uint64_t enough_, produced_ = 0;
    bool done_ = false;
    void* stream_; // a z_stream, kept out of this header
};
// Inflated size of the compressed stream from `offset` of a file to its end (at most
// `enough`). Throws std::runtime_error naming the file when it cannot be opened.
std::uint64_t inflated_file_bytes(const std::string& path, std::uint64_t offset,
                                  std::uint64_t enough);

} // namespace snert::detail
