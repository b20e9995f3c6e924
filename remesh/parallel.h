// Deterministic data parallelism for remesh/'s loops over independent items (not installed).
#pragma once

#include <algorithm>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace meshlift {

/// Runs body(begin, end) over [0, count) in blocks of 4096 on `threads` threads (block b goes to
/// thread b mod threads; 0 threads = hardware concurrency). Bodies write per-index results only,
/// so the outcome never depends on the thread count or the scheduling. An exception thrown by a
/// body stops its thread's blocks; once every thread has ended, the one of the lowest-numbered
/// thread that threw is rethrown to the caller (never std::terminate from a worker).
template <typename Body>
void parallel_blocks(std::size_t count, unsigned threads, const Body& body) {
  constexpr std::size_t kBlock = 4096;
  const std::size_t blocks = (count + kBlock - 1) / kBlock;
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  threads = static_cast<unsigned>(std::min<std::size_t>(threads, std::max<std::size_t>(blocks, 1)));
  std::vector<std::exception_ptr> failure(threads);
  auto worker = [&](unsigned t) {
    try {
      for (std::size_t b = t; b < blocks; b += threads) body(b * kBlock, std::min(count, (b + 1) * kBlock));
    } catch (...) {
      failure[t] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  pool.reserve(threads - 1);
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker, t);
  worker(0);
  for (auto& thread : pool) thread.join();
  for (const std::exception_ptr& e : failure)
    if (e) std::rethrow_exception(e);
}

}  // namespace meshlift
