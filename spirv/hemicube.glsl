// Hemicube conventions, mirrored from src/passes/hemicube_geometry.h (read
// that header for the picture). Include with GL_GOOGLE_include_directive.
#ifndef XRAD_HEMICUBE_GLSL
#define XRAD_HEMICUBE_GLSL

const int HEMICUBE_FACES = 5;

// Right, up, forward per face, in the hemicube's local frame (z = normal).
const vec3 HEMICUBE_RIGHT[5] = vec3[5](vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, -1, 0),
                                       vec3(-1, 0, 0), vec3(1, 0, 0));
const vec3 HEMICUBE_UP[5] = vec3[5](vec3(0, 1, 0), vec3(0, 0, 1), vec3(0, 0, 1),
                                    vec3(0, 0, 1), vec3(0, 0, 1));
const vec3 HEMICUBE_FORWARD[5] = vec3[5](vec3(0, 0, 1), vec3(1, 0, 0), vec3(-1, 0, 0),
                                         vec3(0, 1, 0), vec3(0, -1, 0));

// Texel i (< 3 res^2) of the part of a hemicube that weighs (thesis 2.2.2):
// the top face's res^2 texels, then each side face's upper half, rows
// res/2 .. res-1 (res even). Returns the face; `texel` is (column, row).
uint hemicube_weighted_texel(uint i, uint res, out uvec2 texel)
{
    uint top = res * res, half_face = top / 2u;
    if (i < top) {
        texel = uvec2(i % res, i / res);
        return 0u;
    }
    uint j = i - top, r = half_face + j % half_face;
    texel = uvec2(r % res, r / res);
    return 1u + j / half_face;
}

// The direction of a texel's centre in the hemicube's local frame, with
// unit component along the face's axis (the faces as hemicube_face below
// maps directions to them). Its delta form factor is d.z / (pi |d|^4) of
// the texel's area, its solid angle 1 / |d|^3 of it.
vec3 hemicube_texel_direction(uint face, uvec2 texel, uint res)
{
    vec2 uv = (vec2(texel) + 0.5) / float(res) * 2.0 - 1.0;
    float u = uv.x, v = uv.y;
    return face == 0u ? vec3(u, v, 1.0)
         : face == 1u ? vec3(1.0, u, v)
         : face == 2u ? vec3(-1.0, -u, v)
         : face == 3u ? vec3(-u, 1.0, v)
                      : vec3(u, -1.0, v);
}

// Clip position of local direction d on `face`: reversed-Z with an infinite
// far plane (depth = near / distance along the face axis; clear to 0, test
// GREATER), so that everything nearer than `near` is clipped.
vec4 hemicube_clip(vec3 d, int face, float near)
{
    return vec4(dot(d, HEMICUBE_RIGHT[face]), dot(d, HEMICUBE_UP[face]), near,
                dot(d, HEMICUBE_FORWARD[face]));
}

// Face of a local direction with d.z > 0, and its continuous pixel
// coordinate at resolution res: (right, up) . d / (forward . d), from [-1, 1]
// to [0, res]. The face's axes are written out rather than read from the
// tables above: a table indexed at run time costs more than the rest of
// the lookup on lavapipe, and these are the same numbers.
int hemicube_face(vec3 d, uint res, out vec2 t)
{
    int face = 0;
    vec2 ab = d.xy / d.z;
    float best = d.z;
    if (d.x > best) { face = 1; best = d.x; ab = vec2(d.y, d.z) / d.x; }
    if (-d.x > best) { face = 2; best = -d.x; ab = vec2(-d.y, d.z) / -d.x; }
    if (d.y > best) { face = 3; best = d.y; ab = vec2(-d.x, d.z) / d.y; }
    if (-d.y > best) { face = 4; ab = vec2(d.x, d.z) / -d.y; }
    t = (ab + 1.0) * 0.5 * float(res);
    return face;
}

// Face of a local direction with d.z > 0, and its pixel at resolution res.
int hemicube_lookup(vec3 d, uint res, out uvec2 px)
{
    vec2 t;
    int face = hemicube_face(d, res, t);
    px = uvec2(clamp(floor(t), vec2(0), vec2(float(res - 1u))));
    return face;
}

#endif
