#version 450
// Cross redistribution bookkeeping (src/passes/cross_update.c; thesis
// Algorithm 4.4 lines 5 and 12-14, Algorithm 4.5 GATHERRADIOSITY), one
// mode per dispatch (spirv/cross_shared.h):
//  RESET     per element of M: B = E, Bu = 0 (line 5; M's emission
//            reaches C through the patches' totals, R_p(M, C), never
//            through progressive shots, src/solvers/cross.c);
//  INDIRECT_C per element: B - Bu - E on C, 0 on M: what the gather and
//            back hemicubes show (R_g(C, M) gathers shot radiosity of C
//            alone; M occludes but adds nothing, that is R_p(M, M); the
//            direct light is the lights' own hemicubes' part,
//            cross_reconstruct.comp); and the largest |component| of it
//            (peak), for the hemicubes' fp16 scale;
//  GATHERED  per element of M: B = E + rho * (the gathered sums of its
//            surface's coarse samples, interpolated bilinearly at the
//            element's sample), Bu = 0 (lines 12-14: the total is shot
//            next, so nothing is left unshot); an element in contact
//            B = E; a mesh group's other faces are GROUPS';
//  GROUPS    a workgroup per mesh group: its faces' elements B = E + rho *
//            the group's gather hemicube read from their own points
//            (gather_group), Bu = 0;
//  TOTAL     per patch of M: the area mean of B, what the patch shoots
//            (line 13: T updated with B_s).
// The shot radiosity B - Bu of M before the reset (line 4) is not needed:
// what M gave C last time is kept per element (cross_reconstruct.comp).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#include "radiosity.h"
#include "cross_shared.h"
#include "hemicube.glsl"
#include "cell.glsl"

layout(local_size_x = CROSS_UPDATE_GROUP) in;

layout(push_constant) uniform Push { cross_update_push pc; };

layout(std430, binding = CROSS_UPDATE_BINDING_SURFACES) readonly buffer Surfaces { gpu_surface surfaces[]; };
layout(std430, binding = CROSS_UPDATE_BINDING_ELEMENTS) readonly buffer Elements { gpu_element elements[]; };
layout(std430, binding = CROSS_UPDATE_BINDING_MATERIALS) readonly buffer Materials { gpu_material materials[]; };
layout(std430, binding = CROSS_UPDATE_BINDING_B) buffer Total { vec4 B[]; };
layout(std430, binding = CROSS_UPDATE_BINDING_BU) buffer Unshot { vec4 Bu[]; };
layout(std430, binding = CROSS_UPDATE_BINDING_PATCHES) readonly buffer Patches { cross_patch patches[]; };
layout(std430, binding = CROSS_UPDATE_BINDING_VALUES) buffer Values { cross_value values[]; };
layout(std430, binding = CROSS_UPDATE_BINDING_GATHERED) readonly buffer Gathered { vec4 gathered[]; };
layout(std430, binding = CROSS_UPDATE_BINDING_OUT) writeonly buffer Out { vec4 outv[]; };
layout(std430, binding = CROSS_UPDATE_BINDING_SURFACE_PATCH) readonly buffer SurfacePatch { uint surface_patch[]; };
layout(std430, binding = CROSS_UPDATE_BINDING_PEAK) buffer Peak { uint peak; };
layout(std430, binding = CROSS_UPDATE_BINDING_FRAMES) readonly buffer Frames { gpu_shooter frames[]; };
layout(binding = CROSS_UPDATE_BINDING_GATHER_HEMICUBES) uniform texture2DArray gather_hemicubes;

// Parameter of coarse sample c of n along a side: the centroid of its cell
// (the part of the side within half a spacing, clipped), where the gather
// hemicube of its patch sits (solvers/dynamic_patches.c).
float knot(uint c, uint n)
{
    if (n < 2u)
        return 0.5;
    float h = 1.0 / float(n - 1u);
    return 0.5 * (max(0.0, (float(c) - 0.5) * h) + min(1.0, (float(c) + 0.5) * h));
}

