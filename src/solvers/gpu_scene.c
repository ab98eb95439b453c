#include "solvers/gpu_scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "gpu/cmd.h"
#include "gpu/context.h"
#include "hemicube_shared.h"
#include "radiosity.h"
#include "scene/scene_luminaire.h"
#include "solvers/hemicube_clusters.h"
#include "solvers/surface_bvh.h"

/* Host copies of the posed geometry, filled by fill_geometry. */
typedef struct geometry {
    struct gpu_surface *surfaces;
    struct gpu_element *elements;
    struct gpu_hemicube_vertex *vertices;
} geometry;

static void geometry_free(geometry *g)
{
    free(g->surfaces);
    free(g->elements);
    free(g->vertices);
    memset(g, 0, sizeof(*g));
}

/* Buffers cannot be empty; a scene without surfaces still gets one entry. */
static size_t at_least_one(size_t n) { return n ? n : 1; }

/* The host tables at `time`, the hemicube vertices among them. */
static xrad_status fill_geometry(const xrad_scene *scene, const uint32_t *fixed_patches,
                                 const hemicube_clusters *layout, double time, geometry *g,
                                 double *diameter, xrad_error *err)
{
    memset(g, 0, sizeof(*g));
    g->surfaces = calloc(at_least_one(scene->surface_count), sizeof(*g->surfaces));
    g->elements = calloc(at_least_one(scene->element_count), sizeof(*g->elements));
    g->vertices = calloc(at_least_one(layout->vertex_count), sizeof(*g->vertices));
    xform *poses = calloc(at_least_one(scene->object_count), sizeof *poses);
    if (!g->surfaces || !g->elements || !g->vertices || !poses) {
        free(poses);
        geometry_free(g);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of host memory for the GPU scene",
                         scene->path);
    }
    vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
    for (uint32_t s = 0; s < scene->surface_count; s++) {
        const surface *sf = &scene->surfaces[s];
        xform pose = scene_object_pose(scene, sf->object, time);
        vec3 c[4], n;
        scene_surface_world(scene, s, time, c, &n);
        struct gpu_surface *gsf = &g->surfaces[s];
        for (int k = 0; k < 4; k++) {
            gsf->corner[k] = gpu_vec4(c[k], 1);
            lo = v3(fmin(lo.x, c[k].x), fmin(lo.y, c[k].y), fmin(lo.z, c[k].z));
            hi = v3(fmax(hi.x, c[k].x), fmax(hi.y, c[k].y), fmax(hi.z, c[k].z));
        }
        gsf->normal_area = gpu_vec4(n, sf->area);
        gsf->first_element = sf->first_element;
        gsf->nu = sf->nu;
        gsf->nv = sf->nv;
        gsf->material = sf->material;
        gsf->object = sf->object;
        gsf->dynamic = scene->objects[sf->object].dynamic ? 1u : 0u;
        gsf->mesh = (sf->mesh ? GPU_SURFACE_MESH : 0u) | (sf->triangle ? GPU_SURFACE_TRIANGLE : 0u);
        gsf->tile_x = sf->tile_x;
        gsf->tile_y = sf->tile_y;
        if (fixed_patches) {
            gsf->patches_s = fixed_patches[3 * s];
            gsf->patches_t = fixed_patches[3 * s + 1];
            gsf->patch_first = fixed_patches[3 * s + 2];
        }

        for (uint32_t e = 0; e < sf->nu * sf->nv; e++) {
            const element *el = &scene->elements[sf->first_element + e];
            struct gpu_element *ge = &g->elements[sf->first_element + e];
            ge->pos_area = gpu_vec4(xf_point(&pose, el->pos), el->area);
            /* The receiver normal: a normal map's where there is one (Wallner
             * 3.3), posed with its object. */
            ge->normal =
                scene->element_normal
                    ? gpu_vec4(v3_norm(xf_dir(&pose, scene->element_normal[sf->first_element + e])),
                               0)
                    : gpu_vec4(n, 0);
            ge->surface = s;
            ge->texel_x = el->texel_x;
            ge->texel_y = el->texel_y;
            ge->albedo = gpu_vec4(scene_element_albedo(scene, sf->first_element + e), 0);
        }
    }
    /* A vertex is posed as the corner it is at (hemicube_clusters.h), so
     * the corners that share it agree to the bit with scene_surface_world. */
    for (uint32_t o = 0; o < scene->object_count; o++)
        poses[o] = scene_object_pose(scene, o, time);
    for (uint32_t v = 0; v < layout->vertex_count; v++) {
        const surface *sf = &scene->surfaces[layout->vertex_source[v] / 4];
        vec3 p = xf_point(&poses[sf->object], sf->p[layout->vertex_source[v] % 4]);
        uint32_t t = layout->vertex_triangle[v];
        g->vertices[v] = (struct gpu_hemicube_vertex){
            .x = (float)p.x, .y = (float)p.y, .z = (float)p.z,
            .surface = t == UINT32_MAX ? 0 : layout->triangle_surface[t],
            .triangle = t == UINT32_MAX ? 0 : t,
        };
    }
    free(poses);
    *diameter = scene->surface_count ? v3_len(v3_sub(hi, lo)) : 0;
    return XRAD_OK;
}

