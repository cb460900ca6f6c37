#version 430
#ifdef ONE_PASS  // compute.py defines it where the driver has 64-bit atomics (NVIDIA's GL; not Mesa 22's llvmpipe)
#extension GL_ARB_gpu_shader_int64 : require
#extension GL_NV_shader_atomic_int64 : require
#endif
// Visibility pass in compute shaders (raster/compute.py): the visibility buffer of the draw
// (visibility.vert/.frag), the global number of the frontmost triangle + 1 per pixel, without the
// GPU's fixed-function rasterizer or its render targets.
//
// Triangles are rasterized in 2D homogeneous coordinates (Olano & Greer 1997): with a triangle's
// clip-space vertices v_k = (x, y, w) as the columns of M, the rows r_k of adj(M) are its edge
// functions, e_k(p) = r_k · (ndc_x, ndc_y, 1); a pixel centre p is covered where every
// e_k / det(M) >= 0, and there the clip depth z / w = Σ e_k z_k / det(M) is linear in p. No
// clipping is needed: a triangle that crosses the eye's plane covers only what lies in front of
// it. Coverage is watertight: a shared edge's row is computed from the same two vertices in both
// triangles, so its e_k are exact negatives (`precise` forbids fused multiply-adds that would
// round them differently), and a pixel centre on it lies in both (depth decides). The depth is
// OpenGL's (reversed Z: near / z; nothing in front of the near plane); the nearest hit has the
// largest depth, an exact tie keeps the larger triangle number. For a triangle wholly in front of
// the eye the depth is the plane through its projected vertices (z / w is linear in NDC), which
// keeps float precision on a triangle of a pixel, where Σ e_k z_k / det(M) would not.
//
// Triangles wholly in front of the eye whose bounding box holds at most SMALL_PIXELS pixel
// centres (almost all of a detailed mesh's) are rasterized by one invocation each, those of at
// most MEDIUM_PIXELS by MEDIUM_LANES invocations each (MEDIUM_PER_GROUP triangles per work group:
// a triangle of a few hundred pixels does not hold 256 invocations, most of them idle; on the H200
// 64 was the fastest of 32, 64, 128 and 256, or within 0.001 ms of it, on four of the five bench
// scenes, docs/results/gpu/issue10/stop45); both resolve
// visibility with atomics. With 64-bit
// atomics (ONE_PASS) a pixel's word is the depth's float bits above the number, and one atomicMax
// per covered pixel keeps the nearest hit, an exact tie the larger number: the visibility buffer
// of Nanite (Karis 2021), in one pass over the triangles. Without them, atomicMax on the depth's
// float bits, then a second pass over the triangles: atomicMax on the number where the depth won
// (the same result, bit for bit, at twice the rasterization). The others (large, or crossing the eye's
// plane) are listed with their edge functions and rasterized by tiles of TILE × TILE pixels: a
// work group reads the list in batches, keeps the triangles whose edge functions do not reject
// the whole tile, and each invocation keeps its pixels' nearest hit in registers, merged at the
// end with the atomics' and stored into the target image.
//
// Stages (uniform `stage`), in the order compute.py runs them:
//   0 CLEAR: per pixel: clear the atomics' depth and number, and the lists' lengths
//   1 SMALL_DEPTH: per triangle: a small one's depth (ONE_PASS: and number); the medium and the large listed
//   2 MEDIUM_GROUPS: one invocation: the work groups of stages 3 and 5 (an indirect dispatch)
//   3 MEDIUM_DEPTH: per medium triangle, MEDIUM_LANES invocations: its depth (ONE_PASS: and number)
//   4 SMALL_NUMBERS: per triangle: a small one's number where its depth won (not run with ONE_PASS)
//   5 MEDIUM_NUMBERS: per medium triangle: its number where its depth won (not run with ONE_PASS)
//   6 TILES: per tile: the large triangles, the merge, the target
layout(local_size_x = 256) in;

struct Listed {  // a listed triangle: its edge functions with the vertices' clip z, det(M), number
    vec4 e0, e1, e2;  // (r_k, z_k)
    vec4 rest;  // (det, triangle number + 1 as float bits, unused, unused)
};