// The segment [knot(c0), knot(c0 + 1)] holding s (clamped to the outer
// knots) and s's fraction along it.
float bracket(float s, uint n, out uint c0)
{
    c0 = 0u;
    // One sample: no segment (its knots coincide, and 0 / 0 through
    // clamp() is undefined in SPIR-V); the caller reads no neighbour.
    if (n < 2u)
        return 0.0;
    while (c0 + 2u < n && s > knot(c0 + 1u, n))
        c0++;
    float a = knot(c0, n), b = knot(c0 + 1u, n);
    return clamp((s - a) / (b - a), 0.0, 1.0);
}

// GROUPS: each face of a mesh group (patch p, one workgroup) reads the
// group's gather hemicube from its own receiver point x (its cell's
// centroid, where the CPU reference and the shooting passes take an
// element's value) and normal n. Each texel the hemicube saw is a piece of
// surface at the distance its alpha holds (from the hemicube's origin o),
// facing along the normal its neighbours' points give (the nearer of the
// two on each axis, so that a depth edge does not tilt it). From x that
// piece spans the texel's solid angle from o times (dist / |q - x|)^2 x
// cos' / cos (its cosines towards x and o), in the direction from x to it,
// by n's cosine. A face lies up to half its group's size from o; read at o
// through the hemicube's irradiance vector, the 320-face ball's lowest
// faces, 30 cm above the ball's own shadow, came out up to 6% off the CPU
// reference (one hemicube a face: 0.7%; now 1%,
// tests/solvers/test_mesh_ball.c). Without cos' / cos the floor's
// foreshortening, 30 cm away, was 10% off for a point 3 cm further from
// it. What lies below o's horizon and above the face's (a face tilted by t
// from the group's axis sees (1 - cos t) / 2 of its cosine-weighted
// hemisphere there: the view factor of a tilted plane to the half-space
// above another) takes the horizon ring's mean radiosity. The texels are
// read a tile at a time into shared memory, once for all the group's
// faces.
// Texels a tile: each invocation loads 4 (fewer barriers, which lavapipe
// runs as a switch between its invocations' coroutines).
const uint TILE = 4u * CROSS_UPDATE_GROUP;
shared vec4 tile_q[TILE]; // xyz: the texel's point; w: 1 where it counts
shared vec4 tile_n[TILE]; // xyz: its piece's normal (0: none); w: cos towards o
shared vec3 tile_w[TILE]; // B x its solid angle from o x dist^2 (cosines apart)

// The world point a gather hemicube texel shows, and its alpha (<= 0:
// nothing drawn).
vec3 texel_point(uint layer, uint face, ivec2 t, vec3 o, mat3 frame, out float alpha)
{
    alpha = texelFetch(gather_hemicubes, ivec3(t, int(layer + face)), 0).a;
    vec3 d = hemicube_texel_direction(face, uvec2(t), pc.res);
    return o + (alpha * pc.diameter * inversesqrt(dot(d, d))) * (frame * d);
}

// Texel i of the group's hemicube (layer first: 5 p) into tile slot l.
void load_texel(uint i, uint l, uint layer, vec3 o, mat3 frame)
{
    uint res = pc.res;
    tile_q[l] = vec4(0.0);
    if (i >= 3u * res * res)
        return;
    uvec2 tu;
    uint face = hemicube_weighted_texel(i, res, tu);
    vec4 v = texelFetch(gather_hemicubes, ivec3(ivec2(tu), int(layer + face)), 0);
    if (v.a <= 0.0 || v.r + v.g + v.b <= 0.0)
        return; // nothing drawn, or black (M, back sides)
    ivec2 t = ivec2(tu);
    vec3 d = hemicube_texel_direction(face, tu, res);
    float r2 = dot(d, d), dist = v.a * pc.diameter;
    vec3 q = o + (dist * inversesqrt(r2)) * (frame * d);
    vec3 edge[2];
    for (int a = 0; a < 2; a++) {
        ivec2 step = a == 0 ? ivec2(1, 0) : ivec2(0, 1);
        ivec2 tp = t + step, tm = t - step;
        float ap = -1.0, am = -1.0;
        vec3 qp = q, qm = q;
        if (tp[a] < int(res))
            qp = texel_point(layer, face, tp, o, frame, ap);
        if (tm[a] >= 0)
            qm = texel_point(layer, face, tm, o, frame, am);
        float ep = ap > 0.0 ? abs(ap - v.a) : 1e30, em = am > 0.0 ? abs(am - v.a) : 1e30;
        edge[a] = ep <= em ? qp - q : q - qm;
    }
    vec3 nq = cross(edge[0], edge[1]);
    float nn = dot(nq, nq);
    nq = nn > 0.0 ? nq * inversesqrt(nn) : vec3(0.0);
    // Oriented towards o; its cosine there.
    float co = dot(nq, o - q) / dist;
    if (co < 0.0) {
        nq = -nq;
        co = -co;
    }
    float texel_area = 4.0 / float(res * res);
    tile_q[l] = vec4(q, 1.0);
    tile_n[l] = vec4(nq, max(co, 1e-6));
    tile_w[l] = v.rgb * (texel_area * dist * dist / (r2 * sqrt(r2)));
}

