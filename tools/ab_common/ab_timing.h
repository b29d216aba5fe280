// The A/B drivers' clock and statistic (tools/bvh_ab, tools/kdtree_build_ab): the calling
// thread's CPU time, so a shared machine's other work does not count, and the median of the
// alternated repeats.
#pragma once

#include <algorithm>
#include <ctime>
#include <vector>

namespace ab {
inline double cpu_seconds() {
    timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

inline double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}
}  // namespace ab
