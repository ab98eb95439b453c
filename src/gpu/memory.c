#include "gpu/memory.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "gpu/context.h"

/* ------------------------------------------------ offset bookkeeping */

static bool reserve(gpu_suballoc *sa, uint32_t need)
{
    if (sa->cap >= need)
        return true;
    uint32_t cap = sa->cap ? sa->cap : 8;
    while (cap < need)
        cap *= 2;
    gpu_range *r = realloc(sa->free, (size_t)cap * sizeof(*r));
    if (!r)
        return false;
    sa->free = r;
    sa->cap = cap;
    return true;
}

bool gpu_suballoc_init(gpu_suballoc *sa, uint64_t size)
{
    memset(sa, 0, sizeof(*sa));
    if (!reserve(sa, 2))
        return false;
    sa->size = size;
    if (size) {
        sa->free[0] = (gpu_range){0, size};
        sa->count = 1;
    }
    return true;
}

void gpu_suballoc_finish(gpu_suballoc *sa)
{
    free(sa->free);
    memset(sa, 0, sizeof(*sa));
}

gpu_suballoc_result gpu_suballoc_alloc(gpu_suballoc *sa, uint64_t size, uint64_t align,
                                       uint64_t *offset)
{
    if (!align)
        align = 1;
    if (size == 0 || (align & (align - 1)))
        return GPU_SUBALLOC_FULL;
    uint32_t best = UINT32_MAX;
    uint64_t best_at = 0;
    for (uint32_t i = 0; i < sa->count; i++) {
        gpu_range r = sa->free[i];
        uint64_t at = (r.offset + align - 1) & ~(align - 1);
        if (at < r.offset || at - r.offset > r.size || r.size - (at - r.offset) < size)
            continue;
        if (best == UINT32_MAX || r.size < sa->free[best].size) {
            best = i;
            best_at = at;
        }
    }
    if (best == UINT32_MAX)
        return GPU_SUBALLOC_FULL;
    /* Room for the split now and for any later free (see gpu_suballoc). */
    if (!reserve(sa, sa->live + 3))
        return GPU_SUBALLOC_NOMEM;
    gpu_range r = sa->free[best];
    gpu_range pre = {r.offset, best_at - r.offset};
    gpu_range post = {best_at + size, r.offset + r.size - (best_at + size)};
    gpu_range *f = sa->free;
    if (pre.size && post.size) {
        memmove(&f[best + 2], &f[best + 1], (size_t)(sa->count - best - 1) * sizeof(*f));
        f[best] = pre;
        f[best + 1] = post;
        sa->count++;
    } else if (pre.size || post.size) {
        f[best] = pre.size ? pre : post;
    } else {
        memmove(&f[best], &f[best + 1], (size_t)(sa->count - best - 1) * sizeof(*f));
        sa->count--;
    }
    sa->live++;
    sa->used += size;
    *offset = best_at;
    return GPU_SUBALLOC_OK;
}

bool gpu_suballoc_free(gpu_suballoc *sa, uint64_t offset, uint64_t size)
{
    if (!size || !sa->live || offset > sa->size || size > sa->size - offset)
        return false;
    uint64_t end = offset + size;
    uint32_t i = 0; /* first free range after the freed one */
    while (i < sa->count && sa->free[i].offset < offset)
        i++;
    gpu_range *f = sa->free;
    bool merge_prev = false, merge_next = false;
    if (i > 0) {
        uint64_t prev_end = f[i - 1].offset + f[i - 1].size;
        if (prev_end > offset)
            return false;
        merge_prev = prev_end == offset;
    }
    if (i < sa->count) {
        if (f[i].offset < end)
            return false;
        merge_next = f[i].offset == end;
    }
    if (merge_prev && merge_next) {
        f[i - 1].size += size + f[i].size;
        memmove(&f[i], &f[i + 1], (size_t)(sa->count - i - 1) * sizeof(*f));
        sa->count--;
    } else if (merge_prev) {
        f[i - 1].size += size;
    } else if (merge_next) {
        f[i].offset = offset;
        f[i].size += size;
    } else {
        memmove(&f[i + 1], &f[i], (size_t)(sa->count - i) * sizeof(*f));
        f[i] = (gpu_range){offset, size};
        sa->count++;
    }
    sa->live--;
    sa->used -= size;
    return true;
}

uint64_t gpu_suballoc_largest_free(const gpu_suballoc *sa)
{
    uint64_t m = 0;
    for (uint32_t i = 0; i < sa->count; i++)
        if (sa->free[i].size > m)
            m = sa->free[i].size;
    return m;
}

/* ---------------------------------------------------- device memory */

