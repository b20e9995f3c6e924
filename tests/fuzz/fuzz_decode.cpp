// Fuzz target: a whole (or cut, or damaged) .mlz file through decode() and inspect().
#include <cstddef>
#include <cstdint>
#include <span>

#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace meshlift;
  const std::span<const std::uint8_t> bytes(data, size);
  fuzz::check_result(decode(bytes, fuzz::fuzz_options()));
  // A level cap takes the same path with synthesis stopped early.
  DecodeOptions coarse = fuzz::fuzz_options();
  coarse.max_level = 1;
  fuzz::check_result(decode(bytes, coarse));
  const StreamInfo info = inspect(bytes);
  if (info.status != Status::ok && info.message.empty()) fuzz::violated("inspect error without a message");
  return 0;
}
