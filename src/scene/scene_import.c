/* Model files through assimp's C API: glTF 2.0 (.gltf, .glb), OBJ with its
 * MTL, PLY -> the scene builder. Every mesh instance of the node tree
 * becomes a triangle mesh of the current object, its positions taken
 * through the node's transform (metres, glTF's unit); materials give
 * albedo and emission; the first camera (or the one named) the scene's.
 * What a file has that xrad does not model is listed as warnings, one
 * line per kind, never dropped silently (scenes/README.md "Model files"). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <assimp/cimport.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "core/error.h"
#include "scene/scene.h"
#include "scene/scene_internal.h"

#define PI 3.14159265358979323846

/* Albedo must stay below 1 (scene.h); a glTF base colour of 1 becomes this. */
#define ALBEDO_MAX 0.999

typedef struct import_ctx {
    xrad_scene_builder *b;
    const char *path;
    const struct aiScene *ai;
    const scene_import_desc *desc;
    xrad_error *err;
    uint32_t *material_index; /* per assimp material: builder index, or UINT32_MAX */
    uint32_t instances;       /* mesh instances added */
    uint32_t triangles;
    /* What is ignored, counted for the warnings. */
    uint32_t textured, metallic, transmissive, clamped, skinned, morphed, non_triangle;
    char clamped_name[64];
} import_ctx;

bool scene_import_supported(const char *path)
{
    const char *dot = strrchr(path, '.');
    if (!dot)
        return false;
    static const char *const ext[] = {".gltf", ".glb", ".obj", ".ply"};
    for (size_t k = 0; k < sizeof(ext) / sizeof(ext[0]); k++)
        if (!strcasecmp(dot, ext[k]))
            return true;
    return false;
}

static float color_max(struct aiColor4D c)
{
    return fmaxf(c.r, fmaxf(c.g, c.b));
}

/* Builder index of assimp material m, added on first use. */
static xrad_status import_material(import_ctx *c, uint32_t m, uint32_t *out)
{
    if (c->material_index[m] != UINT32_MAX) {
        *out = c->material_index[m];
        return XRAD_OK;
    }
    const struct aiMaterial *am = c->ai->mMaterials[m];
    struct aiString name;
    char mname[SCENE_NAME_MAX];
    if (aiGetMaterialString(am, AI_MATKEY_NAME, &name) == aiReturn_SUCCESS && name.length)
        snprintf(mname, sizeof(mname), "%.20s/%.40s", c->desc->prefix, name.data);
    else
        snprintf(mname, sizeof(mname), "%.20s/material%u", c->desc->prefix, m);

    /* glTF's baseColorFactor; OBJ's Kd (assimp's diffuse) otherwise. */
    struct aiColor4D base = {0.8f, 0.8f, 0.8f, 1};
    if (aiGetMaterialColor(am, AI_MATKEY_BASE_COLOR, &base) != aiReturn_SUCCESS)
        aiGetMaterialColor(am, AI_MATKEY_COLOR_DIFFUSE, &base);
    double albedo[3] = {base.r, base.g, base.b};
    bool clamped = false;
    for (int k = 0; k < 3; k++) {
        if (!(albedo[k] >= 0))
            albedo[k] = 0;
        if (albedo[k] > ALBEDO_MAX) {
            albedo[k] = ALBEDO_MAX;
            clamped = true;
        }
    }
    if (clamped && c->clamped++ == 0)
        snprintf(c->clamped_name, sizeof(c->clamped_name), "%.40s (%.3g)", mname,
                 color_max(base));

    /* emissiveFactor x KHR_materials_emissive_strength, a radiance in
     * W/(m^2 sr); a Lambertian emitter's exitance is pi times it. */
    struct aiColor4D em = {0, 0, 0, 1};
    aiGetMaterialColor(am, AI_MATKEY_COLOR_EMISSIVE, &em);
    float strength = 1;
    aiGetMaterialFloatArray(am, AI_MATKEY_EMISSIVE_INTENSITY, &strength, NULL);
    double emission[3] = {PI * em.r * strength, PI * em.g * strength, PI * em.b * strength};
    for (int k = 0; k < 3; k++)
        if (!(emission[k] >= 0))
            emission[k] = 0;

    static const enum aiTextureType textured[] = {
        aiTextureType_DIFFUSE,  aiTextureType_BASE_COLOR, aiTextureType_EMISSIVE,
        aiTextureType_NORMALS,  aiTextureType_EMISSION_COLOR, aiTextureType_METALNESS,
        aiTextureType_DIFFUSE_ROUGHNESS, aiTextureType_AMBIENT_OCCLUSION, aiTextureType_UNKNOWN};
    for (size_t k = 0; k < sizeof(textured) / sizeof(textured[0]); k++)
        if (aiGetMaterialTextureCount(am, textured[k])) {
            c->textured++;
            break;
        }
    float metal = 0, transmission = 0;
    if (aiGetMaterialFloatArray(am, AI_MATKEY_METALLIC_FACTOR, &metal, NULL) ==
            aiReturn_SUCCESS &&
        metal > 0)
        c->metallic++;
    if (aiGetMaterialFloatArray(am, AI_MATKEY_TRANSMISSION_FACTOR, &transmission, NULL) ==
            aiReturn_SUCCESS &&
        transmission > 0)
        c->transmissive++;

    xrad_material_desc md = {.name = mname};
    memcpy(md.albedo, albedo, sizeof(albedo));
    memcpy(md.emission, emission, sizeof(emission));
    xrad_status st = xrad_scene_builder_add_material(c->b, &md, out, c->err);
    if (!st)
        c->material_index[m] = *out;
    return st;
}