/* Large enough that a scene needs a handful of allocations, small enough
 * that a half-empty block does not matter on lavapipe (host memory). */
#define BLOCK_SIZE (32ull << 20)

struct gpu_block {
    VkDeviceMemory memory;
    uint64_t size;
    uint32_t type;
    bool linear, dedicated;
    void *mapped;
    gpu_suballoc sa;
    struct gpu_block *next;
};

struct gpu_memory {
    struct gpu_block *blocks;
    uint64_t category_bytes[GPU_MEM_CATEGORY_COUNT];
    uint64_t category_peak[GPU_MEM_CATEGORY_COUNT]; /* since create or the last reset */
    uint64_t total_bytes, total_peak;
    uint64_t heap_bytes[VK_MAX_MEMORY_HEAPS];
    uint32_t block_count, allocations;
    /* xrad_context_desc.memory_limit_mib: a smaller budget than the device's, so that
     * "does not fit" can be tried on any machine. 0: none. */
    uint64_t budget_limit;
    /* A redistribution thread and a display thread allocate from one
     * context (schedule/scheduler.h). */
    pthread_mutex_t lock;
};

const char *gpu_mem_category_name(gpu_mem_category c)
{
    static const char *const names[GPU_MEM_CATEGORY_COUNT] = {
        "geometry", "radiosity", "render targets", "staging", "redistribution", "other"};
    return (unsigned)c < GPU_MEM_CATEGORY_COUNT ? names[c] : "?";
}

xrad_status gpu_memory_create(struct xrad_context *ctx, gpu_memory **out, xrad_error *err)
{
    gpu_memory *m = calloc(1, sizeof(*m));
    if (!m)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (memory allocator)");
    m->budget_limit = ctx->memory_limit;
    if (pthread_mutex_init(&m->lock, NULL) != 0) {
        free(m);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "memory allocator: pthread_mutex_init failed");
    }
    *out = m;
    return XRAD_OK;
}

static void block_destroy(struct xrad_context *ctx, struct gpu_block *b)
{
    gpu_memory *m = ctx->mem;
    if (b->mapped)
        vkUnmapMemory(ctx->device, b->memory);
    vkFreeMemory(ctx->device, b->memory, NULL);
    m->heap_bytes[ctx->mem_props.memoryTypes[b->type].heapIndex] -= b->size;
    m->block_count--;
    gpu_suballoc_finish(&b->sa);
    free(b);
}

void gpu_memory_destroy(struct xrad_context *ctx, gpu_memory **mem)
{
    if (!mem || !*mem)
        return;
    struct gpu_block *b = (*mem)->blocks;
    while (b) {
        struct gpu_block *next = b->next;
        block_destroy(ctx, b);
        b = next;
    }
    pthread_mutex_destroy(&(*mem)->lock);
    free(*mem);
    *mem = NULL;
}

/* The memory type for `usage` among `bits`: required flags must be there;
 * among those, preferred flags count for and avoided ones against. */
static int pick_type(const struct xrad_context *ctx, uint32_t bits, gpu_mem_usage usage)
{
    VkMemoryPropertyFlags required = 0, preferred = 0, avoided = 0;
    switch (usage) {
    case GPU_MEM_DEVICE:
        preferred = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
        break;
    case GPU_MEM_UPLOAD:
        required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        /* Host writes go to uncached memory best (write-combined). */
        avoided = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
        break;
    case GPU_MEM_READBACK:
        required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        preferred = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
        break;
    }
    int best = -1, best_score = 0;
    for (uint32_t i = 0; i < ctx->mem_props.memoryTypeCount; i++) {
        VkMemoryPropertyFlags f = ctx->mem_props.memoryTypes[i].propertyFlags;
        if (!(bits & (1u << i)) || (f & required) != required ||
            (f & VK_MEMORY_PROPERTY_PROTECTED_BIT) ||
            (f & VK_MEMORY_PROPERTY_LAZILY_ALLOCATED_BIT))
            continue;
        int score = 2 * __builtin_popcount(f & preferred) - __builtin_popcount(f & avoided);
        if (best < 0 || score > best_score) {
            best = (int)i;
            best_score = score;
        }
    }
    return best;
}

