// What a receiving element computes from one shooting patch, shared by the
// passes that shoot (reconstruct.comp, cross_reconstruct.comp,
// incremental_reconstruct.comp): its receiver point, the visibility test in
// the shooter's ID hemicube and the form factor. Include after radiosity.h,
// hemicube.glsl and the pass's `surfaces` buffer (gpu_surface). The reasons
// for each choice are in reconstruct.comp.
#ifndef XRAD_SHOOTING_GLSL
#define XRAD_SHOOTING_GLSL

#include "cell.glsl"

// The occluder a hemicube texel names (surface index i) as the hemicube
// was drawn: `old` asks for the pose before the current one, which only a
// pass that keeps it (incremental_reconstruct.comp) defines before
// including this file.
#ifndef SHOOTING_OCCLUDER
#define SHOOTING_OCCLUDER(i, old) surfaces[i]
#endif

// Whether surface i is absent from what a pass's hemicubes drew, so that
// the walk over every surface (shooting_bvh_hidden) must not count it as
// an occluder either: cross's progressive iterations draw C alone
// (reconstruct.comp defines it).
#ifndef SHOOTING_UNDRAWN
#define SHOOTING_UNDRAWN(i) false
#endif

const float SHOOTING_PI = 3.14159265358979323846;

// Where the line from o through x meets surface `sf` (a planar convex
// quad), as a multiple s of x - o (x at 1); -1 where it misses it.
float shooting_hit(gpu_surface sf, vec3 o, vec3 x)
{
    vec3 n = sf.normal_area.xyz, dir = x - o;
    float along = dot(n, dir);
    if (along == 0.0)
        return -1.0;
    float s = dot(n, sf.corner[0].xyz - o) / along;
    vec3 p = o + s * dir;
    for (int k = 0; k < 4; k++) {
        vec3 a = sf.corner[k].xyz, b = sf.corner[(k + 1) & 3].xyz;
        if (dot(cross(b - a, p - a), n) < 0.0)
            return -1.0;
    }
    return s;
}

// Whether the segment from o to x crosses surface `sf` before x: within
// (1e-4, 1 - 1e-5) of its length, so that the shooter's own plane and a
// surface touching or coplanar with x's do not count.
bool shooting_blocks(gpu_surface sf, vec3 o, vec3 x)
{
    float s = shooting_hit(sf, o, x);
    return s > 1e-4 && s < 1.0 - 1e-5;
}

// A mesh face may be smaller than a texel: a 320-face ball seen from a
// ceiling light at 64 texels a side drew many faces in no texel at all, or
// only where its neighbours' IDs won, and progressive's ball came out at
// 0.76 of the CPU reference's on its worst face (0.94 at 256 texels). So a
// mesh face whose ID the texels do not show is visible where the texel
// towards x shows nothing nearer than x: the distance drawn there (the ID
// hemicube's second channel) at least x's, less the slack of a texel's
// offset across a surface seen at its angle (three texels: at 1.5 the
// 320-face ball's worst face was 0.947, at 3 0.973, at 6 no better). Quads
// keep the ID rule alone.
bool shooting_depth_visible(uvec2 texel, vec3 o, vec3 x, uint res)
{
    if (texel.x == 0u)
        return true;
    vec3 d = x - o;
    float r = length(d);
    float c = abs(dot(SHOOTING_OCCLUDER(texel.x - 1u, false).normal_area.xyz, d)) / max(r, 1e-30);
    float tangent = min(sqrt(max(1.0 - c * c, 0.0)) / max(c, 1e-3), 8.0);
    return uintBitsToFloat(texel.y) >= r * (1.0 - 3.0 / float(res) * tangent - 1e-3);
}