// Member element `index` of group p (its member surfaces' elements in
// order), 0xffffffff past them.
uint group_element(cross_patch p, uint index)
{
    for (uint m = 0u; m < p.member_count; m++) {
        gpu_surface ms = surfaces[surface_patch[p.member_first + m]];
        uint n = ms.nu * ms.nv;
        if (index < n)
            return ms.first_element + index;
        index -= n;
    }
    return 0xffffffffu;
}

void gather_group(uint p)
{
    cross_patch cp = patches[p];
    if (cp.member_count == 0u)
        return; // the whole workgroup: a block, not a group
    gpu_shooter f = frames[CROSS_FRAMES_GATHER * pc.patch_count + p];
    vec3 z = f.normal.xyz, tx = f.tangent.xyz, o = f.pos_area.xyz;
    mat3 frame = mat3(tx, cross(z, tx), z);
    uint layer = p * 5u, l = gl_LocalInvocationID.x, texels = 3u * pc.res * pc.res;
    // Batches of a workgroup's worth of elements, while any is left (the
    // same test for every invocation: the barriers below need all of them).
    for (uint base = 0u; group_element(cp, base) != 0xffffffffu; base += CROSS_UPDATE_GROUP) {
        uint k = group_element(cp, base + l);
        bool mine = k != 0xffffffffu && (elements[k].flags & GPU_ELEMENT_BURIED_ANY) == 0u;
        vec3 x = vec3(0.0), n = vec3(0.0, 0.0, 1.0), sum = vec3(0.0);
        if (mine) {
            gpu_surface sf = surfaces[elements[k].surface];
            uint ke = k - sf.first_element;
            x = cell_centroid(sf, ke % sf.nu, ke / sf.nu);
            // its receiver normal, its face's or its normal map's
            // (xrad.h normal_map), posed
            n = elements[k].normal.xyz;
        }
        for (uint t0 = 0u; t0 < texels; t0 += TILE) {
            barrier();
            for (uint j = l; j < TILE; j += CROSS_UPDATE_GROUP)
                load_texel(t0 + j, j, layer, o, frame);
            barrier();
            for (uint j = 0u; mine && j < TILE; j++) {
                vec4 qv = tile_q[j];
                if (qv.w == 0.0)
                    continue;
                vec3 w = qv.xyz - x;
                float w2 = dot(w, w), c = dot(n, w);
                if (c <= 0.0 || w2 <= 0.0)
                    continue;
                float iw = inversesqrt(w2);
                vec4 nq = tile_n[j];
                // cos' / cos: the same side seen from both, and not grazing from o
                float cx = -dot(nq.xyz, w) * iw;
                float ratio = dot(nq.xyz, nq.xyz) == 0.0 ? 1.0 : cx > 0.0 ? min(cx / nq.w, 4.0) : 0.0;
                sum += tile_w[j] * (c * iw * ratio / w2);
            }
        }
        if (mine) {
            float ct = clamp(dot(n, z), -1.0, 1.0);
            vec3 ring = gathered[pc.patch_count + p].rgb;
            vec3 g = sum * (pc.inv_scale / 3.14159265358979) + 0.5 * (1.0 - ct) * ring;
            gpu_material m = materials[surfaces[elements[k].surface].material];
            B[k] = vec4(m.emission.rgb + elements[k].albedo.rgb * max(g, vec3(0.0)), 0.0);
            Bu[k] = vec4(0.0);
        }
    }
}

