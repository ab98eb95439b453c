// Hemicube render pass, vertex stage, shared by the two paths
// (src/passes/hemicube.c): hemicube_multiview.vert defines
// HEMICUBE_MULTIVIEW (gl_ViewIndex is the face, one render pass instance per
// hemicube), hemicube_layered.vert does not (instance = hemicube * 5 + face,
// written to gl_Layer). Indexed triangles, each with a provoking vertex
// of its own carrying its ids (hemicube_shared.h); the frame of each
// hemicube comes from the frames buffer (z = normal, x = tangent, y = z x
// x, as spirv/hemicube.glsl expects).
#include "radiosity.h"
#include "hemicube_shared.h"
#include "hemicube.glsl"

layout(push_constant) uniform Push { hemicube_push pc; };
layout(std430, binding = HEMICUBE_BINDING_FRAMES) readonly buffer Frames { gpu_shooter frames[]; };
layout(std430, binding = HEMICUBE_BINDING_COUNTS) readonly buffer Counts { uint counts[]; };

layout(location = HEMICUBE_ATTR_POS) in vec3 in_pos;
layout(location = HEMICUBE_ATTR_IDS) in uvec2 in_ids; // surface, triangle

// Flat values are the provoking vertex's: the triangle's own, or, for the
// origin, the same at every vertex.
layout(location = 0) flat out uvec2 ids;    // surface, triangle
layout(location = 1) flat out vec3 origin;  // m, world: the hemicube's (moved) origin
layout(location = 2) out vec3 rel;          // m: the point from the origin, at the pixel centre
// The same at a covered sample (centroid): where the radiosity variant's
// atlas coordinate is taken, inside the triangle (its distance, the back
// hemicubes' depth, stays at the centre, as the resolve expects).
layout(location = 3) centroid out vec3 rel_c;
// The surface the hemicube stands on (none for a group of mesh faces,
// which may see each other): hemicube_radiosity.frag draws it black
// where its OWN_BLACK is set (gather).
layout(location = 4) flat out uint own;

void main()
{
#ifdef HEMICUBE_MULTIVIEW
    uint h = pc.hemicube;
    int face = int(gl_ViewIndex);
    bool live = pc.count_word == HEMICUBE_NO_COUNT || h < counts[pc.count_word];
#else
    uint h = uint(gl_InstanceIndex) / uint(HEMICUBE_FACES);
    int face = gl_InstanceIndex % HEMICUBE_FACES;
    gl_Layer = gl_InstanceIndex;
    bool live = true;
#endif
    gpu_shooter f = frames[pc.first + h];
    vec3 z = normalize(f.normal.xyz);
    vec3 x = normalize(f.tangent.xyz - dot(f.tangent.xyz, z) * z);
    vec3 y = cross(z, x);
    // The origin leaves its own surface by a hair (plus a few float steps
    // of its coordinates), so that surface lies below the horizon, where
    // the side faces' rows carry no weight, instead of on it.
    vec3 o = f.pos_area.xyz;
    float ulps = 8.0 * 1.1920929e-7 * max(abs(o.x), max(abs(o.y), abs(o.z)));
    o += z * (pc.hair + ulps);
    vec3 d = in_pos - o;
    vec3 local = vec3(dot(d, x), dot(d, y), dot(d, z));
    // A dead hemicube (beyond the indirect count) puts every vertex behind
    // the eye: everything is clipped.
    gl_Position = live ? hemicube_clip(local, face, pc.near) : vec4(0.0, 0.0, 0.0, -1.0);
    ids = in_ids;
    origin = o;
    rel = d;
    rel_c = d;
    own = f.group != 0u ? 0xffffffffu : f.surface;
}