// Whether the receiver point x (of the surface whose ID is `id`, surface +
// 1) is visible in the ID hemicube `hemicube` of `ids` drawn from o, x lying
// in the local direction `local` of the hemicube's frame.
//
// Without `neighbours`, visible where the texel x projects to shows the
// receiver's surface. With them, x's ID must show in one of the 3 x 3
// texels around (thesis 4.3.3: no holes from sampling), and those texels
// are also the candidate occluders: x is hidden where the segment o -> x
// crosses a surface one of them shows (shooting_blocks, against the
// surface's own quad). Trusting the candidates alone (visible unless one
// blocks) let light through walls where the wall crossed was not among
// them (a 1e6 W/m^2 room lit its dim neighbour). The nearest-texel check
// alone (x's ID in one of the 8 texels) let light through every
// occluder's silhouette, a texel wide: the contact shadows at the foot of
// the Cornell box's blocks were lost (floor elements there 1.7-4.3 times
// the CPU reference's) and floor under the blocks was lit. The Barsi and
// Wallner seeds compare depths for the same reason; here the occluder's
// own quad decides, which also keeps the shadow's edge where the geometry
// puts it instead of a texel off.
//
// `occluders` false: thesis 4.3.3's nearest-texel check alone (x's ID in
// its texel or one of the 8 around it). Cross's redistribution keeps it
// for what M sees and lights (its shadows were tuned against it; issue 14
// left them as they were), but not for the direct light M hides from C,
// which must match the shots that gave it (cross_reconstruct.comp,
// blocked_direct).
// Incremental uses the occluder test in its redistribution and in the
// progressive shots that redistribution removes again, the two alike: its
// old hemicubes show M where the old pose had it, so `old` looks the
// occluder up there (SHOOTING_OCCLUDER). With the plain check in one and
// the occluder test in the other, or the new pose's quads for the old
// hemicubes, what a frame removed differed from what was shot and 10,000
// frames of a sliding box ran to -38 or +1.9 times the power bound.
#ifdef SHOOTING_BVH
bool shooting_bvh_hidden(vec3 c, vec3 x, bool quads_only);
// Set by the includer where the occluder test may take a mesh's faces
// from the hierarchy (shooting_visible_at): the shots no redistribution
// removes again (reconstruct.comp), so that none sees differently from
// the pass that removes it.
bool shooting_exact_mesh = false;
#endif

bool shooting_visible_at(utexture2DArray ids, uint res, bool neighbours, vec3 local,
                         uint hemicube, uint id, vec3 o, vec3 x, bool occluders, bool old)
{
    uvec2 px;
    int face = hemicube_lookup(local, res, px);
    int layer = int(hemicube) * HEMICUBE_FACES + face;
    bool mesh = surfaces[id - 1u].mesh != 0u;
    if (!neighbours) {
        uvec2 texel = texelFetch(ids, ivec3(px, layer), 0).rg;
        return texel.x == id || (mesh && shooting_depth_visible(texel, o, x, res));
    }
    int last = int(res) - 1;
    bool found = false, beyond = false, mesh_shown = mesh;
    for (int dy = -1; dy <= 1; dy++) {
        for (int dx = -1; dx <= 1; dx++) {
            ivec2 q = clamp(ivec2(px) + ivec2(dx, dy), ivec2(0), ivec2(last));
            uint shown = texelFetch(ids, ivec3(q, layer), 0).r;
            if (shown == id) {
                if (!occluders)
                    return true;
                found = true;
            } else if (occluders && shown != 0u) {
                float s = shooting_hit(SHOOTING_OCCLUDER(shown - 1u, old), o, x);
                if (s > 1e-4 && s < 1.0 - 1e-5)
                    return false;
                beyond = beyond || s >= 1.0 - 1e-5;
                mesh_shown = mesh_shown || surfaces[shown - 1u].mesh != 0u;
            }
        }
    }
#ifdef SHOOTING_BVH
    // Mesh faces smaller than a texel: the face a texel shows is the one at
    // its centre, and the face that the segment to x crosses may be one
    // beside it that no texel shows. Found among the texels, x behind a
    // mesh's silhouette took light through it (wuson-room's floor round
    // the wuson 3% bright, the walls 2% dark, progressive at
    // density_scale 0.4). So where the texels show a mesh face, or x lies
    // on one, the segment decides, through every surface's hierarchy.
    if (occluders && shooting_exact_mesh && !old && mesh_shown)
        return !shooting_bvh_hidden(o, x, false);
#endif
    if (!found && mesh)
        return shooting_depth_visible(texelFetch(ids, ivec3(px, layer), 0).rg, o, x, res);
    if (found || !occluders)
        return found;
    // x's surface nowhere among the texels: it may be seen so nearly
    // edge-on that the hemicube drew it in no texel (a sliver thinner than
    // a texel, which no neighbour check finds), or hidden. Where its
    // projected thickness, sqrt(area) x cos / distance, is under a couple
    // of texels, it is visible unless a candidate occluder blocks the
    // segment (tested above): the side of a cabinet, in the plane of a
    // small ceiling light's edge, took 0.84 of that light at 64 texels a
    // side. Elsewhere the surface is drawn where it is seen, and its
    // absence means it is hidden. Only where a surface the texels show
    // lies on the line beyond x, as behind a sliver in view: where they
    // show only surfaces that the segment misses, the one that hides x may
    // be one no texel shows (a room lit at 1e6 W/m^2 lit its dim neighbour
    // through a wall hidden behind a box). Not within two texels of the
    // shooter's horizon (local.z, the shooter's cosine, times the
    // distance): there a surface resting on the shooter's plane lies too,
    // such as a box's bottom 0.1 mm above the floor, which the contact rule
    // keeps dark and no occluder hides from a floor patch beside it.
    gpu_surface rs = SHOOTING_OCCLUDER(id - 1u, old);
    vec3 d = x - o;
    float r2 = dot(d, d);
    float texels = sqrt(rs.normal_area.w) * abs(dot(d, rs.normal_area.xyz)) / r2 * 0.5 * float(res);
    return beyond && texels < 2.0 && local.z > 4.0 / float(res) * sqrt(r2);
}

