// Points of a surface's element grid (src/scene/scene.h), from the
// surface's posed corners (gpu_surface): what the passes that take an
// element's receiver point share (shooting.glsl, cross_update.comp).
// Include after radiosity.h.
#ifndef XRAD_CELL_GLSL
#define XRAD_CELL_GLSL

vec3 cell_bilinear(gpu_surface sf, float s, float t)
{
    return mix(mix(sf.corner[0].xyz, sf.corner[1].xyz, s),
               mix(sf.corner[3].xyz, sf.corner[2].xyz, s), t);
}

// The parameter interval covered by samples [i0, i1] of n along one side
// (src/scene/scene.h), as in select.comp.
vec2 cell_param_range(uint i0, uint i1, uint n)
{
    if (n < 2u)
        return vec2(0.0, 1.0); // a tiny triangle's one element (scene.h)
    float h = 1.0 / float(n - 1u);
    return vec2(max(0.0, (float(i0) - 0.5) * h), min(1.0, (float(i1) + 0.5) * h));
}

// The receiver point of element (i, j) of surface sf: the midpoint of its
// cell, and a tiny triangle's centroid for its one element
// (scene_cell_centre).
vec3 cell_centroid(gpu_surface sf, uint i, uint j)
{
    vec2 rs = cell_param_range(i, i, sf.nu), rt = cell_param_range(j, j, sf.nv);
    bool lone = sf.nv < 2u && (sf.mesh & GPU_SURFACE_TRIANGLE) != 0u;
    return cell_bilinear(sf, 0.5 * (rs.x + rs.y), lone ? 1.0 / 3.0 : 0.5 * (rt.x + rt.y));
}

#endif
