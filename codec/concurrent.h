// Two tasks at once, for the encoder's and the decoder's independent stages (internal to codec/).
#pragma once

#include <cstdint>
#include <exception>
#include <new>
#include <system_error>
#include <thread>

namespace meshlift {

/// Runs first() on a thread of its own while second() runs on the caller's, and returns true once
/// both have ended; returns false, having run neither, where no thread can be started (a process
/// limit). An exception from either is rethrown once both have ended (second()'s if both threw),
/// never std::terminate from the thread. For tasks that may wait for each other (a producer and
/// its consumer), which must not run one after the other.
template <class First, class Second>
bool try_run_both(First&& first, Second&& second) {
  std::exception_ptr failure;
  std::thread thread;
  try {
    thread = std::thread([&] {
      try {
        first();
      } catch (...) {
        failure = std::current_exception();
      }
    });
  } catch (const std::system_error&) {
    return false;
  } catch (const std::bad_alloc&) {  // the thread's own state
    return false;
  }
  try {
    second();
  } catch (...) {
    thread.join();
    throw;
  }
  thread.join();
  if (failure) std::rethrow_exception(failure);
  return true;
}

/// first() and second(), side by side if `concurrent` (try_run_both), else, or where no thread
/// can be started, one after the other on the caller's thread. The tasks must not write what the
/// other reads. Both always run; an exception from either is rethrown once both have ended
/// (second()'s if both threw).
template <class First, class Second>
void run_both(bool concurrent, First&& first, Second&& second) {
  if (concurrent && try_run_both(first, second)) return;
  std::exception_ptr failure;
  try {
    first();
  } catch (...) {
    failure = std::current_exception();
  }
  second();
  if (failure) std::rethrow_exception(failure);
}

/// part(e0, e1, f0, f1) over the coarse edges [0, E) and faces [0, F) of a level: with
/// `concurrent`, the second halves (E / 2 on, F / 2 on) on a thread of their own beside the first
/// halves (run_both), each half in order; else all of them at once on the caller's thread.
template <class Part>
void in_halves(bool concurrent, std::uint32_t E, std::uint32_t F, Part&& part) {
  if (!concurrent) return part(0u, E, 0u, F);
  run_both(true, [&] { part(E / 2, E, F / 2, F); }, [&] { part(0u, E / 2, 0u, F / 2); });
}

}  // namespace meshlift