static xrad_status block_create(struct xrad_context *ctx, uint64_t size, uint32_t type,
                                bool linear, bool dedicated, struct gpu_block **out,
                                xrad_error *err)
{
    gpu_memory *m = ctx->mem;
    struct gpu_block *b = calloc(1, sizeof(*b));
    if (!b)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (memory block)");
    if (!gpu_suballoc_init(&b->sa, size)) {
        free(b);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (memory block)");
    }
    b->size = size;
    b->type = type;
    b->linear = linear;
    b->dedicated = dedicated;
    VkMemoryAllocateInfo info = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
        .allocationSize = size,
        .memoryTypeIndex = type,
    };
    if (VK_CHECK(ctx, err, vkAllocateMemory(ctx->device, &info, NULL, &b->memory)))
        goto fail_alloc;
    VkMemoryPropertyFlags f = ctx->mem_props.memoryTypes[type].propertyFlags;
    /* Only coherent memory is handed out mapped, so no caller has to flush. */
    if ((f & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) && (f & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT) &&
        VK_CHECK(ctx, err, vkMapMemory(ctx->device, b->memory, 0, VK_WHOLE_SIZE, 0, &b->mapped)))
        goto fail_map;
    m->heap_bytes[ctx->mem_props.memoryTypes[type].heapIndex] += size;
    m->block_count++;
    b->next = m->blocks;
    m->blocks = b;
    *out = b;
    return XRAD_OK;

fail_map:
    vkFreeMemory(ctx->device, b->memory, NULL);
fail_alloc:
    gpu_suballoc_finish(&b->sa);
    free(b);
    return XRAD_ERROR_SYSTEM;
}

static void unlink_block(gpu_memory *m, struct gpu_block *b)
{
    for (struct gpu_block **p = &m->blocks; *p; p = &(*p)->next) {
        if (*p == b) {
            *p = b->next;
            return;
        }
    }
}

static xrad_status alloc_locked(struct xrad_context *ctx, const VkMemoryRequirements *req,
                                gpu_mem_usage usage, bool linear, gpu_mem_category category,
                                gpu_allocation *out, xrad_error *err)
{
    gpu_memory *m = ctx->mem;
    memset(out, 0, sizeof(*out));
    int type = pick_type(ctx, req->memoryTypeBits, usage);
    if (type < 0)
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "no Vulkan memory type fits (allowed types 0x%x, %s)",
                         req->memoryTypeBits,
                         usage == GPU_MEM_DEVICE ? "device" : "host-visible coherent");
    bool dedicated = req->size > BLOCK_SIZE / 4;
    struct gpu_block *block = NULL;
    uint64_t offset = 0;
    for (struct gpu_block *b = m->blocks; b && !dedicated; b = b->next) {
        if (b->dedicated || b->type != (uint32_t)type || b->linear != linear)
            continue;
        gpu_suballoc_result r = gpu_suballoc_alloc(&b->sa, req->size, req->alignment, &offset);
        if (r == GPU_SUBALLOC_NOMEM)
            return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (memory allocator)");
        if (r == GPU_SUBALLOC_OK) {
            block = b;
            break;
        }
    }
    if (!block) {
        xrad_status s = block_create(ctx, dedicated ? req->size : BLOCK_SIZE, (uint32_t)type,
                                     linear, dedicated, &block, err);
        if (s)
            return s;
        if (gpu_suballoc_alloc(&block->sa, req->size, req->alignment, &offset) !=
            GPU_SUBALLOC_OK) {
            unlink_block(m, block);
            block_destroy(ctx, block);
            return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (memory allocator)");
        }
    }
    *out = (gpu_allocation){
        .memory = block->memory,
        .offset = offset,
        .size = req->size,
        .mapped = block->mapped ? (char *)block->mapped + offset : NULL,
        .type = (uint32_t)type,
        .category = category,
        .block = block,
    };
    m->category_bytes[category] += req->size;
    if (m->category_bytes[category] > m->category_peak[category])
        m->category_peak[category] = m->category_bytes[category];
    m->total_bytes += req->size;
    if (m->total_bytes > m->total_peak)
        m->total_peak = m->total_bytes;
    m->allocations++;
    return XRAD_OK;
}

xrad_status gpu_memory_alloc(struct xrad_context *ctx, const VkMemoryRequirements *req,
                             gpu_mem_usage usage, bool linear, gpu_mem_category category,
                             gpu_allocation *out, xrad_error *err)
{
    pthread_mutex_lock(&ctx->mem->lock);
    xrad_status s = alloc_locked(ctx, req, usage, linear, category, out, err);
    pthread_mutex_unlock(&ctx->mem->lock);
    return s;
}

void gpu_memory_free(struct xrad_context *ctx, gpu_allocation *a)
{
    if (!a || !a->block)
        return;
    gpu_memory *m = ctx->mem;
    pthread_mutex_lock(&m->lock);
    struct gpu_block *b = a->block;
    gpu_suballoc_free(&b->sa, a->offset, a->size);
    m->category_bytes[a->category] -= a->size;
    m->total_bytes -= a->size;
    m->allocations--;
    /* Empty blocks go back at once: xrad holds few long-lived resources,
     * and returning them keeps the budget figures honest. */
    if (b->sa.live == 0) {
        unlink_block(m, b);
        block_destroy(ctx, b);
    }
    pthread_mutex_unlock(&m->lock);
    memset(a, 0, sizeof(*a));
}

