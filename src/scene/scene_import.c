/* Model files through assimp's C API: glTF 2.0 (.gltf, .glb), OBJ with its
 * MTL, PLY -> the scene builder. Every mesh instance of the node tree
 * becomes a triangle mesh of the current object, its positions taken
 * through the node's transform (metres, glTF's unit); materials give
 * albedo (the base colour factor times its texture, an albedo map with the
 * mesh's texture coordinates: scene_texture.h) and emission; the first
 * camera (or the one named) the scene's.
 * What a file has that xrad does not model is listed as warnings, one
 * line per kind, never dropped silently (scenes/README.md "Model files").
 * Bad input is refused naming the file and the node and mesh at fault;
 * what assimp would abort, hang or over-allocate on is refused before it
 * gets there (faces_sound, ply_check; tests/fuzz/README.md). */
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <assimp/cfileio.h>
#include <assimp/cimport.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/version.h>
#include <cjson/cJSON.h>

#include "core/error.h"
#include "scene/scene.h"
#include "scene/scene_internal.h"
#include "scene/scene_texture.h"

#define PI 3.14159265358979323846

/* Albedo must stay below 1 (scene.h); a glTF base colour of 1 becomes this. */
#define ALBEDO_MAX 0.999

/* The node tree is walked recursively: deeper than this is refused rather
 * than risking the stack (no model nests anywhere near it). */
#define NODE_DEPTH_MAX 256u

/* A PLY header longer than this is refused: the counts in it must be
 * checked before assimp reserves memory for them (ply_check). */
#define PLY_HEADER_MAX (64u << 10)

/* assimp's own warnings passed on, distinct lines, at most this many. */
#define ASSIMP_LINES 8
#define ASSIMP_LINE_MAX 200

typedef struct import_log {
    char line[ASSIMP_LINES][ASSIMP_LINE_MAX];
    uint32_t lines, more;
} import_log;

