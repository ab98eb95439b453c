#version 450
// Radiosity hemicube, fragment stage: B of the visible surface point, from
// the atlas at its element-texel coordinate (the triangle's corner values,
// hemicube_shared.h, at the point's barycentric coordinates), times the
// pass's scale; back sides are black. The coordinate is clamped to the surface's
// tile so that no texel of a neighbouring tile is read.
//
// CELLS (gather, hemicube_desc.cells): the value of the element whose cell
// holds the point (the cell: the part of the surface within half a sample
// spacing, scene.h), piecewise constant, the basis the CPU reference's
// area-to-area form factors integrate. Bilinear filtering between samples,
// as the display shows them, drags the free floor beside a box towards the
// buried samples under it, and a box side's lowest elements, which see
// that strip at a grazing angle over half their view, were 7-11% dark
// (gather, a generic room: surface_error 0.024 -> 0.005). Otherwise
// bilinear between element samples (thesis 4.1): cross's redistribution
// was built on it, and with cells its furnace came out 1.05% off
// E / (1 - rho) and a 10,000-frame slide 1% past its power bound.
//
// OPEN_ONLY (cross's gather hemicubes, hemicube_desc.open_only): bilinear,
// but cells wherever one of the four samples is buried (under a box). The
// gather that lights a moving box saw the free floor strip at its foot
// dragged towards the buried samples under it: room 1's sliding box
// (tests/solvers/rooms.c) at rest had its -x side at 0.971 of the CPU
// reference, 0.988 with this. Cells everywhere in that gather did as well
// there, but moved cross's 0.999 furnace (nothing buried in it) from 0.80%
// to 2.8% off E / (1 - rho): a change of M's gather of some 1e-5 that 0.999
// multiplies; with nothing buried this is plain bilinear to the bit.
//
// Alpha is the distance from the hemicube's origin times pc.depth_scale
// (1 / scene diameter, so it lies in [0, 1]): the depth the cross method's
// reprojection reads from its back hemicubes (thesis 4.5.2, REPROJECT); a
// colour channel rather than the depth attachment, so that the same
// vkCmdResolveImage resolves it with the colour (0: nothing drawn).
#extension GL_GOOGLE_include_directive : require
#include "hemicube_shared.h"

// 1: bilinear from four texelFetch, where the device cannot filter RGBA32F.
layout(constant_id = 0) const uint SHADER_BILINEAR = 0u;
// 1: each element's cell value (above).
layout(constant_id = 1) const uint CELLS = 0u;
// 1: the hemicube's own surface black (hemicube_desc.own_black, below).
layout(constant_id = 2) const uint OWN_BLACK = 0u;
// 1: the cell value where a sample is buried (hemicube_desc.open_only, above).
layout(constant_id = 3) const uint OPEN_ONLY = 0u;

layout(push_constant) uniform Push { hemicube_push pc; };
layout(binding = HEMICUBE_BINDING_ATLAS) uniform sampler2D atlas;
layout(std430, binding = HEMICUBE_BINDING_TRIANGLES) readonly buffer Triangles {
    gpu_hemicube_triangle triangles[];
};
layout(std430, binding = HEMICUBE_BINDING_VERTICES) readonly buffer Vertices {
    gpu_hemicube_vertex vertices[];
};
layout(std430, binding = HEMICUBE_BINDING_INDICES) readonly buffer Indices { uint indices[]; };

layout(location = 0) flat in uvec2 ids; // surface, triangle
layout(location = 1) flat in vec3 origin;
layout(location = 2) in vec3 rel;
layout(location = 3) centroid in vec3 rel_c;
layout(location = 4) flat in uint own;

layout(location = 0) out vec4 color;

// Rounds to the nearest fp16 value (ties to even) in the shader, so that
// the colour attachment's float -> half conversion, whose rounding the API
// leaves to the implementation, has nothing left to round: lavapipe
// truncates, which biases every hemicube low by half an fp16 step on
// average and, through 1 / (1 - rho), the solution by far more. Exact for
// the fp16 normal range; B x scale <= 1 keeps clear of overflow.
vec4 round_to_half(vec4 v)
{
    uvec4 b = floatBitsToUint(v);
    b += 0xfffu + ((b >> 13u) & 1u);
    return uintBitsToFloat(b & ~0x1fffu);
}

