// The BVH at another revision (old_bvh*.h, renamed by run.sh) against the working tree's, in one
// process: the same rays traced by both at width 8 (eight lanes over a node's children and a
// block's triangles), one thread, CPU time of the thread, the two alternated, medians; every hit
// compared bit for bit. A mesh given with "-" for its rays times the two builds instead.
//   driver REPEAT MESH RAYS [MESH RAYS ...]      (files written by dump_rays.py)
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <vector>

#include "render/accel/bvh_traverse.h"
#include "render/accel/old_bvh_traverse.h"
#include "tools/ab_common/ab_timing.h"

using namespace patina;
using ab::cpu_seconds;
using ab::median;

namespace {
void read_or_die(FILE* f, void* p, size_t size, size_t count, const char* path) {
    if (std::fread(p, size, count, f) != count) {
        std::fprintf(stderr, "%s: cannot read\n", path);
        std::exit(2);
    }
}

FILE* open_or_die(const char* path) {
    FILE* f = std::fopen(path, "rb");
    if (!f) {
        std::fprintf(stderr, "%s: cannot open\n", path);
        std::exit(2);
    }
    return f;
}

// int64 T, then T x 9 float32 corners
std::vector<float> read_mesh(const char* path) {
    FILE* f = open_or_die(path);
    int64_t n;
    read_or_die(f, &n, 8, 1, path);
    std::vector<float> t(size_t(n) * 9);
    read_or_die(f, t.data(), 4, t.size(), path);
    std::fclose(f);
    return t;
}

// int64 n, int64 any_hit, then n x 3 origins, n x 3 directions, n tmax (float32)
struct Rays {
    int64_t n = 0, any_hit = 0;
    std::vector<float> o, d, tmax;
};

Rays read_rays(const char* path) {
    FILE* f = open_or_die(path);
    Rays r;
    read_or_die(f, &r.n, 8, 1, path);
    read_or_die(f, &r.any_hit, 8, 1, path);
    r.o.resize(size_t(r.n) * 3);
    r.d.resize(size_t(r.n) * 3);
    r.tmax.resize(size_t(r.n));
    read_or_die(f, r.o.data(), 4, r.o.size(), path);
    read_or_die(f, r.d.data(), 4, r.d.size(), path);
    read_or_die(f, r.tmax.data(), 4, r.tmax.size(), path);
    std::fclose(f);
    return r;
}

struct Hits {
    std::vector<float> t, u, v;
    std::vector<int32_t> prim;  // or the any-hit flag
    explicit Hits(size_t n) : t(n), u(n), v(n), prim(n) {}
    bool operator==(const Hits& o) const {
        const size_t bytes = 4 * t.size();
        return std::memcmp(t.data(), o.t.data(), bytes) == 0 && std::memcmp(u.data(), o.u.data(), bytes) == 0 &&
               std::memcmp(v.data(), o.v.data(), bytes) == 0 && prim == o.prim;
    }
};

template <bool kOld, class B>
double trace(const B& bvh, const Rays& r, Hits& out) {
    const double start = cpu_seconds();
    for (int64_t i = 0; i < r.n; ++i) {
        const float *o = &r.o[3 * i], *d = &r.d[3 * i];
        HitPacket<1> h;
        if constexpr (kOld) {
            if (r.any_hit) out.prim[i] = old_bvh_occluded<8, 8>(bvh, o, d, 0.0f, r.tmax[i]);
            else old_bvh_intersect<8, 8>(bvh, o, d, 0.0f, r.tmax[i], h);
        } else {
            if (r.any_hit) out.prim[i] = bvh_occluded<8, 8>(bvh, o, d, 0.0f, r.tmax[i]);
            else bvh_intersect<8, 8>(bvh, o, d, 0.0f, r.tmax[i], h);
        }
        if (!r.any_hit) out.t[i] = h.t, out.u[i] = h.u, out.v[i] = h.v, out.prim[i] = h.prim;
    }
    return cpu_seconds() - start;
}

template <class B>
size_t bytes_of(const B& bvh) {
    return bvh.nodes.size() * sizeof(bvh.nodes[0]) + bvh.blocks.size() * sizeof(bvh.blocks[0]);
}

void compare_builds(const char* name, const std::vector<float>& tri, int repeat) {
    std::vector<double> old_s, new_s;
    size_t old_bytes = 0, new_bytes = 0;
    for (int k = 0; k < repeat; ++k) {
        for (int which = 0; which < 2; ++which) {
            const double start = cpu_seconds();
            if ((which ^ (k & 1)) == 0) {
                old_bytes = bytes_of(old_build_bvh(tri.data(), tri.size() / 9));
                old_s.push_back(cpu_seconds() - start);
            } else {
                new_bytes = bytes_of(build_bvh(tri.data(), tri.size() / 9));
                new_s.push_back(cpu_seconds() - start);
            }
        }
    }
    std::printf("%-24s build old %.3f s new %.3f s (CPU, medians of %d); BVH bytes old %zu new %zu\n", name,
                median(old_s), median(new_s), repeat, old_bytes, new_bytes);
}
}  // namespace

int main(int argc, char** argv) {
    if (argc < 4) {
        std::fprintf(stderr, "usage: driver REPEAT MESH RAYS [MESH RAYS ...] (RAYS '-': builds only)\n");
        return 2;
    }
    const int repeat = std::atoi(argv[1]);
    for (int m = 2; m + 1 < argc; m += 2) {
        const std::vector<float> tri = read_mesh(argv[m]);
        if (std::strcmp(argv[m + 1], "-") == 0) {
            compare_builds(argv[m], tri, repeat);
            continue;
        }
        const Rays r = read_rays(argv[m + 1]);
        const OldBvh a = old_build_bvh(tri.data(), tri.size() / 9);
        const Bvh b = build_bvh(tri.data(), tri.size() / 9);
        Hits ha(size_t(r.n)), hb(size_t(r.n));
        std::vector<double> ta, tb, ratio;
        for (int k = 0; k < repeat; ++k) {
            double x, y;
            if (k % 2 == 0) {
                x = trace<true>(a, r, ha);
                y = trace<false>(b, r, hb);
            } else {
                y = trace<false>(b, r, hb);
                x = trace<true>(a, r, ha);
            }
            ta.push_back(x);
            tb.push_back(y);
            ratio.push_back(x / y);
        }
        const bool same = ha == hb;
        std::printf("%-32s %8lld rays %-7s old %.4f s new %.4f s old/new %.3f (median pair ratio %.3f) %s\n",
                    argv[m + 1], static_cast<long long>(r.n), r.any_hit ? "any" : "closest", median(ta), median(tb),
                    median(ta) / median(tb), median(ratio), same ? "identical" : "DIFFERENT");
        std::printf("    BVH bytes: old nodes %zu blocks %zu, new nodes %zu blocks %zu\n",
                    a.nodes.size() * sizeof(a.nodes[0]), a.blocks.size() * sizeof(a.blocks[0]),
                    b.nodes.size() * sizeof(b.nodes[0]), b.blocks.size() * sizeof(b.blocks[0]));
        if (!same) return 1;
    }
    return 0;
}
