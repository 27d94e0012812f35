// Bytes of volume files for the snert_io tests.
#include "volume_files.h"

#include <fstream>
#include <iterator>
#include <numeric>

#include <gtest/gtest.h>
#include <zlib.h>

namespace snert::io_test {

Bytes read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return Bytes(std::istreambuf_iterator<char>(in), {});
}

Bytes text_bytes(const std::string& text) {
    return Bytes(text.begin(), text.end());
}

Bytes concat(Bytes a, const Bytes& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

Bytes gzip(const Bytes& in) {
    z_stream z{};
    deflateInit2(&z, 6, Z_DEFLATED, 31, 8, Z_DEFAULT_STRATEGY);
    Bytes out(deflateBound(&z, uLong(in.size())) + 64);
    z.next_in = const_cast<Bytef*>(in.data());
    z.avail_in = uInt(in.size());
    z.next_out = out.data();
    z.avail_out = uInt(out.size());
    deflate(&z, Z_FINISH);
    out.resize(z.total_out);
    deflateEnd(&z);
    return out;
}

Bytes gunzip(const Bytes& in) {
    z_stream z{};
    inflateInit2(&z, 15 + 32);
    Bytes out;
    unsigned char chunk[1 << 16];
    z.next_in = const_cast<Bytef*>(in.data());
    z.avail_in = uInt(in.size());
    int status = Z_OK;
    while (status == Z_OK) {
        z.next_out = chunk;
        z.avail_out = sizeof chunk;
        status = inflate(&z, Z_NO_FLUSH);
        out.insert(out.end(), chunk, chunk + (sizeof chunk - z.avail_out));
    }
    inflateEnd(&z);
    return out;
}

void expect_clear_error(const std::string& message, const std::string& file,
                        const std::string& what) {
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_EQ(message.rfind(file, 0), 0u)
        << "message should start with " << file << ": " << message;
    EXPECT_NE(message.find(what), std::string::npos)
        << "message should say '" << what << "': " << message;
}

double sum_of(const Volume& v) {
    return std::accumulate(v.samples.begin(), v.samples.end(), 0.0);
}

void expect_vec3_near(glm::vec3 actual, glm::vec3 expected, float tolerance) {
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(actual[a], expected[a], tolerance) << "axis " << a;
}

std::string nrrd_header(const std::string& type, const std::string& sizes,
                        const std::string& encoding, const std::string& extra) {
    return "NRRD0004\ntype: " + type + "\ndimension: 3\nsizes: " + sizes +
           "\nendian: little\nencoding: " + encoding + "\n" + extra + "\n";
}

} // namespace snert::io_test
