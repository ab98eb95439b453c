#version 450
// Select pass, step 2 (src/passes/select.c), one workgroup: the argmax of
// the surface powers (thesis 4.3.2 FINDSHOOTINGQUAD, done here on the GPU
// instead of by the depth-buffer trick and a readback), the convergence
// test (Algorithm 4.2 line 3), the dynamic shooter subdivision of thesis
// 4.3.3 (GENERATESHOOTINGPATCHES: the patch count follows the power being
// shot), the shooter table with each patch's mean unshot radiosity and its
// randomly rotated hemicube frame (thesis 4.2), Algorithm 4.2 line 7 (clear
// the chosen quad's unshot radiosity), and the indirect parameters that
// size the next passes; with a group, more surfaces in the same shot, and
// the sum of all unshot power for the stop (make_shooter, joins, main).
// Nothing is read by the host per shot.
#extension GL_GOOGLE_include_directive : require
#include "radiosity.h"
#include "select_shared.h"

layout(local_size_x = SELECT_GROUP) in;

layout(push_constant) uniform Push { select_push pc; };

layout(std430, binding = SELECT_BINDING_SURFACES) readonly buffer Surfaces { gpu_surface surfaces[]; };
layout(std430, binding = SELECT_BINDING_ELEMENTS) readonly buffer Elements { gpu_element elements[]; };
layout(std430, binding = SELECT_BINDING_BU) buffer Unshot { vec4 Bu[]; };
layout(std430, binding = SELECT_BINDING_POWER) readonly buffer Power { float power[]; };
layout(std430, binding = SELECT_BINDING_SHOOTERS) writeonly buffer Shooters { gpu_shooter shooters[]; };
layout(std430, binding = SELECT_BINDING_STATUS) buffer Status { select_status status; };
layout(std430, binding = SELECT_BINDING_SHOT) writeonly buffer Shot { vec4 shot[]; };

shared float s_power[SELECT_GROUP];
shared float s_sum[SELECT_GROUP];
shared uint s_index[SELECT_GROUP];
shared uint s_count[SELECT_GROUP];
shared uint s_surface, s_kx, s_ky, s_first_patch, s_joined;
shared uint s_group[SELECT_GROUP_MAX];

const float TWO_PI = 6.28318530717958647692;