typedef struct import_ctx {
    xrad_scene_builder *b;
    const char *path;
    const struct aiScene *ai;
    const scene_import_desc *desc;
    xrad_error *err;
    uint32_t *material_index; /* per assimp material: builder index, or UINT32_MAX */
    uint32_t *map_channel;    /* per assimp material: texture coordinate set of its albedo
                                 map, or UINT32_MAX (none) */
    bool files;               /* maps may be read from files beside the model */
    uint32_t instances;       /* mesh instances added */
    uint32_t triangles;
    uint32_t surfaces_before; /* the builder's surfaces before this file */
    /* What is ignored, counted for the warnings, and where it was first. */
    uint32_t textured, metallic, transmissive, clamped, skinned, morphed, non_triangle;
    uint32_t zero_area, maps, map_failed;
    char clamped_name[64];
    char map_failed_why[320];
    char non_triangle_where[160], zero_area_where[160];
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

/* A name from the file, fit for a message or the builder (which refuses
 * control characters): at most len - 1 bytes of it, control characters
 * as '?'. Returns out. */
static const char *clean(const char *in, char *out, size_t len)
{
    size_t n = 0;
    for (; in[n] && n + 1 < len; n++)
        out[n] = (unsigned char)in[n] < 0x20 || in[n] == 0x7f ? '?' : in[n];
    out[n] = '\0';
    return out;
}

/* The texture `tpath` of material `mname` (a base colour texture, glTF
 * baseColorTexture or OBJ map_Kd, sRGB; a normal texture linear) decoded
 * into *rgb: embedded ("*N", a .glb's images) or a file beside the model. */
static xrad_status load_map(import_ctx *c, const char *tpath, const char *mname, bool srgb,
                            float **rgb, uint32_t *w, uint32_t *h)
{
    char what[700];
    snprintf(what, sizeof(what), "%s: material '%s': texture '%.200s'", c->path, mname, tpath);
    if (tpath[0] == '*') {
        char *end;
        unsigned long k = strtoul(tpath + 1, &end, 10);
        if (*end || end == tpath + 1 || k >= c->ai->mNumTextures || !c->ai->mTextures[k])
            return xrad_fail(c->err, XRAD_ERROR_INPUT, "%s: no such embedded image (%u)", what,
                             c->ai->mNumTextures);
        const struct aiTexture *t = c->ai->mTextures[k];
        if (t->mHeight == 0) /* compressed: mWidth bytes of a PNG, a JPEG */
            return scene_texture_decode(t->pcData, t->mWidth, srgb, what, rgb, w, h, c->err);
        if (t->mWidth > SCENE_TEXTURE_MAX_SIDE || t->mHeight > SCENE_TEXTURE_MAX_SIDE ||
            (uint64_t)t->mWidth * t->mHeight > SCENE_TEXTURE_MAX_TEXELS)
            return xrad_fail(c->err, XRAD_ERROR_INPUT, "%s: %u x %u texels, more than %u on a "
                             "side or %u in all", what, t->mWidth, t->mHeight,
                             SCENE_TEXTURE_MAX_SIDE, SCENE_TEXTURE_MAX_TEXELS);
        size_t n = (size_t)t->mWidth * t->mHeight;
        float *out = malloc(3 * n * sizeof(float));
        uint8_t *v = malloc(3 * n);
        if (!out || !v) {
            free(out);
            free(v);
            return xrad_fail(c->err, XRAD_ERROR_SYSTEM, "%s: out of memory", what);
        }
        /* Raw BGRA8. */
        for (size_t p = 0; p < n; p++) {
            v[3 * p] = t->pcData[p].r;
            v[3 * p + 1] = t->pcData[p].g;
            v[3 * p + 2] = t->pcData[p].b;
        }
        scene_texture_from_8bit(v, 3 * n, srgb, out);
        free(v);
        *rgb = out;
        *w = t->mWidth;
        *h = t->mHeight;
        return XRAD_OK;
    }
    if (!c->files)
        return xrad_fail(c->err, XRAD_ERROR_INPUT, "%s: a file, not read for a model in memory",
                         what);
    /* Relative to the model's folder (glTF URIs, MTL paths). */
    char full[1024];
    const char *slash = strrchr(c->path, '/');
    if (tpath[0] == '/' || !slash)
        snprintf(full, sizeof(full), "%s", tpath);
    else
        snprintf(full, sizeof(full), "%.*s/%s", (int)(slash - c->path), c->path, tpath);
    char *data = NULL;
    size_t size = 0;
    xrad_status st = scene_read_file(full, 256u << 20, &data, &size, c->err);
    if (!st)
        st = scene_texture_decode(data, size, srgb, what, rgb, w, h, c->err);
    else
        xrad_error_prefix(c->err, "%s", what);
    free(data);
    return st;
}

/* Material am's first texture of `type`, if any, into *image (rgb
 * malloc'd, NULL where there is none) and its coordinate set into
 * *channel. One that cannot be read is left out with a warning (the
 * first such reason kept); only running out of memory fails. */
static xrad_status import_texture(import_ctx *c, const struct aiMaterial *am,
                                  enum aiTextureType type, bool srgb, const char *mname,
                                  xrad_image_desc *image, unsigned int *channel)
{
    struct aiString tpath = {0};
    *image = (xrad_image_desc){0};
    if (c->desc->material != UINT32_MAX || !aiGetMaterialTextureCount(am, type) ||
        aiGetMaterialTexture(am, type, 0, &tpath, NULL, channel, NULL, NULL, NULL, NULL) !=
            aiReturn_SUCCESS)
        return XRAD_OK;
    xrad_error why = {0};
    xrad_error *keep = c->err;
    c->err = &why;
    float *texels = NULL;
    xrad_status ms =
        *channel < AI_MAX_NUMBER_OF_TEXTURECOORDS
            ? load_map(c, tpath.data, mname, srgb, &texels, &image->width, &image->height)
            : xrad_fail(&why, XRAD_ERROR_INPUT, "%s: material '%s': texture coordinate set %u",
                        c->path, mname, *channel);
    c->err = keep;
    if (ms == XRAD_ERROR_SYSTEM) {
        *c->err = why;
        return ms;
    }
    if (ms) {
        if (c->map_failed++ == 0)
            snprintf(c->map_failed_why, sizeof(c->map_failed_why), "%s", why.message);
        *image = (xrad_image_desc){0};
        return XRAD_OK;
    }
    image->rgb = texels;
    return XRAD_OK;
}

/* glTF's normalTexture.scale (glTF 2.0, "normalTextureInfo"): a texel's
 * normal is normalize((2 rgb - 1) x (scale, scale, 1)). The texels are
 * rewritten to encode that normal, so that the map reads as the scaled one
 * wherever it is used (scene_texture_normal). */
static void scale_normal_map(const struct aiMaterial *am, xrad_image_desc *normals)
{
    ai_real scale = 1;
    if (aiGetMaterialFloatArray(am, "$tex.scale", aiTextureType_NORMALS, 0, &scale, NULL) !=
            aiReturn_SUCCESS ||
        scale == 1 || !isfinite(scale))
        return;
    float *t = (float *)normals->rgb;
    for (size_t i = 0; i < (size_t)normals->width * normals->height; i++, t += 3) {
        double x = (2.0 * t[0] - 1) * scale, y = (2.0 * t[1] - 1) * scale, z = 2.0 * t[2] - 1;
        double len = sqrt(x * x + y * y + z * z);
        if (!(len > 0))
            continue; /* (0, 0, 0): the map reader's flat fallback (scene_texture_normal) */
        t[0] = (float)(0.5 * (x / len + 1));
        t[1] = (float)(0.5 * (y / len + 1));
        t[2] = (float)(0.5 * (z / len + 1));
    }
}

/* Builder index of assimp material m, added on first use. */
static xrad_status import_material(import_ctx *c, uint32_t m, uint32_t *out)
{
    if (c->material_index[m] != UINT32_MAX) {
        *out = c->material_index[m];
        return XRAD_OK;
    }
    const struct aiMaterial *am = c->ai->mMaterials[m];
    struct aiString name = {0};
    char mname[SCENE_NAME_MAX];
    char own[41];
    if (aiGetMaterialString(am, AI_MATKEY_NAME, &name) == aiReturn_SUCCESS && name.length)
        snprintf(mname, sizeof(mname), "%.20s/%s", c->desc->prefix,
                 clean(name.data, own, sizeof(own)));
    else
        snprintf(mname, sizeof(mname), "%.20s/material%u", c->desc->prefix, m);
    /* glTF lets two materials share a name; the builder does not. */
    for (uint32_t k = 0; k < m && name.length; k++) {
        struct aiString other;
        char theirs[41];
        if (c->material_index[k] != UINT32_MAX &&
            aiGetMaterialString(c->ai->mMaterials[k], AI_MATKEY_NAME, &other) ==
                aiReturn_SUCCESS &&
            !strcmp(clean(other.data, theirs, sizeof(theirs)), own)) {
            size_t len = strlen(mname);
            snprintf(mname + len, sizeof(mname) - len, "#%u", m);
            break;
        }
    }

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

    /* The base colour texture becomes an albedo map (glTF puts it under
     * both BASE_COLOR and DIFFUSE); one that cannot be read leaves the
     * factor alone, with a warning. */
    enum aiTextureType base_type = aiGetMaterialTextureCount(am, aiTextureType_BASE_COLOR)
                                       ? aiTextureType_BASE_COLOR
                                       : aiTextureType_DIFFUSE;
    xrad_image_desc map = {0}, normals = {0};
    unsigned int channel = 0, normal_channel = 0;
    xrad_status st;
    if ((st = import_texture(c, am, base_type, true, mname, &map, &channel)) ||
        (st = import_texture(c, am, aiTextureType_NORMALS, false, mname, &normals,
                             &normal_channel))) {
        free((void *)map.rgb);
        return st;
    }
    if (normals.rgb)
        scale_normal_map(am, &normals);
    if (map.rgb && normals.rgb && channel != normal_channel) {
        /* One coordinate set per material (xrad_mesh_desc.uvs). */
        if (c->map_failed++ == 0)
            snprintf(c->map_failed_why, sizeof(c->map_failed_why),
                     "%s: material '%s': normal texture on coordinate set %u, the base colour "
                     "on %u: the normal texture is left out",
                     c->path, mname, normal_channel, channel);
        free((void *)normals.rgb);
        normals = (xrad_image_desc){0};
    }
    if (map.rgb || normals.rgb) {
        c->map_channel[m] = map.rgb ? channel : normal_channel;
        c->maps += (map.rgb != NULL) + (normals.rgb != NULL);
    }
    /* Textures xrad does not model (emissive, metal-roughness,
     * occlusion), counted for a warning. */
    static const enum aiTextureType textured[] = {
        aiTextureType_EMISSIVE,          aiTextureType_EMISSION_COLOR,    aiTextureType_METALNESS,
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

    xrad_material_desc md = {.name = mname,
                             .albedo_map = map.rgb ? &map : NULL,
                             .normal_map = normals.rgb ? &normals : NULL};
    memcpy(md.albedo, albedo, sizeof(albedo));
    memcpy(md.emission, emission, sizeof(emission));
    st = xrad_scene_builder_add_material(c->b, &md, out, c->err);
    free((void *)map.rgb);
    free((void *)normals.rgb);
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

/* "node 'N': mesh 'M'" for messages: assimp names the mesh of a glTF
 * primitive after its glTF mesh ("M", or "M-K" for primitive K of several);
 * a nameless one is called by its index. */
static void mesh_where(const import_ctx *c, const struct aiNode *node, uint32_t mi, char *out,
                       size_t len)
{
    const struct aiMesh *mesh = c->ai->mMeshes[mi];
    char mname[80], a[61], b[61];
    if (mesh->mName.length)
        snprintf(mname, sizeof(mname), "'%s'", clean(mesh->mName.data, a, sizeof(a)));
    else
        snprintf(mname, sizeof(mname), "#%u", mi);
    snprintf(out, len, "node '%s': mesh %s", clean(node->mName.data, b, sizeof(b)), mname);
}

static bool matrix_finite(const struct aiMatrix4x4 *m)
{
    const float *x = &m->a1;
    for (int k = 0; k < 16; k++)
        if (!isfinite(x[k]))
            return false;
    return true;
}

static xrad_status add_mesh(import_ctx *c, const struct aiNode *node,
                            const struct aiMatrix4x4 *world, uint32_t mi)
{
    char where[160];
    mesh_where(c, node, mi, where, sizeof(where));
    const struct aiMesh *mesh = c->ai->mMeshes[mi];
    if (mesh->mNumBones)
        c->skinned++;
    if (mesh->mNumAnimMeshes)
        c->morphed++;
    uint32_t nt = 0;
    if ((mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) && mesh->mNumVertices && mesh->mFaces)
        for (uint32_t f = 0; f < mesh->mNumFaces; f++)
            nt += mesh->mFaces[f].mNumIndices == 3;
    /* aiProcess_SortByPType leaves points and lines in meshes of their own. */
    if (nt < mesh->mNumFaces && c->non_triangle++ == 0)
        snprintf(c->non_triangle_where, sizeof(c->non_triangle_where), "%s", where);
    if (nt == 0)
        return XRAD_OK;
    /* Refused before allocating: the builder takes at most this many
     * triangles a mesh, and two triangles make at least one surface. */
    if (nt > SCENE_MAX_SURFACES)
        return xrad_fail(c->err, XRAD_ERROR_INPUT, "%s: %s: %u triangles, more than %u",
                         c->path, where, nt, SCENE_MAX_SURFACES);
    if (c->triangles + (uint64_t)nt > 2ull * SCENE_MAX_SURFACES)
        return xrad_fail(c->err, XRAD_ERROR_INPUT,
                         "%s: %s: more than %u triangles in all the mesh instances (a scene "
                         "has at most %u surfaces)", c->path, where, 2 * SCENE_MAX_SURFACES,
                         SCENE_MAX_SURFACES);
    uint32_t mat = c->desc->material;
    if (mat == UINT32_MAX && mesh->mMaterialIndex >= c->ai->mNumMaterials)
        return xrad_fail(c->err, XRAD_ERROR_INPUT, "%s: %s: material %u does not exist (%u "
                         "materials)", c->path, where, mesh->mMaterialIndex,
                         c->ai->mNumMaterials);
    /* ValidateDataStructure checks the indices too; checked again here,
     * as the builder would, so that the message names the file's mesh. */
    for (uint32_t f = 0, t = 0; f < mesh->mNumFaces; f++) {
        const struct aiFace *face = &mesh->mFaces[f];
        if (face->mNumIndices != 3)
            continue;
        for (int k = 0; k < 3; k++)
            if (face->mIndices[k] >= mesh->mNumVertices)
                return xrad_fail(c->err, XRAD_ERROR_INPUT,
                                 "%s: %s: triangle %u: vertex index %u is out of range (%u "
                                 "vertices)", c->path, where, t, face->mIndices[k],
                                 mesh->mNumVertices);
        t++;
    }
    for (uint32_t v = 0; v < mesh->mNumVertices; v++) {
        struct aiVector3D p = mesh->mVertices[v];
        if (!(isfinite(p.x) && isfinite(p.y) && isfinite(p.z)))
            return xrad_fail(c->err, XRAD_ERROR_INPUT, "%s: %s: vertex %u is not finite (%g, "
                             "%g, %g)", c->path, where, v, p.x, p.y, p.z);
    }

    float *pos = malloc(3ull * mesh->mNumVertices * sizeof(float));
    uint32_t *idx = malloc(3ull * nt * sizeof(uint32_t));
    if (!pos || !idx) {
        free(pos);
        free(idx);
        return xrad_fail(c->err, XRAD_ERROR_SYSTEM, "%s: out of memory", c->path);
    }
    xrad_status st = XRAD_OK;
    for (uint32_t v = 0; v < mesh->mNumVertices && !st; v++) {
        float *q = &pos[3 * v];
        apply(world, mesh->mVertices[v], 1, q);
        double m = fmax(fabs(q[0]), fmax(fabs(q[1]), fabs(q[2])));
        if (!(m <= SCENE_MAX_COORD))
            st = xrad_fail(c->err, XRAD_ERROR_INPUT, "%s: %s: vertex %u lies at (%g, %g, %g) m "
                           "through the node transforms, beyond %g m", c->path, where, v, q[0],
                           q[1], q[2], SCENE_MAX_COORD);
    }
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
    bool file_material = mat == UINT32_MAX;
    if (!st && file_material)
        st = import_material(c, mesh->mMaterialIndex, &mat);
    /* The mapped material's texture coordinates, v up as the builder
     * takes them (assimp turns glTF's); set 0 for a scene file's material
     * in place of the file's (the builder reads them if it has a map). */
    float *uvs = NULL;
    uint32_t channel = file_material ? c->map_channel[mesh->mMaterialIndex] : 0;
    if (!st && channel != UINT32_MAX && (file_material || mesh->mTextureCoords[0])) {
        if (!mesh->mTextureCoords[channel])
            st = xrad_fail(c->err, XRAD_ERROR_INPUT,
                           "%s: %s: its material's base colour texture reads texture "
                           "coordinate set %u, which the mesh does not have",
                           c->path, where, channel);
        else if (!(uvs = malloc(2ull * mesh->mNumVertices * sizeof(float))))
            st = xrad_fail(c->err, XRAD_ERROR_SYSTEM, "%s: out of memory", c->path);
        for (uint32_t v = 0; uvs && v < mesh->mNumVertices; v++) {
            uvs[2 * v] = mesh->mTextureCoords[channel][v].x;
            uvs[2 * v + 1] = mesh->mTextureCoords[channel][v].y;
        }
    }
    char name[SCENE_NAME_MAX];
    char own[41];
    const char *base = c->desc->name           ? c->desc->name
                       : node->mName.length ? clean(node->mName.data, own, sizeof(own))
                                            : "node";
    snprintf(name, sizeof(name), "%.40s.%u", base, c->instances++);
    xrad_mesh_desc md = {.name = name,
                         .positions = pos,
                         .vertex_count = mesh->mNumVertices,
                         .indices = idx,
                         .triangle_count = nt,
                         .material = mat,
                         .density = c->desc->density,
                         .uvs = uvs};
    xrad_scene *sc = scene_builder_scene(c->b);
    uint32_t skipped = sc ? sc->skipped_triangles : 0;
    if (!st) {
        st = xrad_scene_builder_add_mesh(c->b, &md, c->err);
        /* Placed in a scene file, the builder's message names the scene
         * file; the model file is said here. */
        if (st && !strstr(c->err->message, c->path))
            xrad_error_prefix(c->err, "%s: %s", c->path, where);
    }
    if (!st && sc && sc->skipped_triangles > skipped) {
        if (c->zero_area == 0)
            snprintf(c->zero_area_where, sizeof(c->zero_area_where), "%s", where);
        c->zero_area += sc->skipped_triangles - skipped;
    }
    c->triangles += nt;
    free(pos);
    free(idx);
    free(uvs);
    return st;
}

static xrad_status add_node(import_ctx *c, const struct aiNode *node,
                            const struct aiMatrix4x4 *parent, uint32_t depth)
{
    char nname[61];
    clean(node->mName.data, nname, sizeof(nname));
    if (depth > NODE_DEPTH_MAX)
        return xrad_fail(c->err, XRAD_ERROR_INPUT, "%s: node '%.60s': nested deeper than %u "
                         "levels", c->path, nname, NODE_DEPTH_MAX);
    struct aiMatrix4x4 world = mul(parent, &node->mTransformation);
    if (!matrix_finite(&world))
        return xrad_fail(c->err, XRAD_ERROR_INPUT, "%s: node '%.60s': its transform (through "
                         "its parents') is not finite", c->path, nname);
    for (uint32_t k = 0; k < node->mNumMeshes; k++) {
        if (node->mMeshes[k] >= c->ai->mNumMeshes)
            return xrad_fail(c->err, XRAD_ERROR_INPUT, "%s: node '%.60s': mesh %u does not "
                             "exist (%u meshes)", c->path, nname, node->mMeshes[k],
                             c->ai->mNumMeshes);
        xrad_status st = add_mesh(c, node, &world, node->mMeshes[k]);
        if (st)
            return st;
    }
    for (uint32_t k = 0; k < node->mNumChildren; k++) {
        xrad_status st = add_node(c, node->mChildren[k], &world, depth + 1);
        if (st)
            return st;
    }
    return XRAD_OK;
}

/* The node named `name` and its world transform (of its parent chain);
 * not looked for deeper than add_node goes. */
static const struct aiNode *find_node(const struct aiNode *n, const char *name,
                                      const struct aiMatrix4x4 *parent, struct aiMatrix4x4 *out,
                                      uint32_t depth)
{
    if (!strcmp(n->mName.data, name)) {
        *out = *parent;
        return n;
    }
    if (depth >= NODE_DEPTH_MAX)
        return NULL;
    struct aiMatrix4x4 world = mul(parent, &n->mTransformation);
    for (uint32_t k = 0; k < n->mNumChildren; k++) {
        const struct aiNode *f = find_node(n->mChildren[k], name, &world, out, depth + 1);
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
        for (uint32_t k = 0; k < ai->mNumCameras && len < sizeof(list); k++) {
            char cname[61];
            len += (size_t)snprintf(list + len, sizeof(list) - len, "%s'%s'", k ? ", " : "",
                                    clean(ai->mCameras[k]->mName.data, cname, sizeof(cname)));
        }
        return xrad_fail(c->err, XRAD_ERROR_INPUT, "%s: no camera named '%s' (the file has %s)",
                         c->path, want, ai->mNumCameras ? list : "none");
    }
    struct aiMatrix4x4 identity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, world;
    const struct aiNode *node = find_node(ai->mRootNode, cam->mName.data, &identity, &world, 0);
    if (node)
        world = mul(&world, &node->mTransformation);
    else
        world = identity;
    /* A glTF camera sits at its node's origin (glTF 2.0 3.10.2). assimp
     * 5.2 also copies the node's translation into mPosition, which the
     * node's transform then applies a second time (a camera at z = 5
     * read as z = 10), so mPosition is not used. */
    float pos[3], dir[3], up[3];
    apply(&world, (struct aiVector3D){0, 0, 0}, 1, pos);
    apply(&world, cam->mLookAt, 0, dir);
    apply(&world, cam->mUp, 0, up);
    /* camera.h calls mHorizontalFOV a half angle, but assimp's glTF 2
     * importer stores yfov x aspect up to 5.2 (Debian 12's: yfov 0.8 at
     * aspect 2 reads 1.6) and the whole horizontal angle
     * 2 atan(tan(yfov / 2) aspect) from 5.3: undone here. */
    double aspect = cam->mAspect > 0 ? cam->mAspect : 1, h = cam->mHorizontalFOV;
    bool product = aiGetVersionMajor() < 5 || (aiGetVersionMajor() == 5 && aiGetVersionMinor() < 3);
    double fov = (product ? h / aspect : 2 * atan(tan(0.5 * h) / aspect)) * 180 / PI;
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
    if (st) {
        char cname[61];
        xrad_error_prefix(c->err, "%s: camera '%s'", c->path,
                          clean(cam->mName.data, cname, sizeof(cname)));
    }
    return st;
}

/* ------------------------------------------------------------ assimp calls */

/* assimp's log lines are "Warn,  T0: text" and "Error, T0: text"; its
 * warnings and the errors it recovers from (a face dropped, a material
 * file not found) are passed on, once each. Control characters (the
 * file's own names and bytes appear in them) become '?'. */
static void log_line(const char *msg, char *user)
{
    import_log *log = (import_log *)user;
    if (strncmp(msg, "Warn", 4) && strncmp(msg, "Error", 5))
        return;
    const char *text = strstr(msg, ": ");
    text = text ? text + 2 : msg;
    /* Only a consequence of faces dropped or points and lines sorted out,
     * both said on their own. */
    if (strstr(text, "unreferenced vertices"))
        return;
    char line[ASSIMP_LINE_MAX];
    size_t n = 0;
    for (; text[n] && n + 1 < sizeof(line); n++)
        line[n] = (unsigned char)text[n] < 0x20 || text[n] == 0x7f ? '?' : text[n];
    while (n && line[n - 1] == '?')
        n--; /* the trailing newline */
    line[n] = '\0';
    for (uint32_t k = 0; k < log->lines; k++)
        if (!strcmp(log->line[k], line))
            return;
    if (log->lines < ASSIMP_LINES)
        memcpy(log->line[log->lines++], line, n + 1);
    else
        log->more++;
}

/* A model file held in memory, served to assimp under its name; every
 * other file it asks for (a glTF's .bin, an OBJ's .mtl) is not there, so
 * that memory input never reaches the file system. */
typedef struct memory_file {
    const char *name;
    const unsigned char *data;
    size_t size;
} memory_file;

typedef struct memory_cursor {
    const memory_file *file;
    size_t pos;
} memory_cursor;

static size_t memory_read(struct aiFile *f, char *out, size_t size, size_t count)
{
    memory_cursor *m = (memory_cursor *)f->UserData;
    if (size == 0)
        return 0;
    size_t n = (m->file->size - m->pos) / size;
    if (count < n)
        n = count;
    memcpy(out, m->file->data + m->pos, n * size);
    m->pos += n * size;
    return n;
}

static size_t memory_write(struct aiFile *f, const char *in, size_t size, size_t count)
{
    (void)f, (void)in, (void)size, (void)count;
    return 0;
}

static size_t memory_tell(struct aiFile *f)
{
    return ((memory_cursor *)f->UserData)->pos;
}

static size_t memory_size(struct aiFile *f)
{
    return ((memory_cursor *)f->UserData)->file->size;
}

static enum aiReturn memory_seek(struct aiFile *f, size_t off, enum aiOrigin origin)
{
    memory_cursor *m = (memory_cursor *)f->UserData;
    size_t base = origin == aiOrigin_SET ? 0 : origin == aiOrigin_CUR ? m->pos : m->file->size;
    if (origin != aiOrigin_SET && origin != aiOrigin_CUR && origin != aiOrigin_END)
        return aiReturn_FAILURE;
    /* Offsets are unsigned: a step back arrives wrapped around. */
    size_t to = base + off;
    if (to > m->file->size)
        return aiReturn_FAILURE;
    m->pos = to;
    return aiReturn_SUCCESS;
}

static void memory_flush(struct aiFile *f)
{
    (void)f;
}

static struct aiFile *memory_open(struct aiFileIO *io, const char *name, const char *mode)
{
    const memory_file *file = (const memory_file *)io->UserData;
    if (strcmp(name, file->name) || strchr(mode, 'w') || strchr(mode, 'a'))
        return NULL;
    struct aiFile *f = malloc(sizeof(*f));
    memory_cursor *m = malloc(sizeof(*m));
    if (!f || !m) {
        free(f);
        free(m);
        return NULL;
    }
    *m = (memory_cursor){.file = file};
    *f = (struct aiFile){.ReadProc = memory_read,
                         .WriteProc = memory_write,
                         .TellProc = memory_tell,
                         .FileSizeProc = memory_size,
                         .SeekProc = memory_seek,
                         .FlushProc = memory_flush,
                         .UserData = (aiUserData)m};
    return f;
}

static void memory_close(struct aiFileIO *io, struct aiFile *f)
{
    (void)io;
    if (f)
        free(f->UserData);
    free(f);
}

/* assimp's logger and its last error string are process-wide: one import
 * at a time, so that two scenes loaded on two threads (xrad.h allows it)
 * get their own messages. An application that also gives assimp a C++
 * DefaultLogger of its own loses it here (aiDetachLogStream kills the
 * logger when no C stream is left). */
static pthread_mutex_t import_lock = PTHREAD_MUTEX_INITIALIZER;

/* Whether the faces of every mesh are what assimp's post-processing
 * assumes (it asserts rather than checks, and Debian's assimp keeps its
 * asserts: abort()): every face has indices, in range, and a mesh marked
 * as having polygons has one (Triangulate's assert; a face of no indices
 * is marked a polygon). Else false, the reason in why. */
static bool faces_sound(const struct aiScene *ai, char *why, size_t why_len)
{
    for (uint32_t m = 0; m < ai->mNumMeshes; m++) {
        const struct aiMesh *mesh = ai->mMeshes[m];
        char name[80];
        if (mesh->mName.length)
        {
            char own[61];
            snprintf(name, sizeof(name), "'%s'", clean(mesh->mName.data, own, sizeof(own)));
        }
        else
            snprintf(name, sizeof(name), "#%u", m);
        if ((mesh->mNumVertices && !mesh->mVertices) || (mesh->mNumFaces && !mesh->mFaces)) {
            snprintf(why, why_len, "mesh %s: no vertex or face data", name);
            return false;
        }
        uint32_t most = 0;
        for (uint32_t f = 0; f < mesh->mNumFaces; f++) {
            const struct aiFace *face = &mesh->mFaces[f];
            if (face->mNumIndices == 0 || !face->mIndices) {
                snprintf(why, why_len, "mesh %s: face %u has no vertices", name, f);
                return false;
            }
            for (uint32_t k = 0; k < face->mNumIndices; k++)
                if (face->mIndices[k] >= mesh->mNumVertices) {
                    snprintf(why, why_len,
                             "mesh %s: face %u: vertex index %u is out of range (%u vertices)",
                             name, f, face->mIndices[k], mesh->mNumVertices);
                    return false;
                }
            if (face->mNumIndices > most)
                most = face->mNumIndices;
        }
        if ((mesh->mPrimitiveTypes & aiPrimitiveType_POLYGON) && most <= 3) {
            snprintf(why, why_len, "mesh %s: marked as having polygons, has none", name);
            return false;
        }
    }
    return true;
}

/* The file through `io` (NULL: the file system); on failure NULL and the
 * reason (assimp's, or faces_sound's) in why, `refused` telling which. */
static const struct aiScene *import_file(const char *path, struct aiFileIO *io, import_log *log,
                                         char *why, size_t why_len, bool *refused)
{
    *refused = false;
    pthread_mutex_lock(&import_lock);
    struct aiLogStream stream = {.callback = log_line, .user = (char *)log};
    aiAttachLogStream(&stream);
    /* Read and validate first, check the faces, then triangulate
     * polygons, weld vertices and sort points and lines out of the
     * triangle meshes (the node tree and its transforms are kept). The
     * second step has no validation: when a step fails there, assimp 5.2's
     * aiApplyPostProcessing releases the scene it has already deleted;
     * add_mesh checks what it takes instead. */
    const struct aiScene *ai =
        aiImportFileExWithProperties(path, aiProcess_ValidateDataStructure, io, NULL);
    if (ai && ai->mRootNode && !faces_sound(ai, why, why_len)) {
        *refused = true;
        aiReleaseImport(ai);
        ai = NULL;
    } else if (ai && ai->mRootNode) {
        ai = aiApplyPostProcessing(ai, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                           aiProcess_SortByPType);
    }
    aiDetachLogStream(&stream);
    if (!*refused && (!ai || !ai->mRootNode)) {
        snprintf(why, why_len, "%s", aiGetErrorString());
        if (ai)
            aiReleaseImport(ai);
        ai = NULL;
    }
    for (char *p = why; !ai && *p; p++)
        if ((unsigned char)*p < 0x20)
            *p = '?';
    pthread_mutex_unlock(&import_lock);
    return ai;
}

/* ---------------------------------------------------------------- PLY check */

static uint32_t ply_type_size(const char *t)
{
    static const struct {
        const char *name;
        uint32_t size;
    } types[] = {{"char", 1},   {"uchar", 1},  {"int8", 1},    {"uint8", 1},
                 {"short", 2},  {"ushort", 2}, {"int16", 2},   {"uint16", 2},
                 {"int", 4},    {"uint", 4},   {"int32", 4},   {"uint32", 4},
                 {"float", 4},  {"float32", 4}, {"double", 8}, {"float64", 8}};
    for (size_t k = 0; k < sizeof(types) / sizeof(types[0]); k++)
        if (!strcmp(t, types[k].name))
            return types[k].size;
    return 1;
}

/* assimp's PLY reader reserves memory for an element count as written in
 * the header before reading any (3e9 vertices: 11 GB and a bad_alloc), so
 * the counts are checked against the body here first: an instance takes
 * at least its fixed-size properties' bytes in a binary file and two bytes
 * (a digit and a separator) per property in ASCII; at least one byte in
 * any case, since assimp reserves per instance even for an element without
 * properties. It also never returns from a header whose end_header is not
 * a line of its own (missing, taken as a property's name, or followed on
 * its line by more than blanks), so the header's lines are checked for
 * that too. `head` is the file's first
 * head_len bytes, of size in all. Lines this does not know are left to
 * assimp, which skips them. */
static xrad_status ply_check(const char *path, const char *head, size_t head_len, uint64_t size,
                             xrad_error *err)
{
    if (head_len < 4 || strncasecmp(head, "ply", 3)) /* assimp's magic test ignores case */
        return XRAD_OK;
    bool binary = false, ended = false;
    char ename[64] = "";
    uint64_t count = 0, need = 0;
    double total = 0; /* bytes, over all elements: double cannot wrap */
    const char *p = head, *stop = head + head_len;
    for (uint32_t number = 1; p < stop && !ended; number++) {
        const char *eol = memchr(p, '\n', (size_t)(stop - p));
        if (!eol)
            break; /* no end of line: no end_header line either */
        char line[256], w[5][64] = {{0}};
        size_t n = (size_t)(eol - p) < sizeof(line) - 1 ? (size_t)(eol - p) : sizeof(line) - 1;
        memcpy(line, p, n);
        line[n] = '\0';
        p = eol + 1;
        int words = sscanf(line, "%63s %63s %63s %63s %63s", w[0], w[1], w[2], w[3], w[4]);
        bool list = words >= 2 && !strcmp(w[1], "list");
        if (words >= 1 && !strcmp(w[0], "end_header")) {
            /* Only blanks after it: assimp 5.2 loops for ever on an
             * end_header followed by a vertical tab and the first vertex
             * (regressions/import/ply-end-header-vtab-hangs-assimp). */
            const char *rest = strstr(line, "end_header") + strlen("end_header");
            if (rest[strspn(rest, " \t\r")] != '\0')
                return xrad_fail(err, XRAD_ERROR_INPUT, "%s: PLY header: line %u: end_header "
                                 "must end its line", path, number);
            ended = true;
        } else if (words >= 2 && !strcmp(w[0], "format")) {
            binary = !strncmp(w[1], "binary", 6);
        } else if (words >= 1 && !strcmp(w[0], "element")) {
            if (words < 3 || w[2][0] < '0' || w[2][0] > '9')
                return xrad_fail(err, XRAD_ERROR_INPUT, "%s: PLY header: line %u: an element "
                                 "needs a name and a count", path, number);
            total += (double)count * (double)(need ? need : 1);
            snprintf(ename, sizeof(ename), "%s", w[1]);
            count = strtoull(w[2], NULL, 10);
            need = 0;
        } else if (words >= 1 && !strcmp(w[0], "property")) {
            if (words < (list ? 5 : 3))
                return xrad_fail(err, XRAD_ERROR_INPUT, "%s: PLY header: line %u: a property "
                                 "needs %s", path, number,
                                 list ? "a count type, an item type and a name"
                                      : "a type and a name");
            need += binary ? ply_type_size(list ? w[2] : w[1]) : 2;
        }
        /* Before the end of the header is known: against the whole file. */
        if (count > size || (double)count * (double)(need ? need : 1) > (double)size)
            return xrad_fail(err, XRAD_ERROR_INPUT,
                             "%s: PLY header: element '%s': %llu of at least %llu byte(s) "
                             "each do not fit in the file's %llu bytes", path, ename,
                             (unsigned long long)count, (unsigned long long)(need ? need : 1),
                             (unsigned long long)size);
    }
    if (!ended)
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: PLY header: no end_header line in the "
                         "first %zu bytes", path, head_len);
    uint64_t body = size - (uint64_t)(p - head);
    if (count > body || (double)count * (double)(need ? need : 1) > (double)body + 1)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: PLY header: element '%s': %llu of at least %llu byte(s) each do "
                         "not fit in the %llu bytes after the header", path, ename,
                         (unsigned long long)count, (unsigned long long)(need ? need : 1),
                         (unsigned long long)body);
    total += (double)count * (double)(need ? need : 1);
    if (total > (double)body + 1)
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: PLY header: its element counts need at "
                         "least %.0f bytes, the file has %llu after the header", path, total,
                         (unsigned long long)body);
    return XRAD_OK;
}

