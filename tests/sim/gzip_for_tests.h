// Test helper: gzip-wrapped deflate of a byte string with zlib, for NRRD test
// data.
#ifndef BURRLAB_TESTS_SIM_GZIP_FOR_TESTS_H_
#define BURRLAB_TESTS_SIM_GZIP_FOR_TESTS_H_

#include <zlib.h>

#include <string>

namespace burrlab::sim::testing {

// gzip of `data` at the given level (0 = stored blocks); empty on a zlib
// failure.
inline std::string Gzip(const std::string& data, int level = 9) {
  z_stream stream{};
  if (deflateInit2(&stream, level, Z_DEFLATED, 16 + MAX_WBITS, 8,
                   Z_DEFAULT_STRATEGY) != Z_OK) {
    return {};
  }
  std::string out(deflateBound(&stream, static_cast<uLong>(data.size())) + 64,
                  '\0');
  stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  stream.avail_in = static_cast<uInt>(data.size());
  stream.next_out = reinterpret_cast<Bytef*>(out.data());
  stream.avail_out = static_cast<uInt>(out.size());
  const bool done = deflate(&stream, Z_FINISH) == Z_STREAM_END;
  out.resize(done ? stream.total_out : 0);
  deflateEnd(&stream);
  return out;
}

}  // namespace burrlab::sim::testing

#endif  // BURRLAB_TESTS_SIM_GZIP_FOR_TESTS_H_
