// Fuzz target: a whole (or cut, or damaged) .mlz file through decode() on one thread and on two
// (the same result) and inspect().
#include <cstddef>
#include <cstdint>
#include <span>

#include "../decode_results.h"
#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace meshlift;
  const std::span<const std::uint8_t> bytes(data, size);
  DecodeOptions one_thread = fuzz::fuzz_options();
  one_thread.threads = 1;
  const DecodeResult result = decode(bytes, one_thread);
  fuzz::check_result(result);
  // Two threads (the output's faces made beside the coefficients, each level's synthesis split)
  // give the same result bit for bit.
  DecodeOptions two_threads = fuzz::fuzz_options();
  two_threads.threads = 2;
  if (!test::same_result(result, decode(bytes, two_threads))) fuzz::violated("two threads decode otherwise than one");
  // A level cap takes the same path with synthesis stopped early.
  DecodeOptions coarse = fuzz::fuzz_options();
  coarse.max_level = 1;
  fuzz::check_result(decode(bytes, coarse));
  const StreamInfo info = inspect(bytes);
  if (info.status != Status::ok && info.message.empty()) fuzz::violated("inspect error without a message");
  return 0;
}
