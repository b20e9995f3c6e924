// Fuzz target: the streaming Decoder fed the input in chunks whose sizes come from the input
// itself, asking for the mesh between pushes; each answer must equal decode() of the same prefix.
//
// Input layout: byte 0 seeds the chunk sizes (xorshift32 over seed | 1), the rest is the stream.
#include <cstddef>
#include <algorithm>
#include <cstdint>
#include <span>

#include "../decode_results.h"
#include "fuzz_check.h"


extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace meshlift;
  if (size < 1) return 0;
  std::uint32_t state = 0x9E3779B9u ^ (std::uint32_t{data[0]} * 0x01000193u) ^ static_cast<std::uint32_t>(size);
  const std::span<const std::uint8_t> stream(data + 1, size - 1);
  Decoder decoder(fuzz::fuzz_options());
  std::size_t at = 0;
  int calls = 0;
  while (at < stream.size()) {
    state ^= state << 13;
    state ^= state >> 17;
    state ^= state << 5;
    // Mostly small chunks (1..64 bytes), sometimes up to 1 KiB; mesh() is compared with decode()
    // on at most 24 prefixes so one input stays well under the time limit.
    const std::size_t chunk = 1 + ((state & 0x300) == 0x300 ? state % 1024 : state % 64);
    const std::size_t n = std::min(chunk, stream.size() - at);
    decoder.push(stream.subspan(at, n));
    at += n;
    if (decoder.bytes_received() != at) fuzz::violated("bytes_received");
    if (calls < 24 || at == stream.size()) {
      ++calls;
      const DecodeResult streamed = decoder.mesh();
      fuzz::check_result(streamed);
      if (!meshlift::test::same_result(streamed, decode(stream.first(at), fuzz::fuzz_options()))) fuzz::violated("streamed != decoded prefix");
    }
  }
  return 0;
}
