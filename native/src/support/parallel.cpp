#include "support/parallel.hpp"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <iterator>
#include <limits>
#include <memory>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

#if defined(__unix__) || defined(__APPLE__)
#include <unistd.h>
#endif

namespace shadecut::detail {

namespace {

thread_local int scoped_thread_count = 0;
thread_local bool inside_pool_thread = false;

int core_count() { return std::max(1, int(std::thread::hardware_concurrency())); }

int process_id() {
#if defined(__unix__) || defined(__APPLE__)
  return int(getpid());
#else
  return 0;
#endif
}

// One loop: chunks handed out in order to whichever thread asks next.
class Loop {
 public:
  Loop(int count, int chunk, const std::function<void(int, int)>& body)
      : count_(count), chunk_(chunk), chunks_((count - 1) / chunk + 1), body_(body) {}

  void take_chunks() {
    for (int k = next_.fetch_add(1); k < chunks_ && !failed_.load(); k = next_.fetch_add(1)) {
      try {
        body_(k * chunk_, std::min(count_, (k + 1) * chunk_));
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex_);
        if (!error_) error_ = std::current_exception();
        failed_ = true;
      }
    }
  }
  int chunks() const { return chunks_; }
  void rethrow() const {
    if (error_) std::rethrow_exception(error_);
  }

 private:
  const int count_, chunk_, chunks_;
  const std::function<void(int, int)>& body_;
  std::atomic<int> next_{0};
  std::atomic<bool> failed_{false};
  std::exception_ptr error_;
  std::mutex error_mutex_;
};

// Threads started once and kept asleep between loops: starting threads for every loop cost the
// Poisson solve, which runs hundreds of short loops, up to a third of its time at 512 x 512. Only
// as many as a loop over every core uses stay: a call asking for 256 threads would otherwise leave 256
// asleep for the rest of the process.
class Pool {
 public:
  // Runs the loop on the caller and `helpers` pool threads; false (and nothing run) when another
  // caller is using the pool.
  bool run(Loop& loop, int helpers) {
    std::unique_lock<std::mutex> in_use(in_use_, std::try_to_lock);
    if (!in_use) return false;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      kept_ = std::numeric_limits<int>::max();
      while (int(workers_.size()) < helpers) {
        try {
          workers_.emplace_back([this, index = int(workers_.size())] { work(index); });
        } catch (const std::system_error&) {
          break;  // fewer threads still finish the loop
        }
      }
      helpers = std::min(helpers, int(workers_.size()));
      loop_ = &loop;
      wanted_ = helpers;
      finished_ = 0;
      ++generation_;
    }
    wake_.notify_all();
    loop.take_chunks();
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [&] { return finished_ == wanted_; });
    loop_ = nullptr;
    retire_beyond(core_count() - 1, lock);
    return true;
  }

 private:
  // Ends and joins the workers from index `kept` on; `lock` holds mutex_ and holds it again after.
  void retire_beyond(int kept, std::unique_lock<std::mutex>& lock) {
    if (int(workers_.size()) <= kept) return;
    std::vector<std::thread> retired(std::make_move_iterator(workers_.begin() + kept),
                                     std::make_move_iterator(workers_.end()));
    workers_.resize(std::size_t(kept));
    kept_ = kept;
    wanted_ = 0;  // the workers that stay go back to sleep
    ++generation_;
    lock.unlock();
    wake_.notify_all();
    for (std::thread& worker : retired) worker.join();
    lock.lock();
  }

  void work(int index) {
    inside_pool_thread = true;
    std::uint64_t seen = 0;
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      wake_.wait(lock, [&] { return generation_ != seen; });
      seen = generation_;
      if (index >= kept_) return;
      if (index >= wanted_) continue;
      Loop* loop = loop_;
      lock.unlock();
      loop->take_chunks();
      lock.lock();
      if (++finished_ == wanted_) done_.notify_one();
    }
  }

  std::mutex in_use_, mutex_;
  std::condition_variable wake_, done_;
  std::vector<std::thread> workers_;
  Loop* loop_ = nullptr;
  int wanted_ = 0, finished_ = 0, kept_ = std::numeric_limits<int>::max();
  std::uint64_t generation_ = 0;
};

// The process's pool. Never destroyed: its threads sleep until the process ends, so that no
// destructor at exit joins threads. A child process made by fork has none of its parent's threads
// and starts a pool of its own.
Pool& pool() {
  static std::mutex creating;
  static Pool* current = nullptr;
  static int owner = 0;
  const std::lock_guard<std::mutex> lock(creating);
  if (current == nullptr || owner != process_id()) {
    current = new Pool;
    owner = process_id();
  }
  return *current;
}

}  // namespace

int default_thread_count() {
  if (scoped_thread_count > 0) return scoped_thread_count;
  return core_count();
}

ThreadCountScope::ThreadCountScope(int threads) : saved_(scoped_thread_count) {
  if (threads > 0) scoped_thread_count = threads;
}

ThreadCountScope::~ThreadCountScope() { scoped_thread_count = saved_; }

void parallel_ranges(int count, int chunk, int threads, const std::function<void(int, int)>& body) {
  if (count <= 0) return;
  chunk = std::max(1, chunk);
  Loop loop(count, chunk, body);
  threads = std::min(threads > 0 ? threads : default_thread_count(), loop.chunks());
  // A loop inside a loop's body, or beside another caller's loop, runs on its own thread.
  if (threads <= 1 || inside_pool_thread || !pool().run(loop, threads - 1)) {
    body(0, count);
    return;
  }
  loop.rethrow();
}

}  // namespace shadecut::detail
