// Times two kd-tree builds of the same mesh interleaved in one process (one thread, CPU time
// of the thread, medians), checks that they build the same tree and prints each tree's SAH
// cost. build_kdtree_old is render/accel/kdtree_build.cpp at another revision (run.sh).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

#include "render/accel/kdtree.h"
#include "tools/ab_common/ab_timing.h"

namespace patina {
KdTree build_kdtree_old(const float*, size_t, const int32_t*, size_t, const KdBuildOptions&);
}
using namespace patina;
using ab::cpu_seconds;
using ab::median;

namespace {
// The SAH cost of the tree as the builder defines it: traversal 1 per interior node and 1.5
// per triangle reference, each weighted by its cell's area relative to the root's.
double sah(const KdTree& t, uint32_t i, Box3 box, double root) {
    const KdNode& n = t.nodes[i];
    const double w = box.area() / root;
    if (n.is_leaf()) return w * 1.5 * n.count();
    Box3 l = box, r = box;
    l.hi[n.axis()] = n.split;
    r.lo[n.axis()] = n.split;
    return w + sah(t, i + 1, l, root) + sah(t, n.above(), r, root);
}

bool same_tree(const KdTree& a, const KdTree& b) {
    if (a.nodes.size() != b.nodes.size() || a.leaf_prims != b.leaf_prims) return false;
    for (size_t k = 0; k < a.nodes.size(); ++k)
        if (a.nodes[k].bits != b.nodes[k].bits || a.nodes[k].first != b.nodes[k].first) return false;
    return true;
}
}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: driver REPEAT MESH.bin...\n");
        return 2;
    }
    const int repeat = std::atoi(argv[1]);
    for (int m = 2; m < argc; ++m) {
        FILE* f = std::fopen(argv[m], "rb");
        int64_t count[2];
        if (!f || std::fread(count, 8, 2, f) != 2) {
            std::fprintf(stderr, "%s: cannot read\n", argv[m]);
            return 2;
        }
        std::vector<float> v(3 * size_t(count[0]));
        std::vector<int32_t> idx(3 * size_t(count[1]));
        const bool ok = std::fread(v.data(), 4, v.size(), f) == v.size() &&
                        std::fread(idx.data(), 4, idx.size(), f) == idx.size();
        std::fclose(f);
        if (!ok) {
            std::fprintf(stderr, "%s: truncated\n", argv[m]);
            return 2;
        }
        KdBuildOptions opt;
        opt.threads = 1;
        auto build = [&](bool old) {
            return old ? build_kdtree_old(v.data(), v.size() / 3, idx.data(), idx.size() / 3, opt)
                       : build_kdtree(v.data(), v.size() / 3, idx.data(), idx.size() / 3, opt);
        };
        std::vector<double> t_old, t_new;
        double sah_old = 0, sah_new = 0;
        bool same = true;
        for (int r = 0; r < repeat; ++r) {
            double c = cpu_seconds();
            const KdTree a = build(true);
            t_old.push_back(cpu_seconds() - c);
            c = cpu_seconds();
            const KdTree b = build(false);
            t_new.push_back(cpu_seconds() - c);
            if (r == 0) {
                sah_old = sah(a, 0, a.bounds, a.bounds.area());
                sah_new = sah(b, 0, b.bounds, b.bounds.area());
                same = same_tree(a, b);
            }
        }
        std::printf("%s: %lld triangles; CPU s old %.3f new %.3f, old/new %.3f; SAH old %.2f new %.2f; %s\n", argv[m],
                    static_cast<long long>(count[1]), median(t_old), median(t_new), median(t_old) / median(t_new),
                    sah_old, sah_new, same ? "the same tree" : "different trees");
    }
}
