#include "parallel.h"

#include <algorithm>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace patina {

int default_thread_count() {
    const unsigned hw = std::thread::hardware_concurrency();
    return hw == 0 ? 1 : static_cast<int>(hw);
}

void parallel_for(size_t n, size_t grain, int threads, const std::function<void(size_t, size_t)>& body) {
    if (threads <= 0) threads = default_thread_count();
    grain = std::max<size_t>(grain, 1);
    // Below this much work per thread, starting threads costs more than it saves.
    constexpr size_t kMinPerThread = 16384;
    const size_t useful = std::max<size_t>(1, n / kMinPerThread);
    const size_t workers = std::min<size_t>(static_cast<size_t>(threads), useful);
    if (workers <= 1) {
        if (n) body(0, n);
        return;
    }
    size_t chunk = (n + workers - 1) / workers;
    chunk = (chunk + grain - 1) / grain * grain;
    std::vector<std::thread> pool;
    std::exception_ptr error;
    std::mutex error_lock;
    for (size_t begin = 0; begin < n; begin += chunk) {
        const size_t end = std::min(n, begin + chunk);
        pool.emplace_back([&, begin, end] {
            try {
                body(begin, end);
            } catch (...) {
                std::lock_guard<std::mutex> g(error_lock);
                if (!error) error = std::current_exception();
            }
        });
    }
    for (auto& t : pool) t.join();
    if (error) std::rethrow_exception(error);
}

}  // namespace patina