/* What the hemicubes' fragments need of each triangle (hemicube_shared.h),
 * the same at every pose. */
static xrad_status upload_triangles(struct xrad_context *ctx, gpu_scene *gs, xrad_error *err)
{
    const xrad_scene *scene = gs->scene;
    const hemicube_clusters *layout = &gs->layout;
    size_t nt = at_least_one(layout->index_count / 3);
    struct gpu_hemicube_triangle *t = calloc(nt, sizeof *t);
    if (!t)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of host memory for the GPU scene",
                         scene->path);
    double inv_w = 1.0 / (scene->atlas_width ? scene->atlas_width : 1);
    double inv_h = 1.0 / (scene->atlas_height ? scene->atlas_height : 1);
    for (uint32_t s = 0; s < scene->surface_count; s++) {
        const surface *sf = &scene->surfaces[s];
        /* Corners p0..p3 carry the element samples (0, 0), (nu-1, 0),
         * (nu-1, nv-1), (0, nv-1): the outer texel centres lie on the
         * surface edges (thesis 4.1), so interpolating uv across the quad
         * and filtering bilinearly reproduces the element samples. */
        uint32_t ci[4] = {0, sf->nu - 1, sf->nv * sf->nu - 1, (sf->nv - 1) * sf->nu};
        const element *e0 = &scene->elements[sf->first_element];
        const element *e1 = &scene->elements[sf->first_element + ci[2]];
        vec4 tile = {(float)((e0->texel_x + 0.5) * inv_w), (float)((e0->texel_y + 0.5) * inv_h),
                     (float)((e1->texel_x + 0.5) * inv_w), (float)((e1->texel_y + 0.5) * inv_h)};
        for (uint32_t k = 0; k < hemicube_surface_triangles(sf); k++) {
            uint32_t ti = layout->first_index[s] / 3 + k;
            struct gpu_hemicube_triangle *tr = &t[ti];
            vec3 p[3];
            for (int i = 0; i < 3; i++) {
                int corner = layout->corners[3 * ti + i];
                const element *el = &scene->elements[sf->first_element + ci[corner]];
                /* A triangle's apex is corners 2 and 3 (scene.h). */
                float w = sf->triangle && corner >= 2 ? 0.0f : 1.0f;
                tr->uvw[i] = (vec4){(float)((el->texel_x + 0.5) * inv_w) * w,
                                    (float)((el->texel_y + 0.5) * inv_h), w, 0};
                p[i] = sf->p[corner];
            }
            /* Rigid poses keep the winding's side. */
            vec3 n = v3_cross(v3_sub(p[1], p[0]), v3_sub(p[2], p[0]));
            tr->tile = tile;
            tr->sign = v3_dot(n, sf->normal) < 0 ? -1.0f : 1.0f;
        }
    }
    xrad_status st = gpu_upload_buffer(ctx, &gs->triangles, 0, t, nt * sizeof *t, err);
    if (!st)
        st = gpu_upload_buffer(ctx, &gs->indices, 0, layout->indices,
                               at_least_one(layout->index_count) * sizeof(uint32_t), err);
    free(t);
    return st;
}

/* Marks buried elements (scene_find_buried, the enclosed ones of
 * scene_find_enclosed as buried under static surfaces, and those of
 * scene_find_enclosed_dynamic as under a moving one) in the host tables
 * and in gs->buried, at the pose the tables hold. */