/* --------------------------------------------------------------- glTF check */

static bool has_ext(const char *path, const char *ext)
{
    const char *dot = strrchr(path, '.');
    return dot && !strcasecmp(dot, ext);
}

static uint32_t le32(const char *p)
{
    const unsigned char *u = (const unsigned char *)p;
    return (uint32_t)u[0] | (uint32_t)u[1] << 8 | (uint32_t)u[2] << 16 | (uint32_t)u[3] << 24;
}

/* Bytes of a .glb that gltf_check reads: the 12-byte header, the first
 * chunk's 8-byte header and that chunk (the JSON). */
static uint64_t glb_json_end(const char *head, size_t head_len)
{
    return head_len < 20 ? 20 : 20 + (uint64_t)le32(head + 12);
}

/* assimp picks the importer by the extension, but when the importers of
 * that extension decline the content (glTF 1 and 2 both claim .gltf and
 * .glb, and both look at the header and parse the JSON first), it offers
 * the file to each of its 40 importers in turn: an STL named .glb loads,
 * and a PLY named .glb reaches assimp's PLY reader without ply_check and
 * hangs it (regressions/import/glb-holding-ply-hangs-assimp). So a glTF
 * is checked here the way glTF 2.0's importer checks it before it takes
 * the file (glTF 2.0 spec 4.4, GLB: magic "glTF", version 2, a first
 * chunk of type JSON; then a JSON object whose "asset" names version 2.x);
 * a file that passes is the glTF 2 importer's, and its errors are its
 * own. OBJ and PLY have one importer each, which never hands a file on.
 * `data` holds the JSON (.gltf) or at least glb_json_end() bytes (.glb). */