static struct aiMatrix4x4 mul(const struct aiMatrix4x4 *a, const struct aiMatrix4x4 *b)
{
    const float *x = &a->a1, *y = &b->a1;
    struct aiMatrix4x4 r;
    float *z = &r.a1;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            float s = 0;
            for (int k = 0; k < 4; k++)
                s += x[4 * i + k] * y[4 * k + j];
            z[4 * i + j] = s;
        }
    return r;
}

static void apply(const struct aiMatrix4x4 *m, struct aiVector3D v, float w, float out[3])
{
    out[0] = m->a1 * v.x + m->a2 * v.y + m->a3 * v.z + m->a4 * w;
    out[1] = m->b1 * v.x + m->b2 * v.y + m->b3 * v.z + m->b4 * w;
    out[2] = m->c1 * v.x + m->c2 * v.y + m->c3 * v.z + m->c4 * w;
}

static double det3(const struct aiMatrix4x4 *m)
{
    return m->a1 * ((double)m->b2 * m->c3 - (double)m->b3 * m->c2) -
           m->a2 * ((double)m->b1 * m->c3 - (double)m->b3 * m->c1) +
           m->a3 * ((double)m->b1 * m->c2 - (double)m->b2 * m->c1);
}

static xrad_status add_mesh(import_ctx *c, const struct aiNode *node,
                            const struct aiMatrix4x4 *world, const struct aiMesh *mesh)
{
    if (mesh->mNumBones)
        c->skinned++;
    if (mesh->mNumAnimMeshes)
        c->morphed++;
    if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || mesh->mNumVertices == 0) {
        c->non_triangle++;
        return XRAD_OK;
    }
    uint32_t nt = 0;
    for (uint32_t f = 0; f < mesh->mNumFaces; f++)
        nt += mesh->mFaces[f].mNumIndices == 3;
    c->non_triangle += nt < mesh->mNumFaces;
    if (nt == 0)
        return XRAD_OK;
    float *pos = malloc(3ull * mesh->mNumVertices * sizeof(float));
    uint32_t *idx = malloc(3ull * nt * sizeof(uint32_t));
    if (!pos || !idx) {
        free(pos);
        free(idx);
        return xrad_fail(c->err, XRAD_ERROR_SYSTEM, "%s: out of memory", c->path);
    }
    for (uint32_t v = 0; v < mesh->mNumVertices; v++)
        apply(world, mesh->mVertices[v], 1, &pos[3 * v]);
    /* A mirroring transform turns the winding, and so the front side. */
    bool mirror = det3(world) < 0;
    uint32_t t = 0;
    for (uint32_t f = 0; f < mesh->mNumFaces; f++) {
        const struct aiFace *face = &mesh->mFaces[f];
        if (face->mNumIndices != 3)
            continue;
        idx[3 * t] = face->mIndices[0];
        idx[3 * t + 1] = face->mIndices[mirror ? 2 : 1];
        idx[3 * t + 2] = face->mIndices[mirror ? 1 : 2];
        t++;
    }
    uint32_t mat = c->desc->material;
    xrad_status st = XRAD_OK;
    if (mat == UINT32_MAX)
        st = import_material(c, mesh->mMaterialIndex, &mat);
    char name[SCENE_NAME_MAX];
    const char *base = c->desc->name           ? c->desc->name
                       : node->mName.length ? node->mName.data
                                            : "node";
    snprintf(name, sizeof(name), "%.40s.%u", base, c->instances++);
    xrad_mesh_desc md = {.name = name,
                         .positions = pos,
                         .vertex_count = mesh->mNumVertices,
                         .indices = idx,
                         .triangle_count = nt,
                         .material = mat,
                         .density = c->desc->density};
    if (!st)
        st = xrad_scene_builder_add_mesh(c->b, &md, c->err);
    c->triangles += nt;
    free(pos);
    free(idx);
    return st;
}