layout(std430, binding = 0) readonly buffer Vertices { float vertices[]; };
layout(std430, binding = 1) readonly buffer Faces { uint faces[]; };
#ifdef ONE_PASS
layout(std430, binding = 2) buffer Nearest { uint64_t nearest[]; };  // (depth bits << 32) | number
#else
layout(std430, binding = 2) buffer Depth { uint depth[]; };
layout(std430, binding = 3) buffer Ids { uint ids[]; };
#endif
layout(std430, binding = 4) buffer Counts { uint listed; uint medium; uint medium_groups[3]; } counts;  // the groups at byte 8
layout(std430, binding = 5) buffer List { Listed listed[]; };
layout(std430, binding = 6) buffer Medium { uint medium[]; };
layout(r32ui, binding = 0) writeonly uniform uimage2D target;

uniform mat4 world_to_clip;
uniform vec3 origin;
uniform ivec2 size;
uniform uint triangles;
uniform int stage;

const int CLEAR = 0, SMALL_DEPTH = 1, MEDIUM_GROUPS = 2, MEDIUM_DEPTH = 3, SMALL_NUMBERS = 4, MEDIUM_NUMBERS = 5, TILES = 6;
const int SMALL_PIXELS = 64;
const int MEDIUM_PIXELS = 4096;
const uint MEDIUM_LANES = 64u;  // invocations per medium triangle
const uint MEDIUM_PER_GROUP = 256u / MEDIUM_LANES;  // medium triangles per work group
const int TILE = 32;  // pixels per tile side: 256 invocations, 4 pixels each
const int BATCH = 256;
const uint MAX_GROUPS = 65535u;

shared Listed batch[BATCH];
shared uint kept[BATCH];
shared uint kept_count;

vec4 clip_of(uint v) {
    precise vec3 p = vec3(vertices[3u * v], vertices[3u * v + 1u], vertices[3u * v + 2u]) - origin;
    precise vec4 c = world_to_clip * vec4(p, 1.0);
    return c;
}

vec3 cross_exact(vec3 a, vec3 b) {
    precise vec3 c = vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
    return c;
}

float edge(vec3 r, float px, float py) {
    precise float e = r.x * px + r.y * py + r.z;
    return e;
}

float pixel_x(int i) { return (2.0 * float(i) + 1.0) / float(size.x) - 1.0; }
float pixel_y(int j) { return (2.0 * float(j) + 1.0) / float(size.y) - 1.0; }

// the edge functions of a triangle at pixel centre (px, py); covered: none has det's opposite sign
bool covers(vec4 a, vec4 b, vec4 c, float det, float px, float py, out vec3 e) {
    e = vec3(edge(a.xyz, px, py), edge(b.xyz, px, py), edge(c.xyz, px, py));
    float s = sign(det);
    return !(e.x * s < 0.0 || e.y * s < 0.0 || e.z * s < 0.0);
}

// the depth of a listed triangle at pixel centre (px, py) where it covers it between the clip
// planes, else -1 (large, or crossing the eye's plane: the edge functions' depth, whose
// cancellation is small on a large triangle)
float depth_at(vec4 a, vec4 b, vec4 c, float det, float px, float py) {
    vec3 e;
    if (!covers(a, b, c, det, px, py, e)) return -1.0;
    precise float d = (e.x * a.w + e.y * b.w + e.z * c.w) / det;
    return (d >= 0.0 && d <= 1.0) ? d : -1.0;
}

struct Setup {  // one triangle in the frame
    vec4 a, b, c;  // edge functions with the vertices' clip z (coverage)
    float det;
    vec4 plane;  // (d0, dd/dx, dd/dy, unused): its depth as a plane in NDC from vertex 0 (when front)
    vec2 origin;  // vertex 0 in NDC
    ivec2 lo, hi;  // pixel centres of the bounding box (when front)
    bool front;  // every vertex in front of the eye
    bool drawn;  // could cover a pixel centre
};

