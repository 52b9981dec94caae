// A thread that runs one job at a time for the frame loop: the sandbox steps its World there while the
// main thread draws the frame before (sandbox.cpp, "pipelined frames").
//
// Why a lasting thread and not std::async per frame: the CPU backend's OpenMP team belongs to the
// thread that opens the parallel regions; a new thread every frame would start a new team every frame.
// A job's exception is kept and thrown again by wait(), on the caller's thread, so a failed step
// reaches the same handlers as when it ran there.
#pragma once

#include <cassert>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace sandbox {

class FrameWorker {
public:
    FrameWorker() : m_thread([this] { loop(); }) {}
    ~FrameWorker() {
        {
            std::lock_guard<std::mutex> lock(m_mutex);
            m_quit = true;
        }
        m_changed.notify_all();
        m_thread.join();
    }
    FrameWorker(const FrameWorker&) = delete;
    FrameWorker& operator=(const FrameWorker&) = delete;

    // Starts `job` on the worker. The worker must be idle (wait() returned since the last post).
    void post(std::function<void()> job) {
        {
            std::lock_guard<std::mutex> lock(m_mutex);
            assert(!m_busy && "FrameWorker::post while a job runs");
            m_job = std::move(job);
            m_busy = true;
        }
        m_changed.notify_all();
    }

    // Returns once the posted job has finished (at once when none is running); throws what it threw.
    void wait() {
        std::unique_lock<std::mutex> lock(m_mutex);
        m_changed.wait(lock, [this] { return !m_busy; });
        if (m_error) {
            std::exception_ptr error = m_error;
            m_error = nullptr;
            std::rethrow_exception(error);
        }
    }

private:
    void loop() {
        std::unique_lock<std::mutex> lock(m_mutex);
        for (;;) {
            m_changed.wait(lock, [this] { return m_quit || m_busy; });
            if (m_quit) return;
            std::function<void()> job = std::move(m_job);
            lock.unlock();
            std::exception_ptr error;
            try {
                job();
            } catch (...) {
                error = std::current_exception();
            }
            lock.lock();
            m_error = error;
            m_busy = false;
            m_changed.notify_all();
        }
    }

    std::mutex m_mutex;
    std::condition_variable m_changed;
    std::function<void()> m_job;
    bool m_busy = false, m_quit = false;
    std::exception_ptr m_error;
    std::thread m_thread;  // last: started once the members it uses exist
};

}  // namespace sandbox