static xrad_status mark_buried(gpu_scene *gs, double time, double diameter, geometry *g,
                               xrad_error *err)
{
    uint32_t count;
    xrad_status s = scene_find_buried(gs->scene, time, GPU_SCENE_CONTACT * diameter, gs->buried,
                                      &count, err);
    if (!s && (gs->flags & GPU_SCENE_ENCLOSE_MOVING))
        s = scene_find_enclosed_dynamic(gs->scene, time, gs->enclosed, gs->enclosed_m, &count,
                                        err);
    if (s)
        return s;
    for (uint32_t e = 0; e < gs->element_count; e++) {
        if (gs->enclosed[e])
            gs->buried[e] = 1;
        else if (gs->enclosed_m[e] && !gs->buried[e])
            gs->buried[e] = 2;
        g->elements[e].flags = gs->buried[e] == 1   ? GPU_ELEMENT_BURIED
                               : gs->buried[e] == 2 ? GPU_ELEMENT_BURIED_M
                                                    : 0u;
    }
    return XRAD_OK;
}

xrad_status gpu_scene_collect_pose(struct xrad_context *ctx, gpu_scene *gs, xrad_error *err)
{
    if (!gs->pose_cmd.cmd)
        return XRAD_OK;
    xrad_status s = gs->pose_cmd.submitted ? gpu_cmd_wait(ctx, &gs->pose_cmd, err) : XRAD_OK;
    gpu_cmd_destroy(ctx, &gs->pose_cmd);
    return s;
}

typedef struct pose_part {
    gpu_buffer *dst;
    const void *data;
    size_t bytes;
} pose_part;

/* The parts: written in place where the device memory is mapped (a CPU
 * device, or a GPU's host-visible device memory), the others through
 * gs->pose_staging in one submission nobody waits for (issue 16.4: five
 * uploads, each with a staging buffer of its own and a host wait, were
 * repeated at every frame of every method). */
static xrad_status upload_pose(struct xrad_context *ctx, gpu_scene *gs, const pose_part *parts,
                               uint32_t count, xrad_error *err)
{
    xrad_status s = gpu_scene_collect_pose(ctx, gs, err);
    if (s)
        return s;
    VkDeviceSize total = 0;
    for (uint32_t i = 0; i < count; i++) {
        if (parts[i].dst->alloc.mapped)
            memcpy(parts[i].dst->alloc.mapped, parts[i].data, parts[i].bytes);
        else
            total += (parts[i].bytes + 255) & ~(VkDeviceSize)255;
    }
    if (!total)
        return XRAD_OK;
    if (gs->pose_staging.size < total) {
        gpu_buffer_destroy(ctx, &gs->pose_staging);
        if ((s = gpu_buffer_create(ctx, total, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, GPU_MEM_UPLOAD,
                                   GPU_MEM_STAGING, &gs->pose_staging, err)))
            return s;
    }
    if ((s = gpu_cmd_begin(ctx, &gs->pose_cmd, err)))
        return s;
    VkDeviceSize at = 0;
    for (uint32_t i = 0; i < count; i++) {
        if (parts[i].dst->alloc.mapped)
            continue;
        memcpy((char *)gs->pose_staging.alloc.mapped + at, parts[i].data, parts[i].bytes);
        VkBufferCopy region = {.srcOffset = at, .dstOffset = 0, .size = parts[i].bytes};
        vkCmdCopyBuffer(gs->pose_cmd.cmd, gs->pose_staging.buffer, parts[i].dst->buffer, 1,
                        &region);
        at += (parts[i].bytes + 255) & ~(VkDeviceSize)255;
    }
    gpu_memory_barrier(gs->pose_cmd.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                       VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT);
    if ((s = gpu_cmd_submit(ctx, &gs->pose_cmd, err)))
        gpu_cmd_destroy(ctx, &gs->pose_cmd);
    return s;
}

