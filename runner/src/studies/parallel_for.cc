#include "studies/parallel_for.h"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <thread>
#include <vector>

namespace burrlab::runner {

void ParallelFor(int n, int jobs, const std::function<void(int)>& task,
                 const std::function<void(int)>& done) {
  std::atomic<int> next{0};
  std::mutex mutex;
  const auto worker = [&]() {
    for (int i = next.fetch_add(1); i < n; i = next.fetch_add(1)) {
      task(i);
      if (done) {
        std::lock_guard<std::mutex> lock(mutex);
        done(i);
      }
    }
  };
  const int threads = std::clamp(jobs, 1, std::max(1, n));
  if (threads == 1) {
    worker();
    return;
  }
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) pool.emplace_back(worker);
  for (std::thread& t : pool) t.join();
}

}  // namespace burrlab::runner