static xrad_status gltf_check(const char *path, const char *data, size_t len, uint64_t size,
                              xrad_error *err)
{
    const char *json = data;
    size_t json_len = len;
    if (has_ext(path, ".glb")) {
        if (len < 20 || memcmp(data, "glTF", 4))
            return xrad_fail(err, XRAD_ERROR_INPUT,
                             "%s: not a binary glTF: it does not begin with \"glTF\"", path);
        if (le32(data + 4) != 2)
            return xrad_fail(err, XRAD_ERROR_INPUT,
                             "%s: binary glTF version %u; xrad reads glTF 2.0", path,
                             le32(data + 4));
        if (memcmp(data + 16, "JSON", 4) || glb_json_end(data, len) > size ||
            glb_json_end(data, len) > len)
            return xrad_fail(err, XRAD_ERROR_INPUT,
                             "%s: binary glTF: the first chunk is not a JSON chunk that fits "
                             "in the file", path);
        json = data + 20;
        json_len = le32(data + 12);
    } else if (!has_ext(path, ".gltf")) {
        return XRAD_OK;
    }
    cJSON *root = cJSON_ParseWithLength(json, json_len);
    const cJSON *asset = cJSON_GetObjectItemCaseSensitive(root, "asset");
    const cJSON *version = cJSON_GetObjectItemCaseSensitive(asset, "version");
    xrad_status st = XRAD_OK;
    if (!cJSON_IsObject(root))
        st = xrad_fail(err, XRAD_ERROR_INPUT, "%s: glTF: the JSON%s is not a JSON object",
                       path, json == data ? "" : " chunk");
    else if (!cJSON_IsObject(asset) || !cJSON_IsString(version))
        st = xrad_fail(err, XRAD_ERROR_INPUT, "%s: glTF: no \"asset\" object with a "
                       "\"version\" string", path);
    else if (version->valuestring[0] != '2' || version->valuestring[1] != '.')
        st = xrad_fail(err, XRAD_ERROR_INPUT, "%s: glTF: asset.version is \"%.16s\"; xrad "
                       "reads glTF 2.0", path, version->valuestring);
    cJSON_Delete(root);
    return st;
}