static xrad_status upload_geometry(struct xrad_context *ctx, gpu_scene *gs, double time,
                                   xrad_error *err)
{
    const xrad_scene *scene = gs->scene;
    geometry g;
    double diameter = 0;
    xrad_status s = fill_geometry(scene, gs->fixed_patches, &gs->layout, time, &g, &diameter,
                                  err);
    if (!s)
        s = mark_buried(gs, time, diameter, &g, err);
    struct gpu_cluster *clusters =
        s ? NULL : malloc(at_least_one(gs->cluster_count) * sizeof *clusters);
    if (!s && !clusters)
        s = xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of host memory for the GPU scene",
                      scene->path);
    if (s) {
        geometry_free(&g);
        return s;
    }
    hemicube_clusters_bounds(&gs->layout, scene, g.surfaces, clusters);
    /* The tree from the first pose; its boxes at every pose. */
    if (!gs->bvh.nodes && scene->surface_count &&
        !(s = surface_bvh_build(g.surfaces, gs->surface_count, &gs->bvh, &gs->bvh_depth, err)))
        s = gpu_upload_buffer(ctx, &gs->bvh_items, 0, gs->bvh.items,
                              gs->surface_count * sizeof(uint32_t), err);
    struct gpu_bvh_node *nodes =
        s ? NULL : malloc(at_least_one(gs->bvh.node_count) * sizeof *nodes);
    if (!s && !nodes)
        s = xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of host memory for the GPU scene",
                      scene->path);
    if (s) {
        free(clusters);
        geometry_free(&g);
        return s;
    }
    /* A margin of 1e-5 of the scene's size: flat quads get a thickness,
     * and the slab test's rounding no miss. */
    surface_bvh_refit(&gs->bvh, g.surfaces, (float)fmax(1e-5 * diameter, 1e-7), nodes);
    const pose_part parts[] = {
        {&gs->surfaces, g.surfaces, at_least_one(gs->surface_count) * sizeof(*g.surfaces)},
        {&gs->elements, g.elements, at_least_one(gs->element_count) * sizeof(*g.elements)},
        {&gs->vertices, g.vertices, at_least_one(gs->vertex_count) * sizeof(*g.vertices)},
        {&gs->clusters, clusters, at_least_one(gs->cluster_count) * sizeof(*clusters)},
        {&gs->bvh_nodes, nodes, at_least_one(gs->bvh.node_count) * sizeof(*nodes)},
    };
    if (!(s = upload_pose(ctx, gs, parts, sizeof(parts) / sizeof(parts[0]), err))) {
        gs->time = time;
        gs->diameter = diameter;
    }
    free(nodes);
    free(clusters);
    geometry_free(&g);
    return s;
}

xrad_status gpu_scene_reset(struct xrad_context *ctx, gpu_scene *gs, bool static_only,
                            xrad_error *err)
{
    const xrad_scene *scene = gs->scene;
    size_t n = at_least_one(gs->element_count);
    vec4 *e = calloc(n, sizeof(*e));
    if (!e)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of host memory for emission",
                         scene->path);
    /* The luminaires' direct light, reflected: each lit element starts as
     * though it emitted rho times it (scene_luminaire.h); static_only (the
     * static scene alone, cross) with the static objects' shadows alone. */
    vec3 *lum = scene->luminaire_count ? calloc(n, sizeof(vec3)) : NULL;
    xrad_status s = scene->luminaire_count && !lum
                        ? xrad_fail(err, XRAD_ERROR_SYSTEM,
                                    "%s: out of host memory for the luminaires' light",
                                    scene->path)
                        : XRAD_OK;
    if (!s && lum)
        s = scene_luminaire_reflected(scene, gs->time, !static_only, lum, err);
    for (uint32_t i = 0; !s && i < gs->element_count; i++) {
        const material *m = &scene->materials[scene->surfaces[scene->elements[i].surface].material];
        e[i] = gpu_vec4(lum ? v3_add(m->emission, lum[i]) : m->emission, 0);
    }
    free(lum);
    if (!s)
        s = gpu_upload_buffer(ctx, &gs->B, 0, e, n * sizeof(*e), err);
    for (uint32_t i = 0; static_only && i < gs->element_count; i++) {
        const surface *sf = &scene->surfaces[scene->elements[i].surface];
        if (scene->objects[sf->object].dynamic)
            e[i] = (vec4){0};
    }
    if (!s)
        s = gpu_upload_buffer(ctx, &gs->Bu, 0, e, n * sizeof(*e), err);
    free(e);
    return s;
}

