/* The radiosity atlas: one nu x nv tile per surface, shelf-packed. Display
 * interpolates only between texel centres of one tile, so tiles need no
 * padding between them (thesis 4.1). */
#include <math.h>
#include <stdlib.h>

#include "core/error.h"
#include "scene/scene.h"
#include "scene/scene_internal.h"

typedef struct tile {
    uint32_t w, h, surface;
} tile;

/* Tallest first, then widest, then scene order: shelves fill with tiles of
 * similar height, and the order (so the layout) is deterministic. */
static int tile_cmp(const void *pa, const void *pb)
{
    const tile *a = pa, *b = pb;
    if (a->h != b->h)
        return a->h > b->h ? -1 : 1;
    if (a->w != b->w)
        return a->w > b->w ? -1 : 1;
    return a->surface < b->surface ? -1 : a->surface > b->surface;
}

/* Height of a shelf packing at `width`; writes positions when `scene` is
 * non-NULL. */
static uint64_t shelf_pack(const tile *tiles, uint32_t n, uint32_t width, xrad_scene *scene)
{
    uint64_t y = 0;
    uint32_t x = 0, shelf_h = 0;
    for (uint32_t k = 0; k < n; k++) {
        if (x + tiles[k].w > width) {
            y += shelf_h;
            x = 0;
            shelf_h = 0;
        }
        if (scene) {
            scene->surfaces[tiles[k].surface].tile_x = x;
            scene->surfaces[tiles[k].surface].tile_y = (uint32_t)y;
        }
        x += tiles[k].w;
        if (tiles[k].h > shelf_h)
            shelf_h = tiles[k].h;
    }
    return y + shelf_h;
}

xrad_status scene_pack_atlas(xrad_scene *scene, xrad_error *err)
{
    uint32_t n = scene->surface_count;
    tile *tiles = malloc((n ? n : 1) * sizeof(tile));
    if (!tiles)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory packing the atlas",
                         scene->path);
    uint32_t max_w = 1;
    uint64_t total_w = 0, texels = 0;
    for (uint32_t i = 0; i < n; i++) {
        tiles[i] = (tile){scene->surfaces[i].nu, scene->surfaces[i].nv, i};
        if (tiles[i].w > max_w)
            max_w = tiles[i].w;
        total_w += tiles[i].w;
        texels += (uint64_t)tiles[i].w * tiles[i].h;
    }
    qsort(tiles, n, sizeof(tile), tile_cmp);

    /* Try widths from the widest tile to 4096 (or one shelf of everything)
     * in steps of 1%. Of the packings within 10% of the smallest area, keep
     * the squarest (the smallest longer side), then the smallest. */
    uint32_t hi_w = total_w < SCENE_MAX_SAMPLES ? (uint32_t)total_w : SCENE_MAX_SAMPLES;
    if (hi_w < max_w)
        hi_w = max_w;
    uint64_t min_area = UINT64_MAX;
    uint32_t best_w = max_w;
    uint64_t best_h = 0;
    for (int pass = 0; pass < 2; pass++) {
        for (uint32_t w = max_w;;) {
            uint64_t h = shelf_pack(tiles, n, w, NULL);
            uint64_t area = (uint64_t)w * h;
            if (pass == 0) {
                if (area < min_area)
                    min_area = area;
            } else if (10 * area <= 11 * min_area) {
                uint64_t side = w > h ? w : h, best_side = best_w > best_h ? best_w : best_h;
                if (best_h == 0 || side < best_side ||
                    (side == best_side && area < (uint64_t)best_w * best_h)) {
                    best_w = w;
                    best_h = h;
                }
            }
            if (w == hi_w)
                break;
            uint32_t next = (uint32_t)ceil(w * 1.01);
            w = next > w + 1 ? next : w + 1;
            if (w > hi_w)
                w = hi_w;
        }
    }
    if (best_h > SCENE_MAX_ATLAS_HEIGHT) {
        free(tiles);
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: the element atlas would be %u x %llu texels (%llu elements), "
                         "taller than %u",
                         scene->path, best_w, (unsigned long long)best_h,
                         (unsigned long long)texels, SCENE_MAX_ATLAS_HEIGHT);
    }
    shelf_pack(tiles, n, best_w, scene);
    scene->atlas_width = best_w;
    scene->atlas_height = (uint32_t)best_h;
    free(tiles);
    return XRAD_OK;
}

xrad_status xrad_atlas_create(const xrad_scene *scene, xrad_atlas *atlas, xrad_error *err)
{
    atlas->width = 0;
    atlas->height = 0;
    atlas->rgba = NULL;
    if (!scene)
        return xrad_fail(err, XRAD_ERROR_INPUT, "xrad_atlas_create: no scene");
    size_t texels = (size_t)scene->atlas_width * scene->atlas_height;
    float *rgba = calloc(texels ? texels * 4 : 4, sizeof(float));
    if (!rgba)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory for a %u x %u atlas",
                         scene->path, scene->atlas_width, scene->atlas_height);
    atlas->width = scene->atlas_width;
    atlas->height = scene->atlas_height;
    atlas->rgba = rgba;
    return XRAD_OK;
}

void xrad_atlas_destroy(xrad_atlas *atlas)
{
    if (!atlas)
        return;
    free(atlas->rgba);
    atlas->rgba = NULL;
    atlas->width = 0;
    atlas->height = 0;
}
