// Two tasks at once, for the encoder's independent stages (internal to codec/).
#pragma once

#include <exception>
#include <thread>

namespace meshlift {

/// Runs first() on a thread of its own while second() runs on the caller's, and returns once both
/// have ended; with `concurrent` false, first() then second() on the caller's thread. The tasks
/// must not write what the other reads. An exception from either is rethrown once both have
/// ended (second()'s if both threw), never std::terminate from the thread.
template <class First, class Second>
void run_both(bool concurrent, First&& first, Second&& second) {
  if (!concurrent) {
    first();
    second();
    return;
  }
  std::exception_ptr failure;
  std::thread thread([&] {
    try {
      first();
    } catch (...) {
      failure = std::current_exception();
    }
  });
  try {
    second();
  } catch (...) {
    thread.join();
    throw;
  }
  thread.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace meshlift
