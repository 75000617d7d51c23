// Loops over rows or pixels on several threads, with std::thread rather than OpenMP: the module that
// ships in the Blender add-on may depend on nothing but the C runtime, and GCC's OpenMP runtime
// cannot be linked statically into a shared module (libgomp.a uses initial-exec TLS). Internal.
#pragma once

#include <functional>

namespace shadecut::detail {

/// The threads a loop uses when its caller does not say: the innermost ThreadCountScope of this
/// thread, else every core (std::thread::hardware_concurrency, at least 1).
int default_thread_count();

/// Sets default_thread_count() of the calling thread for its lifetime (threads <= 0: leaves it).
class ThreadCountScope {
 public:
  explicit ThreadCountScope(int threads);
  ~ThreadCountScope();
  ThreadCountScope(const ThreadCountScope&) = delete;
  ThreadCountScope& operator=(const ThreadCountScope&) = delete;

 private:
  int saved_;
};

/// Calls body(begin, end) on consecutive ranges of at most `chunk` indices covering [0, count), on
/// up to `threads` threads (the caller is one of them, the others from a pool kept between calls, at
/// most one fewer than the cores;
/// threads <= 0 means default_thread_count()). Ranges are handed out in increasing order to whichever
/// thread is free, so that a thread that lost its core delays the loop by one chunk only. With one
/// thread or a single chunk, inside another loop's body, or while another thread's loop holds the
/// pool, it calls body(0, count) on the calling thread.
/// The first exception a body throws is rethrown once every thread has stopped taking ranges.
void parallel_ranges(int count, int chunk, int threads, const std::function<void(int, int)>& body);

/// parallel_ranges calling body(i) for each index.
template <class Body>
void parallel_for(int count, int chunk, int threads, Body&& body) {
  parallel_ranges(count, chunk, threads, [&body](int begin, int end) {
    for (int i = begin; i < end; ++i) body(i);
  });
}

}  // namespace shadecut::detail