static xrad_status upload_materials(struct xrad_context *ctx, gpu_scene *gs, xrad_error *err)
{
    const xrad_scene *scene = gs->scene;
    size_t n = at_least_one(scene->material_count);
    struct gpu_material *m = calloc(n, sizeof(*m));
    if (!m)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of host memory for materials",
                         scene->path);
    for (uint32_t i = 0; i < scene->material_count; i++) {
        m[i].albedo = gpu_vec4(scene->materials[i].albedo, 0);
        m[i].emission = gpu_vec4(scene->materials[i].emission, 0);
    }
    xrad_status s = gpu_upload_buffer(ctx, &gs->materials, 0, m, n * sizeof(*m), err);
    free(m);
    return s;
}

/* Zeroes the atlas and leaves it in VK_IMAGE_LAYOUT_GENERAL, where it stays:
 * the atlas scatter pass stores to it and hemicubes sample it. */
static xrad_status init_atlas(struct xrad_context *ctx, gpu_scene *gs, xrad_error *err)
{
    gpu_cmd c;
    xrad_status s = gpu_cmd_begin(ctx, &c, err);
    if (s)
        return s;
    gpu_image_transition(c.cmd, &gs->atlas, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
    VkClearColorValue zero = {.float32 = {0, 0, 0, 0}};
    VkImageSubresourceRange range = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(c.cmd, gs->atlas.image, VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &range);
    gpu_image_barrier(c.cmd, &gs->atlas, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL,
                      VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                      VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    s = gpu_cmd_run(ctx, &c, err);
    gpu_cmd_destroy(ctx, &c);
    return s;
}

gpu_image_desc gpu_scene_atlas_desc(const xrad_scene *scene)
{
    return (gpu_image_desc){
        .format = VK_FORMAT_R32G32B32A32_SFLOAT,
        .width = scene->atlas_width ? scene->atlas_width : 1,
        .height = scene->atlas_height ? scene->atlas_height : 1,
        .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT |
                 VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
        .category = GPU_MEM_RADIOSITY,
    };
}

xrad_status gpu_scene_create(struct xrad_context *ctx, const xrad_scene *scene, double time,
                             uint32_t flags, gpu_scene *out, xrad_error *err)
{
    memset(out, 0, sizeof(*out));
    out->scene = scene;
    out->flags = flags;
    out->surface_count = scene->surface_count;
    out->element_count = scene->element_count;
    out->material_count = scene->material_count;
    const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                       VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                                       VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    size_t ns = at_least_one(scene->surface_count), ne = at_least_one(scene->element_count);
    size_t nm = at_least_one(scene->material_count);
    gpu_image_desc ad = gpu_scene_atlas_desc(scene);
    out->buried = calloc(ne, 1);
    out->enclosed = calloc(ne, 1);
    out->enclosed_m = calloc(ne, 1);
    xrad_status s;
    if (!out->buried || !out->enclosed || !out->enclosed_m) {
        gpu_scene_destroy(ctx, out);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "GPU scene: out of host memory");
    }
    uint32_t enclosed_count;
    if ((s = scene_find_enclosed(scene, out->enclosed, &enclosed_count, err)) ||
        (s = hemicube_clusters_build(scene, &out->layout, err))) {
        gpu_scene_destroy(ctx, out);
        return s;
    }
    out->cluster_count = out->layout.count;
    out->static_cluster_count = out->layout.static_count;
    out->vertex_count = out->layout.vertex_count;
    out->index_count = out->layout.index_count;
    out->static_index_count = out->layout.static_index_count;
    size_t nv = at_least_one(out->vertex_count), ni = at_least_one(out->index_count);
    uint64_t need = ns * sizeof(struct gpu_surface) + ne * sizeof(struct gpu_element) +
                    nm * sizeof(struct gpu_material) + 2 * ne * sizeof(vec4) +
                    nv * sizeof(struct gpu_hemicube_vertex) + ni * sizeof(uint32_t) +
                    ni / 3 * sizeof(struct gpu_hemicube_triangle) +
                    2 * ns * sizeof(struct gpu_bvh_node) + ns * sizeof(uint32_t) +
                    (uint64_t)at_least_one(scene->atlas_width) *
                        at_least_one(scene->atlas_height) * 16;
    if ((s = gpu_memory_check_budget(ctx, need, GPU_MEM_DEVICE, "scene data", err)) ||
        (s = gpu_buffer_create(ctx, ns * sizeof(struct gpu_surface), storage, GPU_MEM_DEVICE,
                               GPU_MEM_GEOMETRY, &out->surfaces, err)) ||
        (s = gpu_buffer_create(ctx, ne * sizeof(struct gpu_element), storage, GPU_MEM_DEVICE,
                               GPU_MEM_GEOMETRY, &out->elements, err)) ||
        (s = gpu_buffer_create(ctx, nm * sizeof(struct gpu_material), storage, GPU_MEM_DEVICE,
                               GPU_MEM_GEOMETRY, &out->materials, err)) ||
        (s = gpu_buffer_create(ctx, ne * sizeof(vec4), storage, GPU_MEM_DEVICE,
                               GPU_MEM_RADIOSITY, &out->B, err)) ||
        (s = gpu_buffer_create(ctx, ne * sizeof(vec4), storage, GPU_MEM_DEVICE,
                               GPU_MEM_RADIOSITY, &out->Bu, err)) ||
        (s = gpu_buffer_create(ctx, nv * sizeof(struct gpu_hemicube_vertex),
                               storage | VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, GPU_MEM_DEVICE,
                               GPU_MEM_GEOMETRY, &out->vertices, err)) ||
        (s = gpu_buffer_create(ctx, ni * sizeof(uint32_t),
                               storage | VK_BUFFER_USAGE_INDEX_BUFFER_BIT, GPU_MEM_DEVICE,
                               GPU_MEM_GEOMETRY, &out->indices, err)) ||
        (s = gpu_buffer_create(ctx, ni / 3 * sizeof(struct gpu_hemicube_triangle), storage,
                               GPU_MEM_DEVICE, GPU_MEM_GEOMETRY, &out->triangles, err)) ||
        (s = gpu_buffer_create(ctx, at_least_one(out->cluster_count) * sizeof(struct gpu_cluster),
                               storage, GPU_MEM_DEVICE, GPU_MEM_GEOMETRY, &out->clusters, err)) ||
        /* quad_bvh: at most 2 n - 1 nodes over n surfaces */
        (s = gpu_buffer_create(ctx, 2 * ns * sizeof(struct gpu_bvh_node), storage,
                               GPU_MEM_DEVICE, GPU_MEM_GEOMETRY, &out->bvh_nodes, err)) ||
        (s = gpu_buffer_create(ctx, ns * sizeof(uint32_t), storage, GPU_MEM_DEVICE,
                               GPU_MEM_GEOMETRY, &out->bvh_items, err)) ||
        (s = gpu_image_create(ctx, &ad, &out->atlas, err)) ||
        (s = upload_triangles(ctx, out, err)) || (s = upload_geometry(ctx, out, time, err)) ||
        (s = upload_materials(ctx, out, err)) ||
        (s = gpu_scene_reset(ctx, out, false, err)) || (s = init_atlas(ctx, out, err))) {
        gpu_scene_destroy(ctx, out);
        xrad_error_prefix(err, "GPU scene");
        return s;
    }
    return XRAD_OK;
}

xrad_status gpu_scene_fix_patches(struct xrad_context *ctx, gpu_scene *gs,
                                  const uint32_t *patches, xrad_error *err)
{
    size_t bytes = 3 * (size_t)(gs->surface_count ? gs->surface_count : 1) * sizeof(uint32_t);
    uint32_t *copy = malloc(bytes);
    if (!copy)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "GPU scene: out of host memory");
    memcpy(copy, patches, 3 * (size_t)gs->surface_count * sizeof(uint32_t));
    free(gs->fixed_patches);
    gs->fixed_patches = copy;
    return upload_geometry(ctx, gs, gs->time, err);
}

