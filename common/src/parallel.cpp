#include "gdm/parallel.h"

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <vector>

#include <unistd.h>

namespace gdm::detail {

namespace {

// One loop's tasks, taken by the threads that join it.
struct Job {
  const std::function<void(std::size_t)>* task = nullptr;
  std::size_t tasks = 0;
  std::atomic<std::size_t> next{0};
  std::mutex error_mutex;
  std::exception_ptr error;

  void work() {
    for (std::size_t k = next.fetch_add(1); k < tasks; k = next.fetch_add(1)) {
      try {
        (*task)(k);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
      }
    }
  }
};

// Workers that sleep between loops. One loop at a time: a caller that finds
// it busy starts threads of its own.
class Pool {
 public:
  bool try_acquire() {
    bool expected = false;
    return !busy_.load(std::memory_order_relaxed) && busy_.compare_exchange_strong(expected, true);
  }
  void release() { busy_.store(false); }

  // Runs the job on the caller and up to `helpers` workers (the caller holds
  // the pool).
  void run(Job& job, std::size_t helpers) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      while (threads_.size() < helpers) threads_.emplace_back([this] { serve(); });
      job_ = &job;
      wanted_ = helpers;
      joined_ = 0;
      ++generation_;
    }
    wake_.notify_all();
    job.work();
    std::unique_lock<std::mutex> lock(mutex_);
    wanted_ = joined_;  // closed: a worker that wakes late does not join
    done_.wait(lock, [this] { return active_ == 0; });
    job_ = nullptr;
  }

 private:
  void serve() {
    std::uint64_t seen = 0;
    std::unique_lock<std::mutex> lock(mutex_);
    while (true) {
      wake_.wait(lock, [&] { return generation_ != seen; });
      seen = generation_;
      if (joined_ >= wanted_ || !job_) continue;
      ++joined_;
      ++active_;
      Job* job = job_;
      lock.unlock();
      job->work();
      lock.lock();
      if (--active_ == 0) done_.notify_one();
    }
  }

  std::atomic<bool> busy_{false};
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::vector<std::thread> threads_;  // never joined: they sleep until the process ends
  Job* job_ = nullptr;
  std::size_t wanted_ = 0, joined_ = 0, active_ = 0;
  std::uint64_t generation_ = 0;
};

// The process's pool. A child of fork() has none of its parent's threads: it
// starts a pool of its own (the parent's is left as it is).
Pool& pool() {
  static std::mutex mutex;
  static Pool* current = nullptr;
  static pid_t owner = 0;
  const std::lock_guard<std::mutex> lock(mutex);
  if (!current || owner != getpid()) {
    current = new Pool;  // never freed: its threads live as long as the process
    owner = getpid();
  }
  return *current;
}

}  // namespace

void run_tasks(std::size_t tasks, int threads, const std::function<void(std::size_t)>& task) {
  Job job;
  job.task = &task;
  job.tasks = tasks;
  const std::size_t helpers = std::min<std::size_t>(tasks, static_cast<std::size_t>(std::max(1, threads))) - 1;
  Pool& p = pool();
  if (helpers == 0) {
    job.work();
  } else if (p.try_acquire()) {
    p.run(job, helpers);
    p.release();
  } else {
    std::vector<std::thread> own;
    own.reserve(helpers);
    for (std::size_t w = 0; w < helpers; ++w) own.emplace_back([&job] { job.work(); });
    job.work();
    for (auto& t : own) t.join();
  }
  if (job.error) std::rethrow_exception(job.error);
}

}  // namespace gdm::detail
