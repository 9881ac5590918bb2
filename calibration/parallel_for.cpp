#include "calibration/parallel_for.hpp"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <exception>
#include <list>
#include <mutex>
#include <thread>
#include <vector>

namespace tofcomp::calibration {
namespace {

// One call of parallel_for: its indices, handed out one at a time to the caller and to the
// workers that join it.
struct Job {
  const std::function<void(int)>* task = nullptr;
  int count = 0;
  std::atomic<int> next{0};
  int helpers_left = 0;  // workers that may still join (the call's thread budget); pool's mutex
  int helping = 0;       // workers inside the job now; pool's mutex
  std::mutex failure_mutex;
  std::exception_ptr failure;

  bool open() const { return helpers_left > 0 && next.load() < count; }
  // Runs indices until none is left; a task's exception is kept (the first one) and the rest run.
  void work() {
    for (int i = next++; i < count; i = next++) {
      try {
        (*task)(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = std::current_exception();
      }
    }
  }
};

// The process's workers, started on first use and kept until exit, so that a call costs a
// wake-up, not a thread's start (the EM sweeps call twice an iteration, a millisecond apart).
// A worker takes any open job; the caller of a job works on it too and waits only for the
// workers inside it, so a task that itself calls parallel_for (a fold's fit striping its
// sweeps) never waits for a worker that is busy elsewhere: nested calls cannot deadlock.
class WorkerPool {
 public:
  static WorkerPool& instance() {
    static WorkerPool pool;
    return pool;
  }

  void run(int count, int threads, const std::function<void(int)>& task) {
    Job job;
    job.task = &task;
    job.count = count;
    job.helpers_left = std::min(threads, count) - 1;
    std::list<Job*>::iterator queued;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      grow(job.helpers_left);
      queued = jobs_.insert(jobs_.end(), &job);
    }
    work_ready_.notify_all();
    job.work();
    {
      std::unique_lock<std::mutex> lock(mutex_);
      jobs_.erase(queued);  // no worker joins it from here on
      job_left_.wait(lock, [&] { return job.helping == 0; });
    }
    if (job.failure) std::rethrow_exception(job.failure);
  }

  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  ~WorkerPool() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
    }
    work_ready_.notify_all();
    for (std::thread& t : workers_) t.join();
  }

 private:
  WorkerPool() = default;

  // At least `count` workers (caller holds mutex_).
  void grow(int count) {
    while (static_cast<int>(workers_.size()) < count) workers_.emplace_back([this] { serve(); });
  }

  Job* open_job() {
    for (Job* job : jobs_) {
      if (job->open()) return job;
    }
    return nullptr;
  }

  void serve() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      Job* job = nullptr;
      work_ready_.wait(lock, [&] { return stopping_ || (job = open_job()) != nullptr; });
      if (stopping_) return;
      --job->helpers_left;
      ++job->helping;
      lock.unlock();
      job->work();
      lock.lock();
      if (--job->helping == 0) job_left_.notify_all();
    }
  }

  std::mutex mutex_;
  std::condition_variable work_ready_;
  std::condition_variable job_left_;
  std::list<Job*> jobs_;
  std::vector<std::thread> workers_;
  bool stopping_ = false;
};

}  // namespace

int thread_count(int requested) {
  if (requested > 0) return requested;
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

void parallel_for(int n, int threads, const std::function<void(int)>& task) {
  if (n <= 0) return;
  if (threads <= 1 || n == 1) {
    // Serial: every task runs, the first exception is rethrown at the end (as on threads).
    std::exception_ptr failure;
    for (int i = 0; i < n; ++i) {
      try {
        task(i);
      } catch (...) {
        if (!failure) failure = std::current_exception();
      }
    }
    if (failure) std::rethrow_exception(failure);
    return;
  }
  WorkerPool::instance().run(n, threads, task);
}

core::ParallelFor parallel_runner(int threads) {
  const int count = thread_count(threads);
  return [count](int n, const std::function<void(int)>& task) { parallel_for(n, count, task); };
}

}  // namespace tofcomp::calibration