static xrad_status add_node(import_ctx *c, const struct aiNode *node,
                            const struct aiMatrix4x4 *parent)
{
    struct aiMatrix4x4 world = mul(parent, &node->mTransformation);
    for (uint32_t k = 0; k < node->mNumMeshes; k++) {
        xrad_status st = add_mesh(c, node, &world, c->ai->mMeshes[node->mMeshes[k]]);
        if (st)
            return st;
    }
    for (uint32_t k = 0; k < node->mNumChildren; k++) {
        xrad_status st = add_node(c, node->mChildren[k], &world);
        if (st)
            return st;
    }
    return XRAD_OK;
}

/* The node named `name` and its world transform (of its parent chain). */
static const struct aiNode *find_node(const struct aiNode *n, const char *name,
                                      const struct aiMatrix4x4 *parent, struct aiMatrix4x4 *out)
{
    if (!strcmp(n->mName.data, name)) {
        *out = *parent;
        return n;
    }
    struct aiMatrix4x4 world = mul(parent, &n->mTransformation);
    for (uint32_t k = 0; k < n->mNumChildren; k++) {
        const struct aiNode *f = find_node(n->mChildren[k], name, &world, out);
        if (f)
            return f;
    }
    return NULL;
}

static xrad_status take_camera(import_ctx *c)
{
    const struct aiScene *ai = c->ai;
    const char *want = c->desc->camera;
    const struct aiCamera *cam = NULL;
    for (uint32_t k = 0; k < ai->mNumCameras && !cam; k++)
        if (!want || !strcmp(ai->mCameras[k]->mName.data, want))
            cam = ai->mCameras[k];
    if (!cam) {
        if (!want)
            return XRAD_OK;
        char list[256] = "";
        size_t len = 0;
        for (uint32_t k = 0; k < ai->mNumCameras && len < sizeof(list); k++)
            len += (size_t)snprintf(list + len, sizeof(list) - len, "%s'%s'", k ? ", " : "",
                                    ai->mCameras[k]->mName.data);
        return xrad_fail(c->err, XRAD_ERROR_INPUT, "%s: no camera named '%s' (the file has %s)",
                         c->path, want, ai->mNumCameras ? list : "none");
    }
    struct aiMatrix4x4 identity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, world;
    const struct aiNode *node = find_node(ai->mRootNode, cam->mName.data, &identity, &world);
    if (node)
        world = mul(&world, &node->mTransformation);
    else
        world = identity;
    float pos[3], dir[3], up[3];
    apply(&world, cam->mPosition, 1, pos);
    apply(&world, cam->mLookAt, 0, dir);
    apply(&world, cam->mUp, 0, up);
    /* camera.h calls mHorizontalFOV a half angle, but assimp's glTF 2
     * importer stores the whole horizontal angle made from yfov and the
     * aspect (2 atan(tan(yfov / 2) aspect); yfov x aspect before 5.3):
     * undone here, exact at aspect 1. */
    double aspect = cam->mAspect > 0 ? cam->mAspect : 1;
    double fov = 2 * atan(tan(0.5 * cam->mHorizontalFOV) / aspect) * 180 / PI;
    xrad_camera_desc cd = {.fov_degrees = fov};
    for (int k = 0; k < 3; k++) {
        cd.position[k] = pos[k];
        cd.look_at[k] = pos[k] + dir[k];
        cd.up[k] = up[k];
    }
    if (aspect != 1) {
        cd.width = aspect > 1 ? 512 : (uint32_t)lround(512 * aspect);
        cd.height = aspect > 1 ? (uint32_t)lround(512 / aspect) : 512;
    }
    xrad_status st = xrad_scene_builder_set_camera(c->b, &cd, c->err);
    if (st)
        xrad_error_prefix(c->err, "%s: camera '%s': ", c->path, cam->mName.data);
    return st;
}