/* What is checked before assimp sees the file; `data` is its first len
 * bytes, as much as content_bytes() asks for. */
static xrad_status content_check(const char *path, const char *data, size_t len, uint64_t size,
                                 xrad_error *err)
{
    if (has_ext(path, ".gltf") || has_ext(path, ".glb"))
        return gltf_check(path, data, len, size, err);
    if (has_ext(path, ".ply"))
        return ply_check(path, data, len < PLY_HEADER_MAX ? len : PLY_HEADER_MAX, size, err);
    return XRAD_OK;
}

/* ------------------------------------------------------------------ import */

/* The part shared by files and memory: `path` names the model in
 * messages; io serves it (NULL: the file system). */
static xrad_status import_scene(xrad_scene_builder *b, const char *path, struct aiFileIO *io,
                                const scene_import_desc *desc, xrad_error *err)
{
    import_log log = {0};
    char why[512];
    bool refused;
    const struct aiScene *ai = import_file(path, io, &log, why, sizeof(why), &refused);
    if (!ai)
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: %s%s", path,
                         refused ? "" : "cannot import: ", why);
    xrad_scene *sc = scene_builder_scene(b);
    import_ctx c = {.b = b, .path = path, .ai = ai, .desc = desc, .err = err, .files = !io,
                    .surfaces_before = sc ? sc->surface_count : 0};
    c.material_index = malloc((ai->mNumMaterials + 1) * sizeof(uint32_t));
    c.map_channel = malloc((ai->mNumMaterials + 1) * sizeof(uint32_t));
    xrad_status st = XRAD_OK;
    if (!c.material_index || !c.map_channel)
        st = xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory", path);
    for (uint32_t m = 0; !st && m < ai->mNumMaterials; m++)
        c.material_index[m] = c.map_channel[m] = UINT32_MAX;

    struct aiMatrix4x4 identity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, parent;
    const struct aiNode *root = ai->mRootNode;
    if (!st && desc->node) {
        root = find_node(ai->mRootNode, desc->node, &identity, &parent, 0);
        if (!root)
            st = xrad_fail(err, XRAD_ERROR_INPUT, "%s: no node named '%s'", path, desc->node);
    } else {
        parent = identity;
    }
    if (!st)
        st = add_node(&c, root, &parent, 0);
    if (!st && c.triangles == 0)
        st = xrad_fail(err, XRAD_ERROR_INPUT, "%s%s%s: no triangles%s", path,
                       desc->node ? ": node " : "", desc->node ? desc->node : "",
                       c.non_triangle ? " (points or lines only)" : "");
    /* Every triangle left out: said here rather than as an object without
     * surfaces. */
    if (!st && sc && sc->surface_count == c.surfaces_before)
        st = xrad_fail(err, XRAD_ERROR_INPUT, "%s: all %u triangle(s) have zero area (the "
                       "first in %s)", path, c.triangles, c.zero_area_where);
    if (!st && desc->take_camera)
        st = take_camera(&c);
    if (!st) {
        if (c.textured)
            scene_builder_warn(b,
                               "%s: %u material(s) with emissive, metal-roughness or occlusion "
                               "textures: ignored",
                               path, c.textured);
        if (c.map_failed)
            scene_builder_warn(b,
                               "%s: %u base colour or normal texture(s) not read, the "
                               "colour factor or the face's normal used alone (first: %s)",
                               path, c.map_failed, c.map_failed_why);
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
            scene_builder_warn(b, "%s: %u mesh(es) of points or lines: ignored (first: %s)",
                               path, c.non_triangle, c.non_triangle_where);
        if (c.zero_area)
            scene_builder_warn(b, "%s: %u zero-area triangle(s) left out (first in %s)", path,
                               c.zero_area, c.zero_area_where);
        if (ai->mNumAnimations)
            scene_builder_warn(b, "%s: %u animation(s): ignored (animate the object in a "
                               "scene file)", path, ai->mNumAnimations);
        if (ai->mNumLights)
            scene_builder_warn(b, "%s: %u punctual light(s): ignored (emission comes from "
                               "emissive materials)", path, ai->mNumLights);
        if (!desc->take_camera && ai->mNumCameras)
            scene_builder_warn(b, "%s: %u camera(s): ignored (the scene file's camera is used)",
                               path, ai->mNumCameras);
        for (uint32_t k = 0; k < log.lines; k++)
            scene_builder_warn(b, "%s: assimp: %s", path, log.line[k]);
        if (log.more)
            scene_builder_warn(b, "%s: assimp: %u more message(s)", path, log.more);
    }
    free(c.material_index);
    free(c.map_channel);
    aiReleaseImport(ai);
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
    /* A .gltf is read whole (it is JSON), a .glb to the end of its JSON
     * chunk, a PLY to PLY_HEADER_MAX (its header), an OBJ not at all. */
    xrad_status st = XRAD_OK;
    long size = -1;
    if (fseek(f, 0, SEEK_END) || (size = ftell(f)) < 0 || fseek(f, 0, SEEK_SET))
        st = xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: cannot read", path);
    uint64_t want = has_ext(path, ".gltf") ? (uint64_t)size
                    : has_ext(path, ".glb") ? 20
                    : has_ext(path, ".ply") ? PLY_HEADER_MAX : 0;
    char *head = NULL;
    size_t n = 0;
    for (int pass = 0; !st && pass < 2; pass++) {
        if (want > (uint64_t)size)
            want = (uint64_t)size;
        char *grown = realloc(head, want + 1);
        if (!grown) {
            st = xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory reading %llu bytes",
                           path, (unsigned long long)want);
            break;
        }
        head = grown;
        n += fread(head + n, 1, want - n, f);
        if (ferror(f))
            st = xrad_fail(err, errno == EISDIR ? XRAD_ERROR_INPUT : XRAD_ERROR_SYSTEM,
                           "%s: cannot read: %s", path, strerror(errno));
        if (!has_ext(path, ".glb") || glb_json_end(head, n) <= n)
            break;
        want = glb_json_end(head, n);
    }
    if (!st)
        st = content_check(path, head, n, (uint64_t)size, err);
    free(head);
    fclose(f);
    if (!st)
        st = import_scene(b, path, NULL, desc, err);
    return st;
}

xrad_status scene_import_memory(xrad_scene_builder *b, const char *name, const void *data,
                                size_t size, const scene_import_desc *desc, xrad_error *err)
{
    if (!scene_import_supported(name))
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: not a model file xrad reads (.gltf, .glb, .obj, .ply)", name);
    /* assimp's stream reader takes an unsigned int size. */
    if (size > UINT32_MAX / 2)
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: larger than %u bytes", name,
                         UINT32_MAX / 2);
    xrad_status st = content_check(name, data, size, size, err);
    if (st)
        return st;
    memory_file file = {.name = name, .data = data, .size = size};
    struct aiFileIO io = {.OpenProc = memory_open,
                          .CloseProc = memory_close,
                          .UserData = (aiUserData)&file};
    return import_scene(b, name, &io, desc, err);
}
