#version 450
// Direct light pass (src/passes/direct.c): for each receiver point x (a
// gather frame: the centroid of an element's cell and its normal) the
// light it takes straight from the emitters, sum over lights l of
// E_l x F(x -> l) with visibility. Each light is split into blocks, more
// where it subtends more: each block's form factor is the exact
// point-to-polygon one (Lambert's formula, shooting_point_to_quad) clipped
// to x's half-space, its visibility one segment from the middle of its
// part in front of x's plane to x, tested against every surface through the
// hierarchy over them (SHOOTING_BVH). A dispatch takes a chunk of the
// lights (direct.c says how many) and adds to what the chunks before it
// wrote: lavapipe stops every loop of an invocation after 65,535
// iterations in all, and one invocation over 192 lights was cut short
// (direct light 46% low) without a word. A light thus
// takes no hemicube pixels: a small bright lamp covers a few texels of a
// 64 x 64 hemicube, and gather's elements read it 10-14% off by where
// those texels fell (a generic room: element p95 0.136).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#include "radiosity.h"
#include "direct_shared.h"
#include "hemicube.glsl"

layout(local_size_x = DIRECT_GROUP) in;

layout(push_constant) uniform Push { direct_push pc; };

layout(std430, binding = DIRECT_BINDING_SURFACES) readonly buffer Surfaces { gpu_surface surfaces[]; };
layout(std430, binding = DIRECT_BINDING_BVH_NODES) readonly buffer BvhNodes { gpu_bvh_node bvh_nodes[]; };
layout(std430, binding = DIRECT_BINDING_BVH_ITEMS) readonly buffer BvhItems { uint bvh_items[]; };
#define SHOOTING_BVH
#include "shooting.glsl"
layout(std430, binding = DIRECT_BINDING_MATERIALS) readonly buffer Materials { gpu_material materials[]; };
layout(std430, binding = DIRECT_BINDING_FRAMES) readonly buffer Frames { gpu_shooter frames[]; };
layout(std430, binding = DIRECT_BINDING_LIGHTS) readonly buffer Lights { uint lights[]; };
layout(std430, binding = DIRECT_BINDING_OUT) buffer Out { vec4 direct[]; };

// Whether the point p of a light is seen from x: the segment crosses no
// surface's quad (shooting_blocks: surfaces touching either end do not
// count).
bool seen(vec3 p, vec3 x)
{
    uint none[9];
    return !shooting_segment_hidden(p, x, none, SHOOTING_EVERY_SURFACE);
}

// The light block [s0, s1] x [t0, t1] of sf, seen from x (normal ne): its
// exact form factor where x sees its middle, else 0.
float block(gpu_surface sf, float s0, float s1, float t0, float t1, vec3 x, vec3 ne)
{
    vec3 q[4];
    q[0] = cell_bilinear(sf, s0, t0);
    q[1] = cell_bilinear(sf, s1, t0);
    q[2] = cell_bilinear(sf, s1, t1);
    q[3] = cell_bilinear(sf, s0, t1);
    float ff = shooting_point_to_quad(x, ne, q);
    uint none[9];
    return ff > 0.0 && !shooting_front_hidden(q, x, ne, none, SHOOTING_EVERY_SURFACE) ? ff : 0.0;
}

void main()
{
    if (gl_GlobalInvocationID.x >= pc.count)
        return;
    uint e = pc.first + gl_GlobalInvocationID.x;
    gpu_shooter f = frames[e];
    vec3 x = f.pos_area.xyz, ne = f.normal.xyz;
    vec3 sum = vec3(0.0);
    for (uint l = pc.light_first; l < pc.light_first + pc.light_count; l++) {
        uint k = lights[l];
        gpu_surface sf = surfaces[k];
        vec3 centre = 0.25 * (sf.corner[0].xyz + sf.corner[1].xyz + sf.corner[2].xyz +
                              sf.corner[3].xyz);
        // A light emits from its front side alone; x on its own surface
        // or in its plane takes nothing.
        if (k == f.surface || dot(x - centre, sf.normal_area.xyz) <= 0.0)
            continue;
        // Blocks per side: about four per the light's size over its
        // distance, so that a block subtends at most ~1/4 rad; 2 to 8.
        float d = length(x - centre), size = sqrt(sf.normal_area.w);
        uint n = uint(clamp(ceil(4.0 * size / max(d, 1e-6)), 2.0, float(DIRECT_MAX_BLOCKS)));
        float h = 1.0 / float(n);
        // A block whose corners and middle x sees alike is taken whole;
        // one they disagree on lies in a penumbra and is split into
        // DIRECT_SPLIT^2 parts, each seen from its middle: a point 9 cm
        // beside a table sees a sliver of 8.5% of the lamp past the
        // table's edge, which no block middle of 7 x 7 saw (the floor
        // there was 17% dark). The corners' visibility by rows, bits.
        uint below = 0u;
        for (uint i = 0u; i <= n; i++)
            below |= seen(cell_bilinear(sf, float(i) * h, 0.0), x) ? 1u << i : 0u;
        float ff = 0.0;
        for (uint bj = 0u; bj < n; bj++) {
            uint above = 0u;
            for (uint i = 0u; i <= n; i++)
                above |= seen(cell_bilinear(sf, float(i) * h, float(bj + 1u) * h), x) ? 1u << i
                                                                                      : 0u;
            for (uint bi = 0u; bi < n; bi++) {
                float s0 = float(bi) * h, t0 = float(bj) * h;
                float whole = block(sf, s0, s0 + h, t0, t0 + h, x, ne);
                uint corners = ((below >> bi) & 3u) | (((above >> bi) & 3u) << 2u);
                uint middle = whole > 0.0 ? 15u : 0u;
                if (corners == middle) {
                    ff += whole;
                    continue;
                }
                float g = h / float(DIRECT_SPLIT);
                for (uint sj = 0u; sj < DIRECT_SPLIT; sj++)
                    for (uint si = 0u; si < DIRECT_SPLIT; si++)
                        ff += block(sf, s0 + float(si) * g, s0 + float(si + 1u) * g,
                                    t0 + float(sj) * g, t0 + float(sj + 1u) * g, x, ne);
            }
            below = above;
        }
        sum += ff * materials[sf.material].emission.rgb;
    }
    float alarm = shooting_walk_steps >= DIRECT_STEP_ALARM ? 1.0 : 0.0;
    direct[e] = vec4(sum, alarm) + (pc.accumulate != 0u ? direct[e] : vec4(0.0));
}
