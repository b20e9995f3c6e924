// Two tasks at once, for the encoder's independent stages (internal to codec/).
#pragma once

#include <exception>
#include <thread>

namespace meshlift {

/// Runs first() on a thread of its own while second() runs on the caller's, and returns once both
/// have ended; with `concurrent` false, first() then second() on the caller's thread. The tasks
/// must not write what the other reads. Both always run; an exception from either is rethrown
/// once both have ended (second()'s if both threw), never std::terminate from the thread.
template <class First, class Second>
void run_both(bool concurrent, First&& first, Second&& second) {
  std::exception_ptr failure;
  auto run_first = [&] {
    try {
      first();
    } catch (...) {
      failure = std::current_exception();
    }
  };
  if (!concurrent) {
    run_first();
    second();
    if (failure) std::rethrow_exception(failure);
    return;
  }
  std::thread thread(run_first);
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