void gpu_scene_destroy(struct xrad_context *ctx, gpu_scene *gs)
{
    if (!gs)
        return;
    free(gs->fixed_patches);
    free(gs->buried);
    free(gs->enclosed);
    free(gs->enclosed_m);
    gpu_cmd_destroy(ctx, &gs->pose_cmd);
    gpu_buffer_destroy(ctx, &gs->pose_staging);
    gpu_image_destroy(ctx, &gs->atlas);
    gpu_buffer_destroy(ctx, &gs->vertices);
    gpu_buffer_destroy(ctx, &gs->indices);
    gpu_buffer_destroy(ctx, &gs->triangles);
    gpu_buffer_destroy(ctx, &gs->clusters);
    gpu_buffer_destroy(ctx, &gs->bvh_nodes);
    gpu_buffer_destroy(ctx, &gs->bvh_items);
    quad_bvh_free(&gs->bvh);
    hemicube_clusters_free(&gs->layout);
    gpu_buffer_destroy(ctx, &gs->Bu);
    gpu_buffer_destroy(ctx, &gs->B);
    gpu_buffer_destroy(ctx, &gs->materials);
    gpu_buffer_destroy(ctx, &gs->elements);
    gpu_buffer_destroy(ctx, &gs->surfaces);
    memset(gs, 0, sizeof(*gs));
}