xrad_status scene_import_model(xrad_scene_builder *b, const char *path,
                               const scene_import_desc *desc, xrad_error *err)
{
    if (!scene_import_supported(path))
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: not a model file xrad reads (.gltf, .glb, .obj, .ply)", path);
    FILE *f = fopen(path, "rb");
    if (!f)
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: cannot open", path);
    fclose(f);
    /* Triangulate polygons, weld vertices, sort points and lines out of the
     * triangle meshes; the node tree and its transforms are kept. */
    const struct aiScene *ai =
        aiImportFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                               aiProcess_SortByPType | aiProcess_ValidateDataStructure);
    if (!ai || !ai->mRootNode)
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: cannot import: %s", path,
                         aiGetErrorString());
    import_ctx c = {.b = b, .path = path, .ai = ai, .desc = desc, .err = err};
    c.material_index = malloc((ai->mNumMaterials + 1) * sizeof(uint32_t));
    xrad_status st = XRAD_OK;
    if (!c.material_index)
        st = xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory", path);
    for (uint32_t m = 0; !st && m < ai->mNumMaterials; m++)
        c.material_index[m] = UINT32_MAX;

    struct aiMatrix4x4 identity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, parent;
    const struct aiNode *root = ai->mRootNode;
    if (!st && desc->node) {
        root = find_node(ai->mRootNode, desc->node, &identity, &parent);
        if (!root)
            st = xrad_fail(err, XRAD_ERROR_INPUT, "%s: no node named '%s'", path, desc->node);
    } else {
        parent = identity;
    }
    if (!st)
        st = add_node(&c, root, &parent);
    if (!st && c.triangles == 0)
        st = xrad_fail(err, XRAD_ERROR_INPUT, "%s%s%s: no triangles", path,
                       desc->node ? ": node " : "", desc->node ? desc->node : "");
    if (!st && desc->take_camera)
        st = take_camera(&c);
    if (!st) {
        if (c.textured)
            scene_builder_warn(b, "%s: %u material(s) with textures: ignored (the colour "
                               "factors alone are used)", path, c.textured);
        if (c.metallic)
            scene_builder_warn(b, "%s: %u material(s) metallic: ignored (diffuse only)", path,
                               c.metallic);
        if (c.transmissive)
            scene_builder_warn(b, "%s: %u material(s) with transmission: ignored (opaque)",
                               path, c.transmissive);
        if (c.clamped)
            scene_builder_warn(b, "%s: %u material(s) with a base colour >= 1, clamped to %g "
                               "(first: %s)", path, c.clamped, ALBEDO_MAX, c.clamped_name);
        if (c.skinned)
            scene_builder_warn(b, "%s: %u skinned mesh(es): drawn in their bind pose", path,
                               c.skinned);
        if (c.morphed)
            scene_builder_warn(b, "%s: %u mesh(es) with morph targets: the base shape is used",
                               path, c.morphed);
        if (c.non_triangle)
            scene_builder_warn(b, "%s: %u mesh(es) of points or lines: ignored", path,
                               c.non_triangle);
        if (ai->mNumAnimations)
            scene_builder_warn(b, "%s: %u animation(s): ignored (animate the object in a "
                               "scene file)", path, ai->mNumAnimations);
        if (ai->mNumLights)
            scene_builder_warn(b, "%s: %u punctual light(s): ignored (emission comes from "
                               "emissive materials)", path, ai->mNumLights);
        if (!desc->take_camera && ai->mNumCameras)
            scene_builder_warn(b, "%s: %u camera(s): ignored (the scene file's camera is used)",
                               path, ai->mNumCameras);
    }
    free(c.material_index);
    aiReleaseImport(ai);
    return st;
}