void gpu_memory_get_stats(struct xrad_context *ctx, gpu_memory_stats *stats)
{
    memset(stats, 0, sizeof(*stats));
    gpu_memory *m = ctx->mem;
    stats->heap_count = ctx->mem_props.memoryHeapCount;
    VkPhysicalDeviceMemoryBudgetPropertiesEXT budget = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MEMORY_BUDGET_PROPERTIES_EXT,
    };
    VkPhysicalDeviceMemoryProperties2 props = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MEMORY_PROPERTIES_2,
        .pNext = &budget,
    };
    if (ctx->features.memory_budget)
        vkGetPhysicalDeviceMemoryProperties2(ctx->phys, &props);
    if (m)
        pthread_mutex_lock(&m->lock);
    for (uint32_t h = 0; h < stats->heap_count; h++) {
        stats->heap_size[h] = ctx->mem_props.memoryHeaps[h].size;
        stats->heap_bytes[h] = m ? m->heap_bytes[h] : 0;
        stats->heap_budget[h] =
            ctx->features.memory_budget ? budget.heapBudget[h] : stats->heap_size[h] / 4 * 3;
        if (m && m->budget_limit && m->budget_limit < stats->heap_budget[h])
            stats->heap_budget[h] = m->budget_limit;
    }
    if (m) {
        memcpy(stats->category_bytes, m->category_bytes, sizeof(stats->category_bytes));
        memcpy(stats->category_peak, m->category_peak, sizeof(stats->category_peak));
        stats->total_bytes = m->total_bytes;
        stats->total_peak = m->total_peak;
        stats->blocks = m->block_count;
        stats->allocations = m->allocations;
        pthread_mutex_unlock(&m->lock);
    }
}

xrad_status gpu_memory_check_budget(struct xrad_context *ctx, uint64_t bytes,
                                    gpu_mem_usage usage, const char *what, xrad_error *err)
{
    int type = pick_type(ctx, UINT32_MAX, usage);
    if (type < 0)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: no Vulkan memory type fits", what);
    uint32_t heap = ctx->mem_props.memoryTypes[type].heapIndex;
    gpu_memory_stats s;
    gpu_memory_get_stats(ctx, &s);
    uint64_t used = s.heap_bytes[heap];
    if (ctx->features.memory_budget) {
        VkPhysicalDeviceMemoryBudgetPropertiesEXT budget = {
            .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MEMORY_BUDGET_PROPERTIES_EXT,
        };
        VkPhysicalDeviceMemoryProperties2 props = {
            .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MEMORY_PROPERTIES_2,
            .pNext = &budget,
        };
        vkGetPhysicalDeviceMemoryProperties2(ctx->phys, &props);
        used = budget.heapUsage[heap]; /* includes other processes */
    }
    uint64_t left = s.heap_budget[heap] > used ? s.heap_budget[heap] - used : 0;
    if (bytes > left)
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "%s needs %.1f MiB of GPU memory, but only %.1f MiB of the %.1f MiB "
                         "budget of memory heap %u are left",
                         what, (double)bytes / 1048576.0, (double)left / 1048576.0,
                         (double)s.heap_budget[heap] / 1048576.0, heap);
    return XRAD_OK;
}

void gpu_memory_reset_peak(struct xrad_context *ctx)
{
    gpu_memory *m = ctx->mem;
    pthread_mutex_lock(&m->lock);
    memcpy(m->category_peak, m->category_bytes, sizeof(m->category_peak));
    m->total_peak = m->total_bytes;
    pthread_mutex_unlock(&m->lock);
}

void xrad_context_get_memory(xrad_context *ctx, xrad_memory_stats *out)
{
    memset(out, 0, sizeof(*out));
    gpu_memory_stats st;
    gpu_memory_get_stats(ctx, &st);
    out->count = GPU_MEM_CATEGORY_COUNT;
    for (uint32_t c = 0; c < GPU_MEM_CATEGORY_COUNT; c++) {
        out->names[c] = gpu_mem_category_name((gpu_mem_category)c);
        out->bytes[c] = st.category_bytes[c];
        out->peak[c] = st.category_peak[c];
    }
    out->total = st.total_bytes;
    out->total_peak = st.total_peak;
    for (uint32_t h = 0; h < st.heap_count; h++)
        out->device_bytes += st.heap_bytes[h];
}

void xrad_context_reset_memory_peak(xrad_context *ctx)
{
    gpu_memory_reset_peak(ctx);
}