// shooting_visible_at with hemicubes of the current pose.
bool shooting_visible(utexture2DArray ids, uint res, bool neighbours, vec3 local, uint hemicube,
                      uint id, vec3 o, vec3 x, bool occluders)
{
    return shooting_visible_at(ids, res, neighbours, local, hemicube, id, o, x, occluders, false);
}

// The surfaces (ID - 1) other than the receiver's (`id`) that the 3 x 3
// texels around the local direction `local` show in hemicube `hemicube`:
// the candidate occluders between the shooter and the receiver, at most 9
// distinct ones in cand[0, count).
uint shooting_candidates(utexture2DArray ids, uint res, vec3 local, uint hemicube, uint id,
                         out uint cand[9])
{
    uvec2 px;
    int face = hemicube_lookup(local, res, px);
    int layer = int(hemicube) * HEMICUBE_FACES + face;
    int last = int(res) - 1;
    uint count = 0u;
    for (int dy = -1; dy <= 1; dy++) {
        for (int dx = -1; dx <= 1; dx++) {
            ivec2 q = clamp(ivec2(px) + ivec2(dx, dy), ivec2(0), ivec2(last));
            uint shown = texelFetch(ids, ivec3(q, layer), 0).r;
            bool seen = shown == 0u || shown == id;
            for (uint k = 0u; k < count && !seen; k++)
                seen = cand[k] == shown - 1u;
            if (!seen)
                cand[count++] = shown - 1u;
        }
    }
    return count;
}

// Whether a receiver at offset d = x - centre from a shooter (cs = d . n_s,
// ce = -d . n_e) can take light from it. It must lie in front of the
// shooter's plane by more than 1e-4 of its distance: a receiver in that
// plane (the bottom of a box standing on the shooter) sees it edge-on,
// F = 0, and rounding must not turn that into the near-field form factor
// of a point touching the shooter. Near the shooter, a patch whose centre
// lies behind the receiver's tangent plane can still light it (a light
// straddling the plane of a block's side; the exact form factor clips the
// patch to the front half-space); far from it, the disk needs the centre
// in front.
bool shooting_faces(vec3 d, float cs, float ce, bool near)
{
    return cs > 1e-4 * length(d) && (near || ce > 0.0);
}

// The terms of shooting_point_to_quad's sum, edge by edge: shooting_arc
// that of the edge from a to b (corners less x) as it is;
// shooting_edge_term that of the edge's part in front of x (normal n);
// shooting_cut_term that of the edges the clipping adds to quad r (less
// x), from where its boundary leaves the front half-space to where it
// enters again, 0 where the plane does not cut it. The polygon clipped
// in a private array (its corners and crossings in turn, up to 5, then a
// loop over them) cost llvmpipe half of conserve far's progressive shots:
// its dynamically indexed array and loops of each lane's own length ran
// as scratch memory under masks (room 1 of tests/solvers/rooms.c, the
// reconstruct pass 12.4 -> 6.2 ms a hemicube with far, 5.1 -> 2.8 with
// off, the solutions the same within 1e-7, 2026-12-07).
float shooting_arc(vec3 a, vec3 b, vec3 n)
{
    vec3 c = cross(a, b);
    float cl = length(c);
    return cl > 0.0 ? atan(cl, dot(a, b)) * dot(n, c) / cl : 0.0;
}