// Area mean of B over the patch's elements: a block's, or every element
// of a group's member surfaces.
vec3 patch_mean(cross_patch p)
{
    vec3 sum = vec3(0.0);
    float area = 0.0;
    if (p.member_count != 0u) {
        for (uint m = 0u; m < p.member_count; m++) {
            gpu_surface ms = surfaces[surface_patch[p.member_first + m]];
            for (uint e = ms.first_element; e < ms.first_element + ms.nu * ms.nv; e++) {
                float a = elements[e].pos_area.w;
                sum += B[e].rgb * a;
                area += a;
            }
        }
        return area > 0.0 ? sum / area : vec3(0.0);
    }
    gpu_surface sf = surfaces[p.surface];
    for (uint j = p.j0; j <= p.j1; j++) {
        for (uint i = p.i0; i <= p.i1; i++) {
            uint e = sf.first_element + j * sf.nu + i;
            float a = elements[e].pos_area.w;
            sum += B[e].rgb * a;
            area += a;
        }
    }
    return area > 0.0 ? sum / area : vec3(0.0);
}

void main()
{
    if (pc.mode == CROSS_UPDATE_GROUPS) {
        gather_group(gl_WorkGroupID.x);
        return;
    }
    uint k = gl_GlobalInvocationID.x;
    if (k >= pc.count)
        return;
    if (pc.mode == CROSS_UPDATE_TOTAL) {
        values[k].total = vec4(patch_mean(patches[k]), 0.0);
        return;
    }
    gpu_surface sf = surfaces[elements[k].surface];
    gpu_material m = materials[sf.material];
    if (pc.mode == CROSS_UPDATE_INDIRECT_C) {
        vec3 v = sf.dynamic != 0u ? vec3(0.0) : B[k].rgb - Bu[k].rgb - m.emission.rgb;
        outv[k] = vec4(v, 0.0);
        vec3 a = abs(v);
        atomicMax(peak, floatBitsToUint(max(a.x, max(a.y, a.z))));
        return;
    }
    if (sf.dynamic == 0u)
        return;
    // An element of M in contact (a box's bottom on the floor) takes no
    // light: its surface's coarse samples gather above it, and their
    // interpolation gave a box bottom 0.1 mm above a floor 14% of the box's
    // mean (tests/solvers/test_dynamic.c, contact).
    bool buried = (elements[k].flags & GPU_ELEMENT_BURIED_ANY) != 0u;
    if (pc.mode == CROSS_UPDATE_RESET || buried) {
        B[k] = vec4(m.emission.rgb, 0.0);
        Bu[k] = vec4(0.0);
        return;
    }
    // GATHERED: the element's sample parameters (i / (nu - 1), j / (nv - 1),
    // scene.h) against its surface's grid of cx x cy coarse samples, whose
    // patches are row-major in (ci, cj) from surface_patch[surface] and
    // whose values were gathered at their cells' centroids (knot()):
    // linear between those points, constant beyond the outer ones.
    uint first = surface_patch[elements[k].surface];
    // A group's faces each read its gather hemicube from their own receiver
    // point and normal (GROUPS, gather_group() above). With one value for
    // all, a 80-face ball's side faces were 0.89 of the CPU
    // reference's; with the hemicube's irradiance vector dotted with each
    // face's normal and the horizon ring, 0.97-1.03, and the 320-face
    // ball's lowest faces 0.945-1.058 (parallax).
    if (patches[first].member_count != 0u)
        return; // GROUPS
    uint cx = patches[first].cx, cy = patches[first].cy;
    uint ke = k - sf.first_element;
    uint c0x, c0y;
    float fx = bracket(float(ke % sf.nu) / float(max(sf.nu, 2u) - 1u), cx, c0x);
    float fy = bracket(float(ke / sf.nu) / float(max(sf.nv, 2u) - 1u), cy, c0y);
    vec2 f = vec2(fx, fy);
    uint p00 = first + c0y * cx + c0x;
    uint dx = cx > 1u ? 1u : 0u, dy = cy > 1u ? cx : 0u; // a single sample: itself
    vec3 g = mix(mix(gathered[p00].rgb, gathered[p00 + dx].rgb, f.x),
                 mix(gathered[p00 + dy].rgb, gathered[p00 + dy + dx].rgb, f.x), f.y);
    B[k] = vec4(m.emission.rgb + elements[k].albedo.rgb * g, 0.0);
    Bu[k] = vec4(0.0);
}