Setup setup(uint t) {
    Setup q;
    uvec3 f = uvec3(faces[3u * t], faces[3u * t + 1u], faces[3u * t + 2u]);
    vec4 c0 = clip_of(f.x), c1 = clip_of(f.y), c2 = clip_of(f.z);
    q.drawn = !(c0.w <= 0.0 && c1.w <= 0.0 && c2.w <= 0.0);  // not wholly behind the eye
    q.front = c0.w > 0.0 && c1.w > 0.0 && c2.w > 0.0;
    q.lo = ivec2(0);
    q.hi = size - 1;
    if (q.front) {
        vec2 half_size = vec2(size) * 0.5;
        vec2 p0 = (c0.xy / c0.w + 1.0) * half_size - 0.5;
        vec2 p1 = (c1.xy / c1.w + 1.0) * half_size - 0.5;
        vec2 p2 = (c2.xy / c2.w + 1.0) * half_size - 0.5;
        vec2 bmin = clamp(min(min(p0, p1), p2), vec2(-2.0), vec2(size) + 1.0);
        vec2 bmax = clamp(max(max(p0, p1), p2), vec2(-2.0), vec2(size) + 1.0);
        q.lo = max(ivec2(ceil(bmin - 1e-3)), ivec2(0));
        q.hi = min(ivec2(floor(bmax + 1e-3)), size - 1);
        q.drawn = q.drawn && all(lessThanEqual(q.lo, q.hi));  // else between pixel centres, or off screen
        // the depth z / w as the plane through the projected vertices: the edge functions' form,
        // Σ e_k z_k / det, cancels to ~1e-2 relative error on a triangle of a pixel, which would put
        // the far side of a thin part in front; differences of the projected vertices do not
        vec2 n0 = c0.xy / c0.w, e1 = c1.xy / c1.w - n0, e2 = c2.xy / c2.w - n0;
        float d0 = c0.z / c0.w, f1 = c1.z / c1.w - d0, f2 = c2.z / c2.w - d0;
        float area = e1.x * e2.y - e1.y * e2.x;
        q.origin = n0;
        q.plane = area != 0.0 ? vec4(d0, (f1 * e2.y - f2 * e1.y) / area, (e1.x * f2 - e2.x * f1) / area, 0.0)
                              : vec4(d0, 0.0, 0.0, 0.0);
    }
    vec3 v0 = c0.xyw, v1 = c1.xyw, v2 = c2.xyw;
    q.a = vec4(cross_exact(v1, v2), c0.z);
    q.b = vec4(cross_exact(v2, v0), c1.z);
    q.c = vec4(cross_exact(v0, v1), c2.z);
    precise float det = v0.x * q.a.x + v0.y * q.a.y + v0.z * q.a.z;
    q.det = det;
    q.drawn = q.drawn && det != 0.0;
    return q;
}

int pixels_of(Setup q) {
    ivec2 extent = q.hi - q.lo + 1;
    return q.front ? extent.x * extent.y : 1 << 30;
}

// the atomic write of one pixel of a triangle in front of the eye: its depth (first pass) or its
// number where its depth won
void write_pixel(Setup q, uint t, int i, int j, bool numbers) {
    float px = pixel_x(i), py = pixel_y(j);
    vec3 e;
    if (!covers(q.a, q.b, q.c, q.det, px, py, e)) return;
    float d = q.plane.x + q.plane.y * (px - q.origin.x) + q.plane.z * (py - q.origin.y);
    if (d < 0.0 || d > 1.0) return;
    uint key = floatBitsToUint(d), pixel = uint(j * size.x + i);
#ifdef ONE_PASS
    atomicMax(nearest[pixel], packUint2x32(uvec2(t + 1u, key)));  // x: the low 32 bits
#else
    if (!numbers) atomicMax(depth[pixel], key);
    else if (depth[pixel] == key) atomicMax(ids[pixel], t + 1u);
#endif
}

// stages SMALL_DEPTH and SMALL_NUMBERS: a small triangle by its own invocation; the first pass lists the others
void small_triangle(uint t, bool numbers) {
    Setup q = setup(t);
    if (!q.drawn) return;
    int pixels = pixels_of(q);
    if (pixels > SMALL_PIXELS) {
        if (numbers) return;
        if (pixels <= MEDIUM_PIXELS) medium[atomicAdd(counts.medium, 1u)] = t;
        else listed[atomicAdd(counts.listed, 1u)] = Listed(q.a, q.b, q.c, vec4(q.det, uintBitsToFloat(t + 1u), 0.0, 0.0));
        return;
    }
    for (int j = q.lo.y; j <= q.hi.y; ++j)
        for (int i = q.lo.x; i <= q.hi.x; ++i) write_pixel(q, t, i, j, numbers);
}

// stages MEDIUM_DEPTH and MEDIUM_NUMBERS: a medium triangle by MEDIUM_LANES invocations (`lane` is
// one of them) striding over its box
void medium_triangle(uint k, uint lane, bool numbers) {
    uint t = medium[k];
    Setup q = setup(t);
    int width = q.hi.x - q.lo.x + 1, pixels = pixels_of(q);
    for (int p = int(lane); p < pixels; p += int(MEDIUM_LANES))
        write_pixel(q, t, q.lo.x + p % width, q.lo.y + p / width, numbers);
}

