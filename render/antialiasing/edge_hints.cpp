#include "render/antialiasing/edge_hints.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <thread>
#include <unordered_map>

#include "render/accel/trace_kernels.h"
#include "render/antialiasing/adaptive_pattern.h"
#include "render/antialiasing/sphere_silhouettes.h"

namespace patina {
namespace {

struct V3 {
    double x, y, z;
};
V3 sub(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 load(const float* p) { return {p[0], p[1], p[2]}; }

// The zones of canonical coordinates u in [ua, ub] (either order), as flags.
uint8_t zones_between(double ua, double ub) {
    if (ua > ub) std::swap(ua, ub);
    const auto zone = [](double u) {
        return std::clamp(static_cast<int>(std::floor(u / aa::kZoneWidth)), 0, aa::kZones - 1);
    };
    uint8_t z = 0;
    for (int j = zone(ua); j <= zone(ub); ++j) z |= 1u << j;
    return z;
}

// The zones a piece of an edge from (ua, va) to (ub, vb) (canonical coordinates) crosses
// between the heights of the zigzags' rows, v in [1/4, 3/4]: where a zigzag places it (its
// rays are at v = 1/4 and 3/4; the parts of an oblique edge above and below the rows are left
// to the corners and the neighbouring strips, a zigzag less for a little accuracy). At
// 256 x 192 this band against [1/8, 7/8] took the converging lines from 3.87 to 3.68 rays a
// pixel and the wires from 2.51 to 2.43 at the same RMSE (to 1 %); [3/8, 5/8] cost 20 % in
// RMSE on the lines. A piece that does not reach the band: the zones it crosses.
constexpr double kBandLow = 0.25, kBandHigh = 0.75;

uint8_t zones_crossed(double ua, double va, double ub, double vb) {
    const double lo = kBandLow, hi = kBandHigh;
    double ta = 0, tb = 1;
    const double dv = vb - va;
    if (dv != 0) {
        const double t_lo = (lo - va) / dv, t_hi = (hi - va) / dv;
        ta = std::max(ta, std::min(t_lo, t_hi));
        tb = std::min(tb, std::max(t_lo, t_hi));
    } else if (va < lo || va > hi) {
        tb = -1;
    }
    if (!(ta <= tb)) return zones_between(ua, ub);
    return zones_between(ua + ta * (ub - ua), ua + tb * (ub - ua));
}

// One mesh edge between merged vertices, and the triangles that have it.
struct EdgeUse {
    int32_t tri[2] = {-1, -1};
    int32_t ends[2][2] = {};  // per triangle: its corners (3 t + e) at the two ends
    int32_t place[2] = {};    // the two ends' merged vertices (place[0] at ends[k][0])
    int count = 0;
};

// The shadow of a segment pa-pb: points of it cast along the light's rays onto what lies
// behind (`receiver`), and the pieces between neighbouring casts that land side by side on
// the film (within kShadowStep pixels) handed to `project` as world segments. A piece
// whose casts are farther apart is halved, down to kShadowDepth halvings: a shadow that
// jumps from one surface to another, or falls off the geometry, ends there. The halvings
// follow the shadow's own size on the film, however near the light is to the edge.
constexpr int kShadowDepth = 12;
constexpr double kShadowStep = 1.5;

struct Cast {
    bool seen = false;  // a receiver behind the point, in front of the camera
    V3 q{};
    double x = 0, y = 0;  // q on the film
};

template <class Receiver, class Film, class Project>
void cast_piece(V3 pa, V3 pb, double t0, const Cast& c0, double t1, const Cast& c1, int depth,
                const Receiver& receiver, const Film& film, const Project& project, int width, int height) {
    if (!c0.seen && !c1.seen) return;
    if (c0.seen && c1.seen) {
        const double dx = c1.x - c0.x, dy = c1.y - c0.y;
        if (dx * dx + dy * dy <= kShadowStep * kShadowStep) {
            project(c0.q, c1.q);
            return;
        }
        // both casts off the film on one side: a straight piece stays there (a curved
        // receiver bringing it back is left out)
        if ((c0.x < 0 && c1.x < 0) || (c0.y < 0 && c1.y < 0) || (c0.x > width && c1.x > width) ||
            (c0.y > height && c1.y > height))
            return;
    }
    if (depth >= kShadowDepth) return;
    const double tm = 0.5 * (t0 + t1);
    Cast cm;
    const V3 pm{pa.x + tm * (pb.x - pa.x), pa.y + tm * (pb.y - pa.y), pa.z + tm * (pb.z - pa.z)};
    cm.seen = receiver(pm, cm.q) && film(cm.q, cm.x, cm.y);
    cast_piece(pa, pb, t0, c0, tm, cm, depth + 1, receiver, film, project, width, height);
    cast_piece(pa, pb, tm, cm, t1, c1, depth + 1, receiver, film, project, width, height);
}

// One point cast: where the light's ray past p lands, and there on the film.
template <class Receiver, class Film>
Cast cast_point(V3 p, const Receiver& receiver, const Film& film) {
    Cast c;
    c.seen = receiver(p, c.q) && film(c.q, c.x, c.y);
    return c;
}

// The mesh's edges between vertices merged by position, each with the triangles that have it:
// what of the pre-pass depends on the geometry alone.
std::vector<EdgeUse> make_mesh_edges(const RenderScene& s) {
    const size_t nt = s.triangle_count;
    const float* tri = s.tree->triangles.data();  // corner e of triangle t at tri + 9 t + 3 e
    // the vertices merged by position (sorted by their coordinates' bits, so the merge is the
    // same in every run): a mesh's seams (split normals or uvs) and shapes that meet exactly
    // share their edges. Vertices, not corners: a mesh shares its vertices, so there are a
    // sixth as many to sort.
    int32_t nv = 0;
    for (size_t k = 0; k < 3 * nt; ++k) nv = std::max(nv, s.indices[k] + 1);
    struct Vertex {
        uint32_t position_bits[3];
        int32_t index;  // -1: no triangle uses it
    };
    std::vector<Vertex> verts(static_cast<size_t>(nv), Vertex{{0, 0, 0}, -1});
    for (size_t k = 0; k < 3 * nt; ++k) {
        Vertex& x = verts[s.indices[k]];
        if (x.index >= 0) continue;
        x.index = s.indices[k];
        for (int a = 0; a < 3; ++a) {
            float f = tri[3 * k + a];
            if (f == 0) f = 0;  // -0 and +0 alike
            std::memcpy(&x.position_bits[a], &f, 4);
        }
    }
    std::sort(verts.begin(), verts.end(), [](const Vertex& x, const Vertex& y) {
        if (x.position_bits[0] != y.position_bits[0]) return x.position_bits[0] < y.position_bits[0];
        if (x.position_bits[1] != y.position_bits[1]) return x.position_bits[1] < y.position_bits[1];
        if (x.position_bits[2] != y.position_bits[2]) return x.position_bits[2] < y.position_bits[2];
        return x.index < y.index;
    });
    std::vector<int32_t> place(static_cast<size_t>(nv), -1);  // vertex -> its merged place
    int32_t places = 0;
    for (size_t i = 0; i < verts.size(); ++i) {
        if (verts[i].index < 0) continue;  // an index no triangle uses
        const bool same = i > 0 && verts[i - 1].index >= 0 &&
                          verts[i - 1].position_bits[0] == verts[i].position_bits[0] &&
                          verts[i - 1].position_bits[1] == verts[i].position_bits[1] &&
                          verts[i - 1].position_bits[2] == verts[i].position_bits[2];
        if (!same) ++places;
        place[verts[i].index] = places - 1;
    }
    const auto merged = [&](int32_t corner) { return place[s.indices[corner]]; };
    // every triangle's edges bucketed by their lower end (counting sort), then each small
    // bucket sorted by the other end: the uses of one edge side by side
    struct EdgeRef {
        int32_t other, triangle, corner_a, corner_b;
    };
    std::vector<int32_t> start(static_cast<size_t>(places) + 1, 0);
    for (size_t t = 0; t < nt; ++t)
        for (int e = 0; e < 3; ++e) {
            const int32_t pa = merged(static_cast<int32_t>(3 * t + e));
            const int32_t pb = merged(static_cast<int32_t>(3 * t + (e + 1) % 3));
            if (pa != pb) ++start[std::min(pa, pb) + 1];
        }
    for (int32_t p = 0; p < places; ++p) start[p + 1] += start[p];
    std::vector<EdgeRef> refs(static_cast<size_t>(start[places]));
    std::vector<int32_t> fill(start.begin(), start.end() - 1);
    for (size_t t = 0; t < nt; ++t)
        for (int e = 0; e < 3; ++e) {
            int32_t ca = static_cast<int32_t>(3 * t + e), cb = static_cast<int32_t>(3 * t + (e + 1) % 3);
            if (merged(ca) == merged(cb)) continue;  // a degenerate edge
            if (merged(ca) > merged(cb)) std::swap(ca, cb);
            refs[fill[merged(ca)]++] = {merged(cb), static_cast<int32_t>(t), ca, cb};
        }
    std::vector<EdgeUse> edges;
    for (int32_t p = 0; p < places; ++p) {
        const auto b0 = refs.begin() + start[p], b1 = refs.begin() + start[p + 1];
        std::sort(b0, b1, [](const EdgeRef& x, const EdgeRef& y) {
            return x.other != y.other ? x.other < y.other : x.triangle < y.triangle;
        });
        for (auto i = b0; i != b1;) {
            auto j = i;
            EdgeUse u;
            u.place[0] = p;
            u.place[1] = i->other;
            for (; j != b1 && j->other == i->other; ++j, ++u.count)
                if (u.count < 2) {
                    u.tri[u.count] = j->triangle;
                    u.ends[u.count][0] = j->corner_a;
                    u.ends[u.count][1] = j->corner_b;
                }
            edges.push_back(u);
            i = j;
        }
    }
    return edges;
}

// A content key of the geometry the edges are made from: the triangles' positions and indices.
uint64_t geometry_key(const RenderScene& s) {
    uint64_t k = 0xcbf29ce484222325ull;  // FNV-1a over 32-bit words
    const auto add = [&](const void* data, size_t words) {
        const uint32_t* w = static_cast<const uint32_t*>(data);
        for (size_t i = 0; i < words; ++i) k = (k ^ w[i]) * 0x100000001b3ull;
    };
    add(s.tree->triangles.data(), 9 * s.triangle_count);
    add(s.indices, 3 * s.triangle_count);
    return k;
}

struct MeshEdges {
    uint64_t key = 0;
    size_t triangles = 0;
    std::vector<EdgeUse> edges;
};

// The last geometry's edges, kept: a preview or a bench re-rendering one scene (another
// camera, another light) merges and sorts its vertices and edges once. Keyed by content, so
// a new scene, even at the old one's addresses, makes its own.
std::shared_ptr<const MeshEdges> mesh_edges(const RenderScene& s) {
    static std::mutex lock;
    static std::shared_ptr<const MeshEdges> last;
    const uint64_t key = geometry_key(s);
    {
        std::lock_guard<std::mutex> g(lock);
        if (last != nullptr && last->key == key && last->triangles == s.triangle_count) return last;
    }
    auto made = std::make_shared<MeshEdges>();
    made->key = key;
    made->triangles = s.triangle_count;
    made->edges = make_mesh_edges(s);
    std::lock_guard<std::mutex> g(lock);
    last = made;
    return made;
}

}  // namespace

void AaEdgeHints::resize(int w, int h) {
    width = w;
    height = h;
    const size_t pixels = static_cast<size_t>(w) * h;
    zones[0].assign(pixels, 0);
    zones[1].assign(pixels, 0);
    nearest.assign(pixels, std::numeric_limits<float>::infinity());
}

void rasterise_edge(AaEdgeHints& h, float x0f, float y0f, float x1f, float y1f, float z0, float z1, float tan_x,
                    float tan_y, std::vector<double>& ts) {
    const double x0 = x0f, y0 = y0f, dx = double(x1f) - x0, dy = double(y1f) - y0;
    // Liang-Barsky: the part of the segment inside the image
    double ta = 0, tb = 1;
    const double p[4] = {-dx, dx, -dy, dy}, q[4] = {x0, h.width - x0, y0, h.height - y0};
    for (int k = 0; k < 4; ++k) {
        if (p[k] == 0) {
            if (q[k] < 0) return;
            continue;
        }
        const double t = q[k] / p[k];
        if (p[k] < 0)
            ta = std::max(ta, t);
        else
            tb = std::min(tb, t);
    }
    if (!(ta <= tb)) return;
    // where it crosses the pixel grid: between two consecutive crossings it is in one pixel
    ts.assign({ta, tb});
    const auto crossings = [&](double a, double d) {
        if (d == 0) return;
        const double lo = std::min(a + ta * d, a + tb * d), hi = std::max(a + ta * d, a + tb * d);
        for (double g = std::ceil(lo); g <= hi; g += 1) ts.push_back((g - a) / d);
    };
    crossings(x0, dx);
    crossings(y0, dy);
    std::sort(ts.begin(), ts.end());
    const auto distance = [&](double t) {
        // 1/z is linear in film space (perspective); the distance is z times the ray's length a unit of z
        const double z = 1.0 / ((1 - t) / z0 + t / z1);
        const double sx = (2 * (x0 + t * dx) / h.width - 1) * tan_x, sy = (1 - 2 * (y0 + t * dy) / h.height) * tan_y;
        return z * std::sqrt(1 + sx * sx + sy * sy);
    };
    // each crossing's distance once, for the pieces on both sides of it
    double distance0 = distance(ts[0]);
    for (size_t k = 0; k + 1 < ts.size(); ++k) {
        const double t0 = ts[k], t1 = ts[k + 1], tm = 0.5 * (t0 + t1);
        const double distance1 = distance(t1);
        const double nearest = std::min(distance0, distance1);
        distance0 = distance1;
        if (t1 - t0 < 1e-12 && ts.size() > 2) continue;
        const int px = std::clamp(static_cast<int>(std::floor(x0 + tm * dx)), 0, h.width - 1);
        const int py = std::clamp(static_cast<int>(std::floor(y0 + tm * dy)), 0, h.height - 1);
        const size_t i = static_cast<size_t>(py) * h.width + px;
        const double xa = x0 + t0 * dx - px, xb = x0 + t1 * dx - px, ya = y0 + t0 * dy - py, yb = y0 + t1 * dy - py;
        h.zones[0][i] |= zones_crossed(xa, ya, xb, yb);                  // (u, v) = (x, y)
        h.zones[1][i] |= zones_crossed(1 - ya, xa, 1 - yb, xb);          // turned: (u, v) = (1 - y, x)
        h.nearest[i] = std::min(h.nearest[i], static_cast<float>(nearest));
    }
}

AaEdgeHints project_feature_edges(const RenderScene& s, float threshold, int threads) {
    AaEdgeHints h;
    const Camera& c = s.camera;
    h.resize(c.width, c.height);
    const size_t pixels = static_cast<size_t>(c.width) * c.height;
    const bool triangles = s.tree != nullptr && s.indices != nullptr && s.triangle_count > 0 &&
                           s.tree->triangle_count() == s.triangle_count;
    if (!triangles && (s.tree == nullptr || s.tree->spheres.empty())) return h;
    const float* tri = s.tree->triangles.data();  // corner e of triangle t at tri + 9 t + 3 e
    const std::shared_ptr<const MeshEdges> mesh = triangles ? mesh_edges(s) : std::make_shared<const MeshEdges>();
    const std::vector<EdgeUse>& edges = mesh->edges;
    const V3 eye = load(c.position), fwd = load(c.forward), right = load(c.right), up = load(c.up);
    const double tan_y = c.tan_half_fov, tan_x = tan_y * c.width / c.height;
    const double z_near = 1e-5 * std::max(s.scene_radius, 1e-6f);
    const float* ng = s.tree->normals.data();
    const auto front = [&](int32_t t, V3 p) { return dot(load(ng + 3 * static_cast<size_t>(t)), sub(eye, p)) > 0; };
    const auto crease = [&](int32_t a, int32_t b) {  // two triangle corners at one place
        if (s.normals == nullptr) return false;
        const double d = dot(load(s.normals + 3 * static_cast<size_t>(s.indices[a])),
                             load(s.normals + 3 * static_cast<size_t>(s.indices[b])));
        return 0.5 * (1 - d) > threshold;
    };
    // a world-space segment into the hints: camera space, clipped to the near plane, then the
    // pinhole projection (crossings: the calling thread's scratch for rasterise_edge)
    const auto project = [&](AaEdgeHints& out, V3 pa, V3 pb, std::vector<double>& crossings) {
        const V3 da = sub(pa, eye), db = sub(pb, eye);
        double za = dot(da, fwd), zb = dot(db, fwd), xa = dot(da, right), xb = dot(db, right), ya = dot(da, up),
               yb = dot(db, up);
        if (za < z_near && zb < z_near) return;
        if (za < z_near || zb < z_near) {
            const double t = (z_near - za) / (zb - za);
            const double xn = xa + t * (xb - xa), yn = ya + t * (yb - ya);
            if (za < z_near) {
                xa = xn, ya = yn, za = z_near;
            } else {
                xb = xn, yb = yn, zb = z_near;
            }
        }
        const auto fx = [&](double x, double z) { return static_cast<float>((x / z / tan_x + 1) * 0.5 * c.width); };
        const auto fy = [&](double y, double z) { return static_cast<float>((1 - y / z / tan_y) * 0.5 * c.height); };
        rasterise_edge(out, fx(xa, za), fy(ya, za), fx(xb, zb), fy(yb, zb), static_cast<float>(za),
                       static_cast<float>(zb), static_cast<float>(tan_x), static_cast<float>(tan_y), crossings);
    };
    const auto film = [&](V3 p, double& x, double& y) {  // film position of a point in front of the camera
        const V3 d = sub(p, eye);
        const double z = dot(d, fwd);
        if (z < z_near) return false;
        x = (dot(d, right) / z / tan_x + 1) * 0.5 * c.width;
        y = (1 - dot(d, up) / z / tan_y) * 0.5 * c.height;
        return true;
    };
    // the edges [begin, end) into `out`: the feature edges, then the shadows
    const auto walk = [&](size_t begin, size_t end, AaEdgeHints& out) {
        std::vector<double> crossings;
        for (size_t e = begin; e < end; ++e) {
            const EdgeUse& u = edges[e];
            const V3 pa = load(tri + 3 * static_cast<size_t>(u.ends[0][0]));
            const V3 pb = load(tri + 3 * static_cast<size_t>(u.ends[0][1]));
            bool feature = u.count != 2;
            if (!feature) {
                const int32_t t0 = u.tri[0], t1 = u.tri[1];
                feature = s.tri_material != nullptr && s.tri_material[t0] != s.tri_material[t1];
                feature = feature || front(t0, pa) != front(t1, pa);
                feature = feature || crease(u.ends[0][0], u.ends[1][0]) || crease(u.ends[0][1], u.ends[1][1]);
            }
            if (feature) project(out, pa, pb, crossings);
        }
        std::unordered_map<int32_t, Cast> casts;  // a light's casts of the merged vertices, by vertex
        // shadow edges: the edges that are silhouettes seen from a light (or boundaries), cast
        // along the light's rays onto what lies behind them; the pieces of the cast shadow are
        // projected into the image like the feature edges
        const TraceKernels& kernels = trace_kernels_w1();  // one width: the same hits for every SIMD width
        for (const Light& light : s.lights) {
            const bool local = is_delta_light(light);
            const SunLight* sun_light = std::get_if<SunLight>(&light.model);
            if (!local && !sun_light) continue;  // area lights and environments: soft shadows
            const V3 lp = local ? load(delta_position(light)) : V3{0, 0, 0};
            const V3 sun = sun_light ? load(sun_light->direction) : V3{0, 0, 0};
            const auto towards_light = [&](V3 p) { return local ? sub(lp, p) : sun; };
            // where the light's ray past p lands: the receiver, or false when nothing is behind p
            const auto receiver = [&](V3 p, V3& q) {
                const V3 d = towards_light(p);
                const double len = std::sqrt(dot(d, d));
                if (!(len > 0)) return false;
                const float o[3] = {float(p.x), float(p.y), float(p.z)};
                const float dir[3] = {float(-d.x / len), float(-d.y / len), float(-d.z / len)};
                // past the edge's own triangles (a ray grazing a smooth mesh's silhouette would
                // find the next facet at once)
                const float tmin = s.ray_offset + 1e-3f * static_cast<float>(local ? len : s.scene_radius);
                float t = std::numeric_limits<float>::infinity(), bu = 0, bv = 0;
                int32_t prim = -1;
                kernels.intersect(*s.tree, RayBatch{o, dir, tmin, nullptr, std::numeric_limits<float>::infinity()},
                                  HitBatch{&t, &prim, &bu, &bv}, 0, 1);
                if (prim < 0) return false;
                q = {p.x + t * dir[0], p.y + t * dir[1], p.z + t * dir[2]};
                return true;
            };
            const auto lit_front = [&](int32_t t, V3 p) {
                return dot(load(ng + 3 * static_cast<size_t>(t)), towards_light(p)) > 0;
            };
            // each end of a shadow edge cast once: the edges of a silhouette meet end to end, so
            // most ends are shared by two edges (the same merged vertex, the same ray, the same
            // cast). Started from its two ends, an edge whose shadow is short on the film costs
            // no ray more (the ball's pre-pass took 250 ms starting from eight pieces an edge,
            // 45 ms from one); the shared ends took the ball's casts from 2816 rays to 2100.
            casts.clear();
            const auto end_cast = [&](int32_t place, V3 p) -> const Cast& {
                const auto [it, fresh] = casts.try_emplace(place);
                if (fresh) it->second = cast_point(p, receiver, film);
                return it->second;
            };
            for (size_t e = begin; e < end; ++e) {
                const EdgeUse& u = edges[e];
                const V3 pa = load(tri + 3 * static_cast<size_t>(u.ends[0][0]));
                const V3 pb = load(tri + 3 * static_cast<size_t>(u.ends[0][1]));
                if (u.count == 2 && lit_front(u.tri[0], pa) == lit_front(u.tri[1], pa)) continue;
                const Cast a = end_cast(u.place[0], pa), b = end_cast(u.place[1], pb);
                const auto project_piece = [&](V3 x, V3 y) { project(out, x, y, crossings); };
                cast_piece(pa, pb, 0.0, a, 1.0, b, 0, receiver, film, project_piece, c.width, c.height);
            }
        }
    };
    // the edges split among threads, each into hints of its own, then merged: zones by OR,
    // distances by min, so the hints are the same for any thread count
    const size_t parts = std::clamp<size_t>(static_cast<size_t>(std::max(threads, 1)), 1,
                                            std::max<size_t>(1, edges.size() / 1024));
    std::vector<AaEdgeHints> part(parts - 1);
    std::vector<std::thread> workers;
    const auto bound = [&](size_t k) { return edges.size() * k / parts; };
    // each helper sizes its own part (1.2 MB at 512 x 384: 0.1 ms the first thread waited for)
    for (size_t k = 1; k < parts; ++k)
        workers.emplace_back([&, k] {
            part[k - 1].resize(c.width, c.height);
            walk(bound(k), bound(k + 1), part[k - 1]);
        });
    walk(0, bound(1), h);
    // the analytic spheres' silhouettes, which have no triangle edges (their cast shadows are
    // left to the signal)
    std::vector<double> crossings;
    for_each_silhouette_piece(s.tree->spheres, c.position, [&](const double* a, const double* b) {
        project(h, V3{a[0], a[1], a[2]}, V3{b[0], b[1], b[2]}, crossings);
    });
    for (auto& w : workers) w.join();
    // merged where a part has an edge (every piece an edge leaves in a pixel flags a zone of
    // zones[0], and only such a piece sets its distance): the full arrays' merge took 0.3 ms
    // of the checkerboard's serial pre-pass at 512 x 384
    for (const AaEdgeHints& o : part)
        for (size_t i = 0; i < pixels; ++i) {
            if (o.zones[0][i] == 0) continue;
            h.zones[0][i] |= o.zones[0][i];
            h.zones[1][i] |= o.zones[1][i];
            h.nearest[i] = std::min(h.nearest[i], o.nearest[i]);
        }
    h.spots = find_highlight_spots(s, threads);
    return h;
}

}  // namespace patina