float shooting_edge_term(vec3 a, vec3 b, vec3 n)
{
    float da = dot(a, n), db = dot(b, n);
    if (!(da > 0.0) && !(db > 0.0))
        return 0.0;
    if ((da > 0.0) != (db > 0.0)) {
        vec3 m = mix(a, b, da / (da - db));
        if (da > 0.0)
            b = m;
        else
            a = m;
    }
    return shooting_arc(a, b, n);
}

float shooting_cut_term(vec3 r[4], vec3 n)
{
    // The crossings alternate, leaving and entering, round the quad; each
    // leaving one joins the next entering one, the last the first.
    // Rounding can make more than one pair where the quad lies in x's
    // plane (a triangle beside x's own in a mesh's face): with the last
    // pair alone, gather's direct light in test_triangles' furnace of
    // one-element triangles came out 1.1% off E / (1 - rho).
    float sum = 0.0;
    vec3 leave = vec3(0.0), first_enter = vec3(0.0);
    bool pending = false, early = false;
    for (int k = 0; k < 4; k++) {
        vec3 a = r[k], b = r[(k + 1) & 3];
        float da = dot(a, n), db = dot(b, n);
        if ((da > 0.0) != (db > 0.0)) {
            vec3 m = mix(a, b, da / (da - db));
            if (da > 0.0) {
                leave = m;
                pending = true;
            } else if (pending) {
                sum += shooting_arc(leave, m, n);
                pending = false;
            } else {
                first_enter = m;
                early = true;
            }
        }
    }
    return pending && early ? sum + shooting_arc(leave, first_enter, n) : sum;
}

// Form factor from the point x (unit normal n) to the convex polygon q[0..3]
// clipped to the half-space in front of x (Lambert: (1/2pi) sum_k gamma_k
// n . (R_k x R_k+1) / |R_k x R_k+1|, ground-truth.md): the clipped
// polygon's edges are the parts of q's edges in front and the cut.
float shooting_point_to_quad(vec3 x, vec3 n, vec3 q[4])
{
    vec3 r[4] = vec3[4](q[0] - x, q[1] - x, q[2] - x, q[3] - x);
    float sum = shooting_edge_term(r[0], r[1], n) + shooting_edge_term(r[1], r[2], n) +
                shooting_edge_term(r[2], r[3], n) + shooting_edge_term(r[3], r[0], n) +
                shooting_cut_term(r, n);
    return abs(sum) / (2.0 * SHOOTING_PI);
}

// The form factor from the receiver point x (normal ne) to the patch sh of
// surface sf, for d = x - centre, cs = cos at the shooter and ce = cos at
// the receiver (both > 0): the disk approximation (eq. 2.2.7/2.2.8 with
// m = 1) where A_s / r^2 <= ratio; nearer, the exact point-to-quad form
// factor to the patch (the limit of the subdivision of thesis 4.3.3).
// Callers test near() first so that the surface is read only when needed.
bool shooting_near(vec3 d, float area, float ratio)
{
    return area > ratio * dot(d, d);
}

float shooting_disk(vec3 d, float cs, float ce, float area)
{
    float r2 = dot(d, d);
    return area * cs * ce / (r2 * (SHOOTING_PI * r2 + area));
}

// The corners of elements [i0, i1] x [j0, j1] of sf.
void shooting_cell_quad(gpu_surface sf, uint i0, uint i1, uint j0, uint j1, out vec3 q[4])
{
    vec2 rs = cell_param_range(i0, i1, sf.nu);
    vec2 rt = cell_param_range(j0, j1, sf.nv);
    q[0] = cell_bilinear(sf, rs.x, rt.x);
    q[1] = cell_bilinear(sf, rs.y, rt.x);
    q[2] = cell_bilinear(sf, rs.y, rt.y);
    q[3] = cell_bilinear(sf, rs.x, rt.y);
}

// The exact form factor from x to elements [i0, i1] x [j0, j1] of sf.
float shooting_cells(vec3 x, vec3 ne, gpu_surface sf, uint i0, uint i1, uint j0, uint j1)
{
    vec3 q[4];
    shooting_cell_quad(sf, i0, i1, j0, j1, q);
    return shooting_point_to_quad(x, ne, q);
}