// could the triangle cover a pixel centre of [lo, hi] (NDC)? No edge function negative at every corner
bool touches(Listed l, vec2 lo, vec2 hi) {
    float s = sign(l.rest.x);
    vec3 r[3] = vec3[3](l.e0.xyz, l.e1.xyz, l.e2.xyz);
    for (int k = 0; k < 3; ++k) {
        vec3 q = r[k] * s;
        if (max(q.x * lo.x, q.x * hi.x) + max(q.y * lo.y, q.y * hi.y) + q.z < 0.0) return false;
    }
    return true;
}

void tile() {
    ivec2 first = ivec2(gl_WorkGroupID.xy) * TILE, last = min(first + TILE - 1, size - 1);
    // a small margin: the corner test in floats must not reject a triangle the exact test keeps
    vec2 margin = 1e-4 + 2.0 / vec2(size) * 1e-3;
    vec2 lo = vec2(pixel_x(first.x), pixel_y(first.y)) - margin, hi = vec2(pixel_x(last.x), pixel_y(last.y)) + margin;
    uint local = gl_LocalInvocationID.x;
    ivec2 mine = first + ivec2(int(local) % TILE, int(local) / TILE);  // rows mine.y + 8 k, k < 4
    float best[4] = float[4](-1.0, -1.0, -1.0, -1.0);
    uint best_id[4] = uint[4](0u, 0u, 0u, 0u);
    uint count = counts.listed;
    for (uint start = 0u; start < count; start += uint(BATCH)) {
        if (local == 0u) kept_count = 0u;
        barrier();
        if (start + local < count) {
            Listed l = listed[start + local];
            if (touches(l, lo, hi)) {
                uint k = atomicAdd(kept_count, 1u);
                batch[k] = l;
            }
        }
        barrier();
        uint n = kept_count;
        for (uint k = 0u; k < n; ++k) {
            Listed l = batch[k];
            uint id = floatBitsToUint(l.rest.y);
            for (int row = 0; row < 4; ++row) {
                ivec2 p = mine + ivec2(0, 8 * row);
                if (p.x > last.x || p.y > last.y) continue;
                float d = depth_at(l.e0, l.e1, l.e2, l.rest.x, pixel_x(p.x), pixel_y(p.y));
                if (d > best[row] || (d == best[row] && d >= 0.0 && id > best_id[row])) {
                    best[row] = d;
                    best_id[row] = id;
                }
            }
        }
        barrier();
    }
    for (int row = 0; row < 4; ++row) {
        ivec2 p = mine + ivec2(0, 8 * row);
        if (p.x > last.x || p.y > last.y) continue;
        uint pixel = uint(p.y * size.x + p.x);
#ifdef ONE_PASS
        uvec2 word = unpackUint2x32(nearest[pixel]);
        float own = uintBitsToFloat(word.y);
        uint id = word.x;
#else
        float own = uintBitsToFloat(depth[pixel]);
        uint id = ids[pixel];
#endif
        if (best_id[row] != 0u && (id == 0u || best[row] > own || (best[row] == own && best_id[row] > id))) id = best_id[row];
        imageStore(target, p, uvec4(id));
    }
}

void main() {
    if (stage == TILES) {
        tile();
        return;
    }
    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uint n = group * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
    if (stage == CLEAR) {
        if (n < uint(size.x * size.y)) {  // infinitely far (reversed Z), the background
#ifdef ONE_PASS
            nearest[n] = uint64_t(0);
#else
            depth[n] = 0u;
            ids[n] = 0u;
#endif
        }
        if (n == 0u) counts.listed = counts.medium = 0u;
    } else if (stage == MEDIUM_GROUPS) {
        uint groups = (counts.medium + MEDIUM_PER_GROUP - 1u) / MEDIUM_PER_GROUP;
        if (n == 0u) counts.medium_groups = uint[3](min(groups, MAX_GROUPS), (groups + MAX_GROUPS - 1u) / MAX_GROUPS, 1u);
    } else if (stage == MEDIUM_DEPTH || stage == MEDIUM_NUMBERS) {
        uint k = group * MEDIUM_PER_GROUP + gl_LocalInvocationID.x / MEDIUM_LANES;
        if (k < counts.medium) medium_triangle(k, gl_LocalInvocationID.x % MEDIUM_LANES, stage == MEDIUM_NUMBERS);
    } else if (n < triangles) {  // SMALL_DEPTH, SMALL_NUMBERS
        small_triangle(n, stage == SMALL_NUMBERS);
    }
}
