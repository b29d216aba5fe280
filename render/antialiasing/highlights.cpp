#include "render/antialiasing/highlights.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

#include "render/accel/trace_kernels.h"

namespace patina {
namespace {

struct V3 {
    double x, y, z;
};
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator*(double s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
V3 unit(V3 a) {
    const double l = std::sqrt(dot(a, a));
    return l > 0 ? (1 / l) * a : V3{0, 0, 0};
}
V3 load(const float* p) { return {p[0], p[1], p[2]}; }

// One triangle with its shading normals (oriented towards the camera's side).
struct Tri {
    V3 p[3], n[3], ng;
};

// Barycentric weights of p in the triangle's plane (extrapolated outside it).
void barycentric(const Tri& t, V3 p, double b[3]) {
    const V3 e1 = t.p[1] - t.p[0], e2 = t.p[2] - t.p[0], d = p - t.p[0];
    const double d00 = dot(e1, e1), d01 = dot(e1, e2), d11 = dot(e2, e2), d20 = dot(d, e1), d21 = dot(d, e2);
    const double den = d00 * d11 - d01 * d01;
    b[1] = den != 0 ? (d11 * d20 - d01 * d21) / den : 0;
    b[2] = den != 0 ? (d00 * d21 - d01 * d20) / den : 0;
    b[0] = 1 - b[1] - b[2];
}

V3 shading_normal(const Tri& t, const double b[3]) { return unit(b[0] * t.n[0] + b[1] * t.n[1] + b[2] * t.n[2]); }

}  // namespace

std::vector<AaSpot> find_highlight_spots(const RenderScene& scene, int threads) {
    std::vector<AaSpot> pieces;
    const bool triangles = scene.tree != nullptr && scene.indices != nullptr && scene.triangle_count > 0 &&
                           scene.tree->triangle_count() == scene.triangle_count;
    if (!triangles && (scene.tree == nullptr || scene.tree->spheres.empty())) return pieces;
    const size_t triangle_count = triangles ? scene.triangle_count : 0;
    const Camera& camera = scene.camera;
    const V3 eye = load(camera.position), fwd = load(camera.forward), right = load(camera.right), up = load(camera.up);
    const double tan_y = camera.tan_half_fov, tan_x = tan_y * camera.width / camera.height;
    const float* tri = scene.tree->triangles.data();  // corner e of triangle t at tri + 9 t + 3 e
    const float* ng = scene.tree->normals.data();
    const TraceKernels& kernels = trace_kernels_w1();  // one width: the same hits for every SIMD width
    // the first hit along a ray from o towards d (unit) beyond tmin: its distance, inf for none
    const auto first_hit = [&](V3 o, V3 d, float tmin, float tmax) {
        const float of[3] = {float(o.x), float(o.y), float(o.z)}, df[3] = {float(d.x), float(d.y), float(d.z)};
        float t = std::numeric_limits<float>::infinity(), bu = 0, bv = 0;
        int32_t prim = -1;
        kernels.intersect(*scene.tree, RayBatch{of, df, tmin, nullptr, tmax}, HitBatch{&t, &prim, &bu, &bv}, 0, 1);
        return prim < 0 ? std::numeric_limits<double>::infinity() : double(t);
    };
    // the film position of a point in front of the camera, and the camera ray through a film position
    const auto film = [&](V3 p, double& x, double& y) {
        const V3 d = p - eye;
        const double z = dot(d, fwd);
        if (!(z > 1e-9)) return false;
        x = (dot(d, right) / z / tan_x + 1) * 0.5 * camera.width;
        y = (1 - dot(d, up) / z / tan_y) * 0.5 * camera.height;
        return true;
    };
    const auto ray_dir = [&](double x, double y) {
        return fwd + ((2 * x / camera.width - 1) * tan_x) * right + ((1 - 2 * y / camera.height) * tan_y) * up;
    };
    struct Rect {
        double x0, y0, x1, y1;
    };
    // the spots on triangles [t_begin, t_end) into `spots`
    const auto search = [&](size_t t_begin, size_t t_end, std::vector<Rect>& spots) {
        for (const Light& light : scene.lights) {
            const bool local = is_delta_light(light);
            const SunLight* sun_light = std::get_if<SunLight>(&light.model);
            if (!local && !sun_light) continue;  // area lights and environments: broad highlights
            const V3 lp = local ? load(delta_position(light)) : V3{0, 0, 0};
            const V3 sun = sun_light ? load(sun_light->direction) : V3{0, 0, 0};
            // the sun is a disc: its mirror image is spread over half its angular radius of normals
            const double sun_spread = sun_light ? 0.5 * std::acos(std::clamp<double>(sun_light->cos_sun, -1, 1)) : 0;
            const SpotLight* spot = std::get_if<SpotLight>(&light.model);
            const auto to_light = [&](V3 p) { return local ? unit(lp - p) : unit(sun); };
            const auto half = [&](V3 p) { return unit(to_light(p) + unit(eye - p)); };
            // the spot at p, a point where the shading normal is the half-vector (ngp: the geometric
            // normal there, facing the camera; normal_at(x, y, q, n): the point q and shading normal n
            // where the camera ray through film position (x, y) meets the surface, false for none)
            const auto place = [&](V3 p, V3 ngp, double alpha, const auto& normal_at) {
                const V3 l = to_light(p), v = unit(eye - p);
                if (dot(ngp, l) <= 0 || dot(ngp, v) <= 0) return;
                if (spot && dot(-1.0 * l, load(spot->direction)) < spot->cos_outer) return;
                // seen: the camera's ray towards p hits nothing before it
                const double dist = std::sqrt(dot(p - eye, p - eye));
                const double slack = 1e-4 * dist + 10 * double(scene.ray_offset);
                const float inf = std::numeric_limits<float>::infinity();
                if (first_hit(eye, unit(p - eye), 0.0f, inf) < dist - slack) return;
                // lit: nothing between p and the light
                const double to_lp = local ? std::sqrt(dot(lp - p, lp - p)) : std::numeric_limits<double>::infinity();
                const V3 o = p + (2 * double(scene.ray_offset)) * ngp;
                const float tmax = local ? float(to_lp * (1 - 1e-4)) : std::numeric_limits<float>::infinity();
                if (std::isfinite(first_hit(o, l, scene.ray_offset, tmax))) return;
                double fx, fy;
                if (!film(p, fx, fy)) return;
                // the spot's size: the normal's offset from the half-vector, a 2-vector in a frame
                // across h, as the film position moves (the camera ray meets the triangle's plane
                // there); the lobe's footprint is where that offset is within kAaSpotWidths lobe
                // widths: an ellipse J q <= r on the film, bounded by a box of half-widths
                // r sqrt((J^T J)^-1) on its diagonal
                const V3 h0 = half(p);
                const V3 t1 = unit(cross(h0, std::fabs(h0.x) < 0.9 ? V3{1, 0, 0} : V3{0, 1, 0})), t2 = cross(h0, t1);
                const auto offset = [&](double x, double y, double o2[2]) {
                    V3 q, n;
                    if (!normal_at(x, y, q, n)) return false;
                    // the normal against the half-vector, in the frame across h0
                    const V3 h = half(q);
                    const V3 r = n - h;
                    o2[0] = dot(r, t1);
                    o2[1] = dot(r, t2);
                    return true;
                };
                constexpr double kStep = 0.25;  // pixels: near the spot, where the offset is about linear
                double ax[2], bx[2], ay[2], by[2];
                if (!offset(fx + kStep, fy, ax) || !offset(fx - kStep, fy, bx) || !offset(fx, fy + kStep, ay) ||
                    !offset(fx, fy - kStep, by))
                    return;
                const double j00 = (ax[0] - bx[0]) / (2 * kStep), j10 = (ax[1] - bx[1]) / (2 * kStep);
                const double j01 = (ay[0] - by[0]) / (2 * kStep), j11 = (ay[1] - by[1]) / (2 * kStep);
                const double m00 = j00 * j00 + j10 * j10, m01 = j00 * j01 + j10 * j11, m11 = j01 * j01 + j11 * j11;
                const double mdet = m00 * m11 - m01 * m01;
                if (!(mdet > 0)) return;  // the normal does not turn across the film: no spot
                const double r = kAaSpotWidths * alpha;
                const double hx = r * std::sqrt(m11 / mdet), hy = r * std::sqrt(m00 / mdet);
                if (!(hx <= kAaSpotMaxHalf && hy <= kAaSpotMaxHalf)) return;  // not sub-pixel: the pattern sees it
                spots.push_back({fx - hx, fy - hy, fx + hx, fy + hy});
            };
            for (size_t t = t_begin; t < t_end; ++t) {
                const size_t material_index =
                    scene.tri_material != nullptr ? static_cast<size_t>(scene.tri_material[t]) : 0;
                if (material_index >= scene.materials.size()) continue;  // no material: nothing to place
                const Material& material = scene.materials[material_index];
                const double alpha = double(highlight_alpha(material)) + sun_spread;
                if (!(alpha < 0.5)) continue;  // no lobe, or one too broad to be sub-pixel anywhere near
                Tri triangle;
                for (int e = 0; e < 3; ++e) {
                    triangle.p[e] = load(tri + 9 * t + 3 * e);
                    const size_t vertex = static_cast<size_t>(scene.indices[3 * t + e]);
                    triangle.n[e] = scene.normals != nullptr ? load(scene.normals + 3 * vertex) : load(ng + 3 * t);
                }
                triangle.ng = load(ng + 3 * t);
                const V3 centre = (1.0 / 3) * (triangle.p[0] + triangle.p[1] + triangle.p[2]);
                // seen from the back: only a two-sided surface shades it, flipped
                if (dot(triangle.ng, eye - centre) < 0) {
                    if (!material.two_sided) continue;
                    triangle.ng = -1.0 * triangle.ng;
                    for (V3& n : triangle.n) n = -1.0 * n;
                }
                // the point where the shading normal is the half-vector h: for a fixed h, the
                // interpolated normal normalize(sum b_i n_i) is h where h = sum x_i n_i with
                // x_i >= 0 (h in the cone of the corners' normals), b = x / sum x; h depends on
                // the point only through the directions to the light and the camera, so a few
                // rounds of that solve converge
                double b[3] = {1.0 / 3, 1.0 / 3, 1.0 / 3};
                const V3 c12 = cross(triangle.n[1], triangle.n[2]), c20 = cross(triangle.n[2], triangle.n[0]),
                         c01 = cross(triangle.n[0], triangle.n[1]);
                const double det = dot(triangle.n[0], c12);
                const double spread =
                    std::max({1 - dot(triangle.n[0], triangle.n[1]), 1 - dot(triangle.n[1], triangle.n[2]),
                              1 - dot(triangle.n[2], triangle.n[0])});
                V3 p = centre;
                bool found = false;
                if (std::fabs(det) > 1e-12) {
                    for (int round = 0; round < 24; ++round) {
                        const V3 h = half(p);
                        const double x[3] = {dot(h, c12) / det, dot(h, c20) / det, dot(h, c01) / det};
                        const double sum = x[0] + x[1] + x[2];
                        if (!(sum > 0)) break;
                        double moved = 0;
                        for (int e = 0; e < 3; ++e) {
                            moved = std::max(moved, std::fabs(x[e] / sum - b[e]));
                            b[e] = x[e] / sum;
                        }
                        if (std::min({b[0], b[1], b[2]}) < -0.5) break;  // far outside: not this triangle's
                        p = b[0] * triangle.p[0] + b[1] * triangle.p[1] + b[2] * triangle.p[2];
                        if (moved < 1e-7) {
                            found = std::min({b[0], b[1], b[2]}) >= -1e-7;
                            break;
                        }
                    }
                } else if (spread < 1e-9) {
                    // flat: the mirror point, where the line from the camera's mirror image to the
                    // light meets the plane (for the sun: the camera ray whose reflection is the sun)
                    const V3 n = unit(triangle.n[0]);
                    const double he = dot(eye - triangle.p[0], n);
                    if (local) {
                        const double hl = dot(lp - triangle.p[0], n);
                        if (!(he > 0 && hl > 0)) continue;
                        p = (eye - (2 * he) * n) + (he / (he + hl)) * (lp - (eye - (2 * he) * n));
                    } else {
                        const V3 d = unit(sun) - (2 * dot(unit(sun), n)) * n;
                        const double dn = dot(d, n);
                        if (!(he > 0 && dn < 0)) continue;
                        p = eye + (-he / dn) * d;
                    }
                    barycentric(triangle, p, b);
                    found = std::min({b[0], b[1], b[2]}) >= -1e-7;
                }
                if (!found) continue;
                place(p, triangle.ng, alpha, [&](double x, double y, V3& q, V3& n) {
                    const V3 d = ray_dir(x, y);
                    const double dn = dot(d, triangle.ng);
                    if (dn == 0) return false;
                    q = eye + (dot(triangle.p[0] - eye, triangle.ng) / dn) * d;
                    double bq[3];
                    barycentric(triangle, q, bq);
                    n = shading_normal(triangle, bq);
                    return true;
                });
            }
            // the analytic spheres (render/accel/spheres.h), with the first part's triangles: the
            // point whose exact normal is the half-vector, by rounds n <- h(c + r n) (a contraction
            // of about r over the distances to the camera and the light)
            const SphereSet& balls = scene.tree->spheres;
            for (size_t k = 0; t_begin == 0 && k < balls.size(); ++k) {
                const int32_t prim = balls.prim_base + static_cast<int32_t>(k);
                const size_t material_index = static_cast<size_t>(scene.tri_material[prim]);
                if (material_index >= scene.materials.size()) continue;
                const double alpha = double(highlight_alpha(scene.materials[material_index])) + sun_spread;
                if (!(alpha < 0.5)) continue;
                const V3 centre{balls.centre_x[k], balls.centre_y[k], balls.centre_z[k]};
                const double radius = balls.radius[k];
                if (!(dot(eye - centre, eye - centre) > radius * radius)) continue;  // the camera inside it
                V3 n = unit(eye - centre);
                bool found = false;
                for (int round = 0; round < 64 && !found; ++round) {
                    const V3 next = half(centre + radius * n);
                    found = dot(next - n, next - n) < 1e-20;
                    n = next;
                }
                if (!found) continue;
                place(centre + radius * n, n, alpha, [&](double x, double y, V3& q, V3& nq) {
                    const V3 d = ray_dir(x, y), f = eye - centre;
                    const double a = dot(d, d), b = dot(f, d), disc = b * b - a * (dot(f, f) - radius * radius);
                    if (!(disc >= 0)) return false;
                    q = eye + ((-b - std::sqrt(disc)) / a) * d;
                    nq = unit(q - centre);
                    return true;
                });
            }
        }
    };
    // the triangles split among threads (the pieces are merged by pixel below: the same for any count)
    const size_t parts = std::clamp<size_t>(static_cast<size_t>(std::max(threads, 1)), 1,
                                            std::max<size_t>(1, triangle_count / 4096));
    std::vector<std::vector<Rect>> found(parts);
    std::vector<std::thread> workers;
    const auto bound = [&](size_t k) { return triangle_count * k / parts; };
    for (size_t k = 1; k < parts; ++k) workers.emplace_back([&, k] { search(bound(k), bound(k + 1), found[k]); });
    search(0, bound(1), found[0]);
    for (auto& w : workers) w.join();
    std::vector<Rect> spots;
    for (const auto& f : found) spots.insert(spots.end(), f.begin(), f.end());
    // each spot cut into the pixels it covers
    for (const Rect& q : spots) {
        const int px0 = std::max(0, static_cast<int>(std::floor(q.x0)));
        const int py0 = std::max(0, static_cast<int>(std::floor(q.y0)));
        const int px1 = std::min(camera.width - 1, static_cast<int>(std::floor(q.x1)));
        const int py1 = std::min(camera.height - 1, static_cast<int>(std::floor(q.y1)));
        for (int py = py0; py <= py1; ++py)
            for (int px = px0; px <= px1; ++px) {
                const double x0 = std::max(q.x0, double(px)) - px, x1 = std::min(q.x1, double(px + 1)) - px;
                const double y0 = std::max(q.y0, double(py)) - py, y1 = std::min(q.y1, double(py + 1)) - py;
                if (!(x1 > x0 && y1 > y0)) continue;
                pieces.push_back({py * camera.width + px, float(x0), float(y0), float(x1), float(y1)});
            }
    }
    // one piece a pixel: the bounding box of its pieces (a spot found on two triangles that
    // share the edge it lies on, or two spots in one pixel)
    std::sort(pieces.begin(), pieces.end(), [](const AaSpot& a, const AaSpot& b) { return a.pixel < b.pixel; });
    std::vector<AaSpot> merged;
    for (const AaSpot& q : pieces) {
        if (!merged.empty() && merged.back().pixel == q.pixel) {
            AaSpot& o = merged.back();
            o.x0 = std::min(o.x0, q.x0);
            o.y0 = std::min(o.y0, q.y0);
            o.x1 = std::max(o.x1, q.x1);
            o.y1 = std::max(o.y1, q.y1);
        } else {
            merged.push_back(q);
        }
    }
    return merged;
}

}  // namespace patina
