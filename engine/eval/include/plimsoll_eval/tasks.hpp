// Running many bodies' evaluations on the caller's task system, as Box2D's b2WorldDef does:
// the caller gives an enqueue and a finish callback; without them a small thread pool of the
// library's own runs the work. Either way the call returns when every item is done.
#pragma once

#include <algorithm>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

namespace plimsoll_eval {

/// Runs items [begin, end) of a task; `worker` is in [0, workerCount).
using TaskCallback = void(int begin, int end, std::uint32_t worker, void* taskContext);

/// The caller's task system. enqueue starts `task` over `itemCount` items split into ranges of
/// at least `minRange`, and returns a handle that finish waits on (enqueue may also run the
/// task at once and return null; finish is then not called).
struct TaskSystem {
    void* (*enqueue)(TaskCallback* task, int itemCount, int minRange, void* taskContext,
                     void* userContext) = nullptr;
    void (*finish)(void* userTask, void* userContext) = nullptr;
    void* userContext = nullptr;
    int workerCount = 1;  ///< workers the task system may run at once

    bool given() const { return enqueue != nullptr && finish != nullptr; }
};

/// A fixed set of worker threads (the calling thread is worker 0): used when the caller gives
/// no task system. Threads are started once, not per call.
class ThreadPool {
public:
    /// Throws std::runtime_error ("cannot start thread 38 of 300: Resource temporarily
    /// unavailable") when the system refuses a thread, after stopping the ones started: a
    /// vector of running threads unwound by the exception would end the process instead.
    explicit ThreadPool(int threads) {
        const int extra = std::max(0, threads - 1);
        workers_.reserve(static_cast<std::size_t>(extra));  // no allocation among the starts
        for (int i = 0; i < extra; ++i) {
            try {
                workers_.emplace_back([this, i] { work(static_cast<std::uint32_t>(i + 1)); });
            } catch (const std::system_error& e) {
                stop();
                throw std::runtime_error("cannot start thread " + std::to_string(i + 2) + " of " +
                                         std::to_string(threads) + ": " + e.code().message());
            }
        }
    }
    ~ThreadPool() { stop(); }
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    int threads() const { return static_cast<int>(workers_.size()) + 1; }

    /// Runs task over [0, itemCount) in chunks of `minRange` items and returns when all are done.
    void run(TaskCallback* task, int itemCount, int minRange, void* taskContext) {
        if (itemCount <= 0) return;
        const int chunk = std::max(1, minRange);
        if (workers_.empty() || itemCount <= chunk) {
            task(0, itemCount, 0, taskContext);
            return;
        }
        {
            std::lock_guard<std::mutex> lock(mutex_);
            task_ = task;
            context_ = taskContext;
            count_ = itemCount;
            chunk_ = chunk;
            next_ = 0;
            busy_ = static_cast<int>(workers_.size());
            ++generation_;
        }
        wake_.notify_all();
        drain(0);
        std::unique_lock<std::mutex> lock(mutex_);
        done_.wait(lock, [this] { return busy_ == 0; });
    }

private:
    void stop() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
        }
        wake_.notify_all();
        for (std::thread& t : workers_) t.join();
        workers_.clear();
    }
    void drain(std::uint32_t worker) {
        for (;;) {
            int begin;
            {
                std::lock_guard<std::mutex> lock(mutex_);
                if (next_ >= count_) return;
                begin = next_;
                next_ = std::min(count_, next_ + chunk_);
            }
            task_(begin, std::min(count_, begin + chunk_), worker, context_);
        }
    }
    void work(std::uint32_t worker) {
        std::uint64_t seen = 0;
        for (;;) {
            {
                std::unique_lock<std::mutex> lock(mutex_);
                wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
                if (stop_) return;
                seen = generation_;
            }
            drain(worker);
            std::lock_guard<std::mutex> lock(mutex_);
            if (--busy_ == 0) done_.notify_all();
        }
    }

    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable wake_, done_;
    TaskCallback* task_ = nullptr;
    void* context_ = nullptr;
    int count_ = 0, chunk_ = 1, next_ = 0, busy_ = 0;
    std::uint64_t generation_ = 0;
    bool stop_ = false;
};

/// Runs `body(item, worker)` for every item in [0, count) on the caller's task system when one
/// is given, else on `pool`.
template <class Body>
void parallelFor(int count, int minRange, const TaskSystem& tasks, ThreadPool& pool, Body& body) {
    TaskCallback* callback = [](int begin, int end, std::uint32_t worker, void* context) {
        for (int i = begin; i < end; ++i) (*static_cast<Body*>(context))(i, worker);
    };
    if (tasks.given()) {
        void* handle = tasks.enqueue(callback, count, minRange, &body, tasks.userContext);
        if (handle) tasks.finish(handle, tasks.userContext);
        return;
    }
    pool.run(callback, count, minRange, &body);
}

}  // namespace plimsoll_eval
