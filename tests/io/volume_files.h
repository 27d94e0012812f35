// Bytes of volume files for the snert_io tests: read them, gzip them, take values from them,
// write NRRD headers; and the checks every loading test makes (a clear one-line error, sums
// and vectors of a loaded volume). Temporary folders, exception messages and the real volumes'
// folder come from tests/support.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/volume.h"

namespace snert::io_test {

using Bytes = std::vector<std::uint8_t>;

// The whole file ({} when it cannot be opened).
Bytes read_bytes(const std::string& path);
Bytes text_bytes(const std::string& text);
Bytes concat(Bytes a, const Bytes& b);
// zlib with gzip framing (window bits 15 + 16), and back (zlib or gzip, detected).
Bytes gzip(const Bytes& in);
Bytes gunzip(const Bytes& in);

// A value stored at `offset` in the machine's byte order (little-endian on every test machine).
template <class T> T load_le(const Bytes& b, std::size_t offset) {
    T v;
    std::memcpy(&v, b.data() + offset, sizeof v);
    return v;
}
template <class T> Bytes as_bytes(const std::vector<T>& values) {
    Bytes b(values.size() * sizeof(T));
    std::memcpy(b.data(), values.data(), b.size());
    return b;
}

// A NRRD header of a 3-D volume, little-endian, ending with its blank line: the data follows.
std::string nrrd_header(const std::string& type, const std::string& sizes,
                        const std::string& encoding, const std::string& extra = "");

// A clear error: one line, starting with the file it is about, saying `what`.
void expect_clear_error(const std::string& message, const std::string& file,
                        const std::string& what);

double sum_of(const Volume& v);
void expect_vec3_near(glm::vec3 actual, glm::vec3 expected, float tolerance);

} // namespace snert::io_test