// Blocks per side of a patch that a receiver very near it sees one by one
// (reconstruct.comp near_cells, incremental_reconstruct.comp
// visible_blocks).
const uint SHOOTING_NEAR_BLOCKS = 8u;

// Within how many patch sizes (squared: r^2 < this x A_s) a receiver sees
// a patch block by block: the progressive shots (reconstruct.comp
// near_within says why two sizes) and the moving object's intake in
// incremental's redistribution, which must see where the shots see.
const float SHOOTING_NEAR_REACH2 = 4.0;

#ifdef SHOOTING_BVH
// ncand for shooting_front_hidden: test every surface, not candidates.
// The texels towards x of a hemicube drawn from a centre behind x's plane
// show what the centre sees, and the surface that hides the part in front
// may be one they do not show: a floor patch cut by the plane of a box's
// side in another room lit that side through the wall, which a box in the
// first room hid from the patch's centre (tests/solvers/test_extremes.c,
// emission range).
const uint SHOOTING_EVERY_SURFACE = 0xffffffffu;

// A flag on ncand: the candidates and every surface that is not a mesh
// face. A segment test is a loop over the surfaces, and a mesh of
// thousands of faces made every such test thousands: a 1280-face ball's
// shots ran past the 60 s wait limit. Mesh faces then block only where the
// texels towards x show them; quads (walls, the light's surroundings), as
// SHOOTING_EVERY_SURFACE says, always.
const uint SHOOTING_EVERY_QUAD = 0x80000000u;

// Whether the segment from c to x meets box [lo, hi] (the slab test over
// t in [-1e-4, 1 + 1e-4]; inv = 1 / (x - c), zero components made tiny so
// that no 0 x inf makes a NaN).
bool shooting_box_crossed(vec3 lo, vec3 hi, vec3 c, vec3 inv)
{
    vec3 t0 = (lo - c) * inv, t1 = (hi - c) * inv;
    vec3 near = min(t0, t1), far = max(t0, t1);
    float enter = max(max(near.x, near.y), max(near.z, -1e-4));
    float leave = min(min(far.x, far.y), min(far.z, 1.0 + 1e-4));
    return enter <= leave;
}

// Steps the hierarchy walks of this invocation have taken: direct.comp
// reports an invocation that came near lavapipe's loop limit.
uint shooting_walk_steps = 0u;

// Whether the segment from c to x crosses a surface (quads_only: a surface
// that is not a mesh face) of the hierarchy bvh_nodes / bvh_items, which
// the includer declares with SHOOTING_BVH: a walk down the boxes the
// segment meets, about 2 log2(surfaces) of them, where a loop over the
// surfaces took thousands of iterations a segment (gpu_bvh_node says what
// that cost on lavapipe).
bool shooting_bvh_hidden(vec3 c, vec3 x, bool quads_only)
{
    vec3 d = x - c;
    vec3 inv = vec3(1.0) / mix(d, vec3(1e-30), lessThan(abs(d), vec3(1e-30)));
    uint stack[GPU_BVH_STACK];
    uint top = 1u;
    stack[0] = 0u;
    while (top > 0u) {
        gpu_bvh_node n = bvh_nodes[stack[--top]];
        shooting_walk_steps++;
        if (!shooting_box_crossed(n.lo.xyz, n.hi.xyz, c, inv))
            continue;
        if (n.count == 0u) {
            if (top + 2u <= GPU_BVH_STACK) {
                stack[top++] = n.first + 1u;
                stack[top++] = n.first;
            }
            continue;
        }
        for (uint k = n.first; k < n.first + n.count; k++) {
            uint m = bvh_items[k];
            shooting_walk_steps++;
            if ((quads_only && surfaces[m].mesh != 0u) || SHOOTING_UNDRAWN(m))
                continue;
            if (shooting_blocks(SHOOTING_OCCLUDER(m, false), c, x))
                return true;
        }
    }
    return false;
}