// Wellons' lowbias32, as hemicube_rotation() in src/passes/hemicube_geometry.c.
uint lowbias32(uint x)
{
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

vec3 bilinear(gpu_surface sf, float s, float t)
{
    return mix(mix(sf.corner[0].xyz, sf.corner[1].xyz, s), mix(sf.corner[3].xyz, sf.corner[2].xyz, s), t);
}

// Parameter interval covered by samples [i0, i1] of n along one side: each
// sample stands for half a spacing either side, clipped to [0, 1]
// (src/scene/scene.h).
vec2 param_range(uint i0, uint i1, uint n)
{
    if (n < 2u)
        return vec2(0.0, 1.0); // a tiny triangle's one element (scene.h)
    float h = 1.0 / float(n - 1u);
    return vec2(max(0.0, (float(i0) - 0.5) * h), min(1.0, (float(i1) + 0.5) * h));
}

// Patches along s and t: the surface's fixed patches where it has them (the
// dynamic methods' surfaces of M, so that what their redistribution removes
// is what was shot, thesis 3.3.4), else about max_patches^2 x
// sqrt(power / max_power) in all, shaped to the surface's aspect, at most
// max_patches and the element count per side, at most max_shooters in all.
// Thesis 4.3.3 makes the count follow the power (every patch then carries
// about the power of one patch of the brightest shot); the square root
// keeps the later, dimmer shots finer, because a patch's visibility is its
// centre's and its receivers nearby see the error of that whatever the
// power: in the Cornell box the blocks' sides were 7-11% dark with the
// linear rule at 8, 3-5% with the square root at 12 (a shot costs its
// patches' hemicubes and one reconstruct over every element per patch;
// the default is 12 since the shots got cheaper, README "12 shooting
// patches a side"; linear below a share of 1% saved only 16% of the shots
// for 3 points of surface error). Cross's iterations after a
// frame's redistribution keep the linear rule (pc.linear_rule; its first
// solve's rounds do not, cross.c): they shoot the signed changes a
// pose brings, and with the square root what the solution held at one pose
// over 10,000 frames of a sliding box wandered past the bound (README
// "Shooter subdivision").
uvec2 patch_counts(gpu_surface sf, float power, float max_power)
{
    if (sf.patches_s != 0u && sf.patches_s * sf.patches_t <= pc.max_shooters)
        return uvec2(sf.patches_s, sf.patches_t);
    float lu = 0.5 * (distance(sf.corner[0].xyz, sf.corner[1].xyz) + distance(sf.corner[3].xyz, sf.corner[2].xyz));
    float lv = 0.5 * (distance(sf.corner[0].xyz, sf.corner[3].xyz) + distance(sf.corner[1].xyz, sf.corner[2].xyz));
    float share = clamp(power / max_power, 0.0, 1.0);
    float n = float(pc.max_patches * pc.max_patches) * (pc.linear_rule != 0u ? share : sqrt(share));
    float aspect = lu / lv;
    uint kx = uint(clamp(ceil(sqrt(n * aspect) - 1e-3), 1.0, float(min(sf.nu, pc.max_patches))));
    uint ky = uint(clamp(ceil(sqrt(n / aspect) - 1e-3), 1.0, float(min(sf.nv, pc.max_patches))));
    while (kx * ky > pc.max_shooters) {
        if (kx >= ky)
            kx--;
        else
            ky--;
    }
    return uvec2(kx, ky);
}

// The status words a shot's later passes and the host read: `count`
// shooters from `shot_surfaces` surfaces (0 when nothing is shot).
void write_counts(uint count, uint shot_surfaces)
{
    status.draw_index_count = pc.draw_index_count;
    status.draw_instance_count = count * pc.instances_per_hemicube;
    status.draw_first_index = 0u;
    status.draw_vertex_offset = 0u;
    status.draw_first_instance = 0u;
    status.dispatch_x = count > 0u ? (pc.element_count + pc.reconstruct_group - 1u) / pc.reconstruct_group : 0u;
    status.dispatch_y = 1u;
    status.dispatch_z = 1u;
    status.shooter_count = count;
    status.surface = count > 0u ? s_surface : SELECT_NONE;
    status.kx = count > 0u ? s_kx : 0u;
    status.ky = count > 0u ? s_ky : 0u;
    status.selections += count > 0u ? 1u : 0u;
    status.patches += count;
    status.surfaces += count > 0u ? shot_surfaces : 0u;
}

// A patch of surface s: kx x ky patches, number k along s then t; its
// hemicube is slot `slot` of the table, its unshot radiosity shot[first ..].
gpu_shooter make_shooter(uint s, uint kx, uint ky, uint k, uint slot, uint first)
{
    gpu_surface sf = surfaces[s];
    vec3 normal = sf.normal_area.xyz;
    vec3 u0 = sf.corner[1].xyz - sf.corner[0].xyz;
    u0 = normalize(u0 - normal * dot(u0, normal));
    vec3 v0 = cross(normal, u0);
    uint px = k % kx, py = k / kx;
    uint i0 = px * sf.nu / kx, i1 = (px + 1u) * sf.nu / kx - 1u;
    uint j0 = py * sf.nv / ky, j1 = (py + 1u) * sf.nv / ky - 1u;
    // A patch shoots from its open elements only: where it runs under a
    // block standing on the surface, its buried elements (no light
    // reaches them, gpu_element.flags; under a static cover: under a
    // moving one, cross gives an element negative light to shoot when
    // M arrives) would dilute the mean radiosity
    // that the receivers beside the block take (cornell-large's plinth
    // faces 0.79 of the CPU reference's), and its quad is cut to their
    // bounds so that the near-field form factor covers no buried part
    // where it can. Fixed patches keep their layout (their shots are
    // removed again as they were).
    vec3 sum = vec3(0.0);
    float area = 0.0;
    bool fixed_patch = sf.patches_s != 0u;
    uvec2 lo = uvec2(i1, j1), hi = uvec2(i0, j0);
    for (uint j = j0; j <= j1; j++) {
        for (uint i = i0; i <= i1; i++) {
            uint e = sf.first_element + j * sf.nu + i;
            if (!fixed_patch && (elements[e].flags & pc.buried_mask) != 0u)
                continue;
            float a = elements[e].pos_area.w;
            sum += Bu[e].rgb * a;
            area += a;
            lo = min(lo, uvec2(i, j));
            hi = max(hi, uvec2(i, j));
        }
    }
    if (area > 0.0 && !fixed_patch) {
        i0 = lo.x;
        j0 = lo.y;
        i1 = hi.x;
        j1 = hi.y;
    }
    vec2 rs = param_range(i0, i1, sf.nu), rt = param_range(j0, j1, sf.nv);
    // A fixed patch turns as patch_rotation() in hemicube_geometry.c
    // does, so that every pass shooting it sees the same texels. The
    // linear rule's shots (cross's iterations of signed changes) turn by
    // the patch's place on its surface, not by the shot's number (README
    // "Shooter subdivision" has what that did to 10,000 frames).
    uint key = sf.patches_s != 0u ? pc.seed * 0x9e3779b9u + 0x7f4a7c15u + sf.patch_first + k
               : pc.linear_rule != 0u
                   ? pc.seed * 0x9e3779b9u + lowbias32(((s * 17u + kx) * 17u + ky) * 257u + k)
                   : pc.seed * 0x9e3779b9u + s_first_patch + slot;
    float angle = float(lowbias32(key)) * (TWO_PI / 4294967296.0);
    gpu_shooter sh;
    vec3 centre = bilinear(sf, 0.5 * (rs.x + rs.y), 0.5 * (rt.x + rt.y));
    // A patch's visibility is its centre's: where the centre lies under
    // a block (a floor patch round a box's foot), its hemicube sees the
    // block's underside and the receivers all round take none of the
    // patch's light. It then shoots from the open element nearest the
    // centre. The centre lies between samples, and a box's edge may
    // pass between it and the nearest one: it counts as buried when any
    // of the samples around it is (inside a box without a bottom, its
    // hemicube showed only back faces, and conservation took all the
    // patch's light away: room 1's box sides at 0.86 of the CPU
    // reference).
    if (area > 0.0 && !fixed_patch) {
        vec2 c = vec2(0.5 * (rs.x + rs.y) * float(sf.nu - 1u),
                      0.5 * (rt.x + rt.y) * float(sf.nv - 1u));
        uvec2 lo_c = clamp(uvec2(floor(c)), uvec2(i0, j0), uvec2(i1, j1));
        uvec2 hi_c = clamp(uvec2(ceil(c)), uvec2(i0, j0), uvec2(i1, j1));
        bool centre_buried = false;
        for (uint j = lo_c.y; j <= hi_c.y; j++)
            for (uint i = lo_c.x; i <= hi_c.x; i++)
                centre_buried = centre_buried ||
                    (elements[sf.first_element + j * sf.nu + i].flags & pc.buried_mask) != 0u;
        uint ic = clamp(uint(c.x + 0.5), i0, i1), jc = clamp(uint(c.y + 0.5), j0, j1);
        if (centre_buried) {
            float best = 3.4e38;
            uvec2 at = uvec2(ic, jc);
            for (uint j = j0; j <= j1; j++) {
                for (uint i = i0; i <= i1; i++) {
                    gpu_element el = elements[sf.first_element + j * sf.nu + i];
                    vec3 off = el.pos_area.xyz - centre;
                    if ((el.flags & pc.buried_mask) == 0u && dot(off, off) < best) {
                        best = dot(off, off);
                        at = uvec2(i, j);
                    }
                }
            }
            vec2 cs = param_range(at.x, at.x, sf.nu), ct = param_range(at.y, at.y, sf.nv);
            centre = bilinear(sf, 0.5 * (cs.x + cs.y), 0.5 * (ct.x + ct.y));
        }
    }
    sh.pos_area = vec4(centre, area);
    sh.normal = vec4(normal, 0.0);
    sh.tangent = vec4(cos(angle) * u0 + sin(angle) * v0, 0.0);
    sh.radiosity = vec4(area > 0.0 ? sum / area : vec3(0.0), 0.0);
    sh.surface = s;
    sh.i0 = i0;
    sh.i1 = i1;
    sh.j0 = j0;
    sh.j1 = j1;
    sh.hemicube = slot;
    sh.group = 0u;
    sh.shot_first = first;
    return sh;
}

// Whether surface i joins the shot of surface s (power p) as one more
// shooter: a surface of one patch by the patch rule, of few elements, not
// of fixed patches, holding at least SELECT_GROUP_SHARE of p. In a mesh's
// thousands of faces the light spreads over many of about equal power,
// each a shot of one hemicube, and a solve stopped by the threshold on the
// largest surface left a few percent of all light unshot among them
// (wuson-room's walls 5% low): a group makes a shot of many faces cost as
// one surface's of as many patches.
bool joins(uint i, uint s, float p, float max_power)
{
    if (i == s || !(power[i] >= float(SELECT_GROUP_SHARE) * p) || !(power[i] > 0.0))
        return false;
    gpu_surface sf = surfaces[i];
    return sf.patches_s == 0u && sf.nu * sf.nv <= pc.group_elements &&
           patch_counts(sf, power[i], max_power) == uvec2(1u);
}

// What the reconstruct pass reads of element e's shot (`shot`): its unshot
// radiosity and its area, (0, 0, 0, -1) where it is buried and shoots
// nothing (main() says why the area travels with it).
vec4 shot_copy(uint e, bool buried)
{
    return buried ? vec4(0.0, 0.0, 0.0, -1.0) : vec4(Bu[e].rgb, elements[e].pos_area.w);
}

void main()
{
    uint t = gl_LocalInvocationIndex;

    // Argmax (ties go to the lowest surface index) and the sum.
    float best = -1.0, total = 0.0;
    uint best_index = SELECT_NONE;
    for (uint s = t; s < pc.surface_count; s += SELECT_GROUP) {
        float p = power[s];
        total += p;
        if (p > best) {
            best = p;
            best_index = s;
        }
    }
    s_power[t] = best;
    s_index[t] = best_index;
    s_sum[t] = total;
    barrier();
    for (uint w = SELECT_GROUP / 2u; w > 0u; w >>= 1) {
        if (t < w) {
            float o = s_power[t + w];
            uint oi = s_index[t + w];
            if (o > s_power[t] || (o == s_power[t] && oi < s_index[t])) {
                s_power[t] = o;
                s_index[t] = oi;
            }
            s_sum[t] += s_sum[t + w];
        }
        barrier();
    }

    if (t == 0u) {
        float p = max(s_power[0], 0.0);
        uint s = s_index[0];
        float max_power = max(status.max_power, p);
        float unshot = max(s_sum[0], 0.0);
        float max_unshot = max(status.max_unshot, unshot);
        status.power = p;
        status.max_power = max_power;
        status.unshot = unshot;
        status.max_unshot = max_unshot;
        // Algorithm 4.2 line 3, on the largest surface; and, where asked, on
        // all that is unshot (a solve stopped by the largest surface alone
        // leaves the sum over a mesh's many faces, each below it).
        bool largest_done = !(p > pc.threshold * max_power);
        bool all_done = pc.unshot_share <= 0.0 || !(unshot > pc.unshot_share * max_unshot);
        bool done = status.converged != 0u || s == SELECT_NONE || (largest_done && all_done);
        uvec2 k = done ? uvec2(0u) : patch_counts(surfaces[s], p, max_power);
        s_surface = done ? SELECT_NONE : s;
        s_kx = k.x;
        s_ky = k.y;
        s_first_patch = status.patches;
        if (done)
            status.converged = 1u;
    }
    barrier();
    if (s_surface == SELECT_NONE) {
        if (t == 0u)
            write_counts(0u, 0u);
        return;
    }

    // The group, in surface order: each invocation counts the surfaces that
    // join in its run of them, an exclusive scan gives where its own go, and
    // the first `room` are taken (the same for any run of the pass).
    uint room = min(pc.group_shooters, min(pc.max_shooters, SELECT_GROUP_MAX + s_kx * s_ky));
    room = room > s_kx * s_ky ? room - s_kx * s_ky : 0u;
    uint joined = 0u;
    if (room > 0u) {
        uint run = (pc.surface_count + SELECT_GROUP - 1u) / SELECT_GROUP;
        uint i0 = min(t * run, pc.surface_count), i1 = min(i0 + run, pc.surface_count);
        float p = s_power[0], max_power = status.max_power;
        uint n = 0u;
        for (uint i = i0; i < i1; i++)
            n += joins(i, s_surface, p, max_power) ? 1u : 0u;
        s_count[t] = n;
        barrier();
        if (t == 0u) {
            uint at = 0u;
            for (uint k = 0u; k < SELECT_GROUP; k++) {
                uint c = s_count[k];
                s_count[k] = at;
                at += c;
            }
            s_joined = min(at, room);
        }
        barrier();
        uint at = s_count[t];
        for (uint i = i0; i < i1 && at < s_joined; i++) {
            if (joins(i, s_surface, p, max_power))
                s_group[at++] = i;
        }
        barrier();
        joined = s_joined;
    }

    uint kx = s_kx, ky = s_ky, patches = kx * ky;
    if (t == 0u)
        write_counts(patches + joined, 1u + joined);
    for (uint k = t; k < patches; k += SELECT_GROUP)
        shooters[k] = make_shooter(s_surface, kx, ky, k, k, 0u);
    for (uint j = t; j < joined; j += SELECT_GROUP)
        shooters[patches + j] =
            make_shooter(s_group[j], 1u, 1u, 0u, patches + j, pc.shot_first + j * pc.group_elements);
    // Every patch has read its unshot radiosity before it is cleared; the
    // reconstruct pass's near field reads it element by element from `shot`
    // (buried elements shoot nothing, as above), with the element's area
    // in w, -1 where buried: its blocks then read `shot` alone, and with
    // the element's flags and area read from `elements` for every cell of
    // every near block, cornell-small's progressive solve took 12.8 s on
    // lavapipe against 11.8 s (farm-bench, medians of 3).
    memoryBarrierBuffer();
    barrier();
    gpu_surface sf = surfaces[s_surface];
    uint n = sf.nu * sf.nv;
    bool fixed_surface = sf.patches_s != 0u;
    for (uint k = t; k < n; k += SELECT_GROUP) {
        uint e = sf.first_element + k;
        shot[k] = shot_copy(e, !fixed_surface && (elements[e].flags & pc.buried_mask) != 0u);
        Bu[e] = vec4(0.0);
    }
    for (uint q = t; q < joined * pc.group_elements; q += SELECT_GROUP) {
        uint j = q / pc.group_elements, k = q % pc.group_elements;
        gpu_surface g = surfaces[s_group[j]];
        if (k >= g.nu * g.nv)
            continue;
        uint e = g.first_element + k;
        shot[pc.shot_first + q] = shot_copy(e, (elements[e].flags & pc.buried_mask) != 0u);
        Bu[e] = vec4(0.0);
    }
}
