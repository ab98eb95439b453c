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

// Clip position of local direction d on `face`: reversed-Z with an infinite
// far plane (depth = near / distance along the face axis; clear to 0, test
// GREATER), so that everything nearer than `near` is clipped.
vec4 hemicube_clip(vec3 d, int face, float near)
{
    return vec4(dot(d, HEMICUBE_RIGHT[face]), dot(d, HEMICUBE_UP[face]), near,
                dot(d, HEMICUBE_FORWARD[face]));
}

// Face of a local direction with d.z > 0, and its pixel at resolution res.
int hemicube_lookup(vec3 d, uint res, out uvec2 px)
{
    int face = 0;
    float best = d.z;
    if (d.x > best) { face = 1; best = d.x; }
    if (-d.x > best) { face = 2; best = -d.x; }
    if (d.y > best) { face = 3; best = d.y; }
    if (-d.y > best) { face = 4; best = -d.y; }
    vec2 ab = vec2(dot(d, HEMICUBE_RIGHT[face]), dot(d, HEMICUBE_UP[face])) / best;
    px = uvec2(clamp(floor((ab + 1.0) * 0.5 * float(res)), vec2(0), vec2(float(res - 1u))));
    return face;
}

#endif