#ifdef SHOOTING_BUNDLE
// The quads that may hide a segment of a bundle (from a patch to one
// receiver), collected once by shooting_collect_bundle: near_cells tests
// up to SHOOTING_NEAR_BLOCKS^2 blocks of a patch from one receiver, with
// conserve far every quad for each, and a walk of the hierarchy per block
// made cornell-small's far solve 25.9 s on lavapipe, 22.8 s with the walk
// once a bundle (on: 12.2 s; README "Conservation of a shot"). The segment tests of the bundle loop over
// these instead (shooting_segment_hidden). SHOOTING_BOX_NONE: none
// collected (more than fit, or no bundle): the tests walk. Only where the
// includer defines SHOOTING_BUNDLE (conserve far's SPIR-V): in the others
// the global state alone cost 2-3% of a progressive solve.
const uint SHOOTING_BOX_QUADS = 16u;
const uint SHOOTING_BOX_NONE = 0xffffffffu;
uint shooting_box_quads[SHOOTING_BOX_QUADS];
uint shooting_box_quad_count = SHOOTING_BOX_NONE;

bool shooting_boxes_meet(vec3 alo, vec3 ahi, vec3 blo, vec3 bhi)
{
    return all(lessThanEqual(alo, bhi)) && all(lessThanEqual(blo, ahi));
}

// Whether the plane of quad s has every point of the bundle from quad q to
// x strictly on one side, by more than 1e-4 of the bundle's size b: then
// no segment of it crosses s (the walls round a patch and its receiver).
// Not where a point lies in the plane (the patch's own surface, x's): with
// those left out too, a few segments that touch a plane within rounding
// came out otherwise, and cornell-small's far solve moved by up to 4e-4
// at 5% of its elements.
bool shooting_bundle_beside(gpu_surface s, vec3 q[4], vec3 x, float b)
{
    vec3 n = s.normal_area.xyz;
    float o = dot(n, s.corner[0].xyz), tol = 1e-4 * b;
    float lo = dot(n, x) - o, hi = lo;
    for (int k = 0; k < 4; k++) {
        float h = dot(n, q[k]) - o;
        lo = min(lo, h);
        hi = max(hi, h);
    }
    return lo > tol || hi < -tol;
}

// Collects into shooting_box_quads the surfaces but mesh faces
// (SHOOTING_EVERY_QUAD) that may hide a segment from quad q to x: whose
// boxes meet the bundle's box (grown by a thousandth of its size against
// rounding) and whose planes cut the bundle; SHOOTING_BOX_NONE where more
// than SHOOTING_BOX_QUADS do. The walk is shooting_bvh_hidden's with a box
// for the segment; one walker for both would take the stack as an inout
// array, copied in and out on each call of the walk every shot runs.
void shooting_collect_bundle(vec3 q[4], vec3 x)
{
    vec3 lo = min(min(min(q[0], q[1]), min(q[2], q[3])), x);
    vec3 hi = max(max(max(q[0], q[1]), max(q[2], q[3])), x);
    float size = max(max(hi.x - lo.x, hi.y - lo.y), hi.z - lo.z);
    lo -= vec3(1e-3 * size + 1e-6);
    hi += vec3(1e-3 * size + 1e-6);
    uint stack[GPU_BVH_STACK];
    uint top = 1u, count = 0u;
    stack[0] = 0u;
    while (top > 0u) {
        gpu_bvh_node n = bvh_nodes[stack[--top]];
        shooting_walk_steps++;
        if (!shooting_boxes_meet(n.lo.xyz, n.hi.xyz, lo, hi))
            continue;
        if (n.count == 0u) {
            if (top + 2u <= GPU_BVH_STACK) {
                stack[top++] = n.first + 1u;
                stack[top++] = n.first;
            }
            continue;
        }
        for (uint k = n.first; k < n.first + n.count; k++) {
            uint m = bvh_items[k];
            shooting_walk_steps++;
            if (surfaces[m].mesh != 0u || SHOOTING_UNDRAWN(m))
                continue;
            gpu_surface s = SHOOTING_OCCLUDER(m, false);
            vec3 slo = min(min(s.corner[0].xyz, s.corner[1].xyz), min(s.corner[2].xyz, s.corner[3].xyz));
            vec3 shi = max(max(s.corner[0].xyz, s.corner[1].xyz), max(s.corner[2].xyz, s.corner[3].xyz));
            if (!shooting_boxes_meet(slo, shi, lo, hi) || shooting_bundle_beside(s, q, x, size))
                continue;
            if (count == SHOOTING_BOX_QUADS) {
                shooting_box_quad_count = SHOOTING_BOX_NONE;
                return;
            }
            shooting_box_quads[count++] = m;
        }
    }
    shooting_box_quad_count = count;
}
#endif
#endif