xrad_status gpu_scene_pose(struct xrad_context *ctx, gpu_scene *gs, double time,
                           xrad_error *err)
{
    if (!isfinite(time))
        return xrad_fail(err, XRAD_ERROR_INPUT, "GPU scene: pose time is not finite");
    return upload_geometry(ctx, gs, time, err);
}

/* The ambient term of the unshot remainder (Cohen, Chen, Wallace and
 * Greenberg 1988, "A progressive refinement approach to fast radiosity
 * image generation", section 4): what the unshot radiosity Bu would add
 * if it spread evenly over an enclosure of the area-mean albedo,
 * rho_i x (sum Bu_j A_j / sum A_j) / (1 - rho_mean), per channel. Exact in
 * a closed uniform furnace, a first-order estimate elsewhere. Buried
 * elements (`buried`, gpu_scene.buried) take no light and are not part of
 * the enclosure: with the term, the bottom of cornell-large's box read 16
 * times the CPU reference's. */
static void add_ambient(const xrad_scene *scene, const uint8_t *buried, const vec4 *bu, vec4 *b,
                        uint32_t n)
{
    double area = 0, u[3] = {0, 0, 0}, rho[3] = {0, 0, 0};
    for (uint32_t i = 0; i < n; i++) {
        if (buried[i])
            continue;
        vec3 al = scene_element_albedo(scene, i);
        double a = scene->elements[i].area;
        area += a;
        u[0] += a * bu[i].x;
        u[1] += a * bu[i].y;
        u[2] += a * bu[i].z;
        rho[0] += a * al.x;
        rho[1] += a * al.y;
        rho[2] += a * al.z;
    }
    if (!(area > 0))
        return;
    double amb[3];
    for (int c = 0; c < 3; c++)
        amb[c] = u[c] / area / (1 - rho[c] / area);
    for (uint32_t i = 0; i < n; i++) {
        if (buried[i])
            continue;
        vec3 al = scene_element_albedo(scene, i);
        b[i].x += (float)(al.x * amb[0]);
        b[i].y += (float)(al.y * amb[1]);
        b[i].z += (float)(al.z * amb[2]);
    }
}

xrad_status gpu_scene_read(struct xrad_context *ctx, gpu_scene *gs, xrad_atlas *atlas,
                           bool ambient, xrad_error *err)
{
    const xrad_scene *scene = gs->scene;
    if (atlas->width != scene->atlas_width || atlas->height != scene->atlas_height ||
        (!atlas->rgba && atlas->width && atlas->height))
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: the atlas is %u x %u texels, the scene's is %u x %u", scene->path,
                         atlas->width, atlas->height, scene->atlas_width, scene->atlas_height);
    if (!gs->element_count)
        return XRAD_OK;
    size_t bytes = gs->element_count * sizeof(vec4);
    vec4 *b = malloc(bytes), *bu = ambient ? malloc(bytes) : NULL;
    if (!b || (ambient && !bu)) {
        free(b);
        free(bu);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of host memory reading B",
                         scene->path);
    }
    xrad_status s = gpu_readback_buffer(ctx, &gs->B, 0, b, bytes, err);
    if (!s && ambient && !(s = gpu_readback_buffer(ctx, &gs->Bu, 0, bu, bytes, err)))
        add_ambient(scene, gs->buried, bu, b, gs->element_count);
    if (!s) {
        memset(atlas->rgba, 0, (size_t)atlas->width * atlas->height * 4 * sizeof(float));
        for (uint32_t i = 0; i < gs->element_count; i++) {
            const element *el = &scene->elements[i];
            float *t = &atlas->rgba[((size_t)el->texel_y * atlas->width + el->texel_x) * 4];
            t[0] = b[i].x;
            t[1] = b[i].y;
            t[2] = b[i].z;
            t[3] = 1.0f;
        }
    }
    free(b);
    free(bu);
    return s;
}