vec3 position(uint i) { return vec3(vertices[i].x, vertices[i].y, vertices[i].z); }

void main()
{
    // The triangle's corners, and the point's barycentric coordinates in
    // it: what interpolating per-corner values would give, from vertices
    // the triangles share.
    uint k = ids.y;
    gpu_hemicube_triangle tri = triangles[k];
    vec3 p0 = position(indices[3u * k]);
    vec3 e1 = position(indices[3u * k + 1u]) - p0, e2 = position(indices[3u * k + 2u]) - p0;
    vec3 n = cross(e1, e2);
    vec3 d = rel_c - (p0 - origin);
    float nn = max(dot(n, n), 1e-37);
    float b1 = dot(cross(d, e2), n) / nn, b2 = dot(cross(e1, d), n) / nn;
    vec3 uvw = tri.uvw[0].xyz + b1 * (tri.uvw[1].xyz - tri.uvw[0].xyz) +
               b2 * (tri.uvw[2].xyz - tri.uvw[0].xyz);
    vec4 tile = tri.tile;
    // Surfaces emit and reflect on their front side only (scene.h). With
    // OWN_BLACK the hemicube's own surface is black too: it lies below the
    // horizon of a hemicube on its normal, but a normal-mapped receiver's
    // hemicube (gather, xrad.h normal_map) tilts, and its origin, a hair
    // in front, saw the surface around it from above (a tilted floor 1%
    // bright). Only gather's frames name their own surface in every case.
    bool own_surface = OWN_BLACK != 0u && ids.x == own;
    float front = tri.sign * dot(n, origin - p0) > 0.0 && !own_surface ? 1.0 : 0.0;
    // u is undefined at a triangle's apex (w = 0): any u of the apex row.
    vec2 uv = vec2(uvw.z > 0.0 ? uvw.x / uvw.z : tile.x, uvw.y);
    vec2 p = clamp(uv, tile.xy, tile.zw);
    vec3 b;
    vec2 size = vec2(textureSize(atlas, 0));
    ivec2 first = ivec2(floor(tile.xy * size)), last = ivec2(floor(tile.zw * size));
    // The element whose cell holds the point: its texel, the nearest sample.
    ivec2 cell = clamp(ivec2(floor(uv * size)), first, last);
    if (CELLS != 0u) {
        b = texelFetch(atlas, cell, 0).rgb;
    } else {
        vec2 t = p * size - 0.5;
        ivec2 i0 = clamp(ivec2(floor(t)), first, last);
        ivec2 i1 = min(i0 + 1, last);
        // OPEN_ONLY: where one of the four samples is buried (alpha 0,
        // atlas_scatter.comp), the value of the element whose cell holds
        // the point, as CELLS gives everywhere. The four alphas come with
        // the filter's own taps, or in one gather: four more fetches a
        // fragment made cross's gather hemicubes a quarter slower.
        float open = 1.0;
        if (SHADER_BILINEAR != 0u) {
            vec2 f = clamp(t - vec2(i0), 0.0, 1.0);
            vec4 b00 = texelFetch(atlas, i0, 0);
            vec4 b10 = texelFetch(atlas, ivec2(i1.x, i0.y), 0);
            vec4 b01 = texelFetch(atlas, ivec2(i0.x, i1.y), 0);
            vec4 b11 = texelFetch(atlas, i1, 0);
            b = mix(mix(b00.rgb, b10.rgb, f.x), mix(b01.rgb, b11.rgb, f.x), f.y);
            open = min(min(b00.a, b10.a), min(b01.a, b11.a));
        } else {
            b = texture(atlas, p).rgb;
            if (OPEN_ONLY != 0u) {
                // At a tile's last texel the footprint takes the next
                // tile's with weight 0; the cell value is then the same.
                vec4 a = textureGather(atlas, p, 3);
                open = min(min(a.x, a.y), min(a.z, a.w));
            }
        }
        if (OPEN_ONLY != 0u && open < 1.0)
            b = texelFetch(atlas, cell, 0).rgb;
    }
    color = round_to_half(vec4(front * pc.scale * b, length(rel) * pc.depth_scale));
}