// Whether the segment from c to x crosses one of the candidate occluders
// cand[0, ncand), or any surface where ncand is SHOOTING_EVERY_SURFACE
// (any but mesh faces beside the candidates with SHOOTING_EVERY_QUAD),
// posed as the hemicube that named them was drawn (SHOOTING_OCCLUDER).
// Every surface through the hierarchy: the flags exist where the shader
// defines SHOOTING_BVH and declares bvh_nodes and bvh_items.
bool shooting_segment_hidden(vec3 c, vec3 x, uint cand[9], uint ncand)
{
#ifdef SHOOTING_BVH
    if (ncand == SHOOTING_EVERY_SURFACE)
        return shooting_bvh_hidden(c, x, false);
    uint count_m = ncand & ~SHOOTING_EVERY_QUAD;
#else
    uint count_m = ncand;
#endif
    for (uint m = 0u; m < count_m; m++)
        if (shooting_blocks(SHOOTING_OCCLUDER(cand[m], false), c, x))
            return true;
#ifdef SHOOTING_BVH
    if ((ncand & SHOOTING_EVERY_QUAD) != 0u) {
#ifdef SHOOTING_BUNDLE
        if (shooting_box_quad_count != SHOOTING_BOX_NONE) {
            for (uint m = 0u; m < shooting_box_quad_count; m++)
                if (shooting_blocks(SHOOTING_OCCLUDER(shooting_box_quads[m], false), c, x))
                    return true;
            return false;
        }
#endif
        return shooting_bvh_hidden(c, x, true);
    }
#endif
    return false;
}

// The middle of quad q's part in front of x's tangent plane (normal ne),
// whence shooting_front_hidden tests the segment to x; whether quad q is
// hidden from x: the segment to x from that point crosses one of
// the candidate occluders cand[0, ncand) (shooting_candidates), posed as
// the hemicube that named them was drawn (SHOOTING_OCCLUDER). From the
// part in front, not the quad's centre: a quad that the plane cuts lights
// x from that part alone, and from a centre behind the plane the segment
// to x runs through x's own object (a light cut by the plane of a floating
// box's side lit its top rows at 0.87 of the CPU reference's).
vec3 shooting_front_point(vec3 q[4], vec3 x, vec3 ne)
{
    vec3 c = vec3(0.0);
    float count = 0.0;
    for (int k = 0; k < 4; k++) {
        vec3 a = q[k], b = q[(k + 1) & 3];
        float da = dot(a - x, ne), db = dot(b - x, ne);
        if (da > 0.0) {
            c += a;
            count += 1.0;
        }
        if ((da > 0.0) != (db > 0.0)) {
            c += mix(a, b, da / (da - db));
            count += 1.0;
        }
    }
    return count > 0.0 ? c / count : 0.25 * (q[0] + q[1] + q[2] + q[3]);
}

bool shooting_front_hidden(vec3 q[4], vec3 x, vec3 ne, uint cand[9], uint ncand)
{
    return shooting_segment_hidden(shooting_front_point(q, x, ne), x, cand, ncand);
}

// Whether the tangent plane of x (normal ne) cuts through quad q of area
// `area`, ce = -d . ne the distance of the quad's centre from the plane:
// the centre may then lie behind the plane, where what it sees says
// nothing of what the quad's part in front sees.
bool shooting_quad_straddles(vec3 q[4], vec3 x, vec3 ne, float ce, float area)
{
    if (ce * ce >= area)
        return false;
    float lo = 3.4e38, hi = -3.4e38;
    for (int k = 0; k < 4; k++) {
        float h = dot(q[k] - x, ne);
        lo = min(lo, h);
        hi = max(hi, h);
    }
    float tol = 1e-4 * sqrt(area);
    return lo < -tol && hi > tol;
}

// shooting_quad_straddles for patch sh of sf.
bool shooting_straddles(vec3 x, vec3 ne, float ce, gpu_surface sf, gpu_shooter sh)
{
    if (ce * ce >= sh.pos_area.w)
        return false;
    vec3 q[4];
    shooting_cell_quad(sf, sh.i0, sh.i1, sh.j0, sh.j1, q);
    return shooting_quad_straddles(q, x, ne, ce, sh.pos_area.w);
}

// The exact form factor from x to patch sh of sf.
float shooting_quad(vec3 x, vec3 ne, gpu_surface sf, gpu_shooter sh)
{
    return shooting_cells(x, ne, sf, sh.i0, sh.i1, sh.j0, sh.j1);
}

#endif
