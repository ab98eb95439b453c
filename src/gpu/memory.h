/*
 * Device memory: few large VkDeviceMemory blocks per memory type,
 * sub-allocated with alignment (libplacebo src/vulkan/malloc.c does the
 * same; drivers limit allocation counts and make each allocation slow).
 *
 * Two layers:
 *  - gpu_suballoc: pure offset bookkeeping over [0, size) with no Vulkan,
 *    unit-tested without a device (tests/gpu/test_suballoc.c);
 *  - gpu_memory: the blocks of one context, budget tracking per category.
 *
 * Buffers (linear) and optimal-tiling images never share a block, so
 * bufferImageGranularity never has to be honoured between neighbours.
 */
#ifndef XRAD_GPU_MEMORY_H
#define XRAD_GPU_MEMORY_H

#include <stdbool.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#include "xrad.h"

struct xrad_context;

/* ------------------------------------------------ offset bookkeeping */

typedef struct gpu_range {
    uint64_t offset, size;
} gpu_range;

/* Free ranges sorted by offset, never adjacent (they are coalesced). The
 * array keeps room for live + 2 ranges, because free ranges are separated
 * by allocations: then freeing never needs memory and cannot fail. */
typedef struct gpu_suballoc {
    uint64_t size;
    uint64_t used;  /* bytes in live allocations, alignment padding excluded */
    uint32_t live;  /* live allocations */
    uint32_t count; /* free ranges */
    uint32_t cap;
    gpu_range *free;
} gpu_suballoc;

typedef enum gpu_suballoc_result {
    GPU_SUBALLOC_OK,
    GPU_SUBALLOC_FULL,  /* no free range fits */
    GPU_SUBALLOC_NOMEM, /* host malloc failed */
} gpu_suballoc_result;

/* An empty allocator of `size` bytes; false when malloc fails. */
bool gpu_suballoc_init(gpu_suballoc *sa, uint64_t size);
void gpu_suballoc_finish(gpu_suballoc *sa);

/* Best fit: the smallest free range that holds `size` bytes starting at a
 * multiple of `align` (a power of two; 0 means 1). size 0 is FULL. */
gpu_suballoc_result gpu_suballoc_alloc(gpu_suballoc *sa, uint64_t size, uint64_t align,
                                       uint64_t *offset);

/* Returns [offset, offset + size) and merges it with free neighbours.
 * false (nothing changed) when the range is not a live allocation: out of
 * bounds or overlapping free space (a double free). */
bool gpu_suballoc_free(gpu_suballoc *sa, uint64_t offset, uint64_t size);

/* Largest free range, bytes. */
uint64_t gpu_suballoc_largest_free(const gpu_suballoc *sa);

/* ---------------------------------------------------- device memory */

/* What the bytes are for, for budget reports. */
typedef enum gpu_mem_category {
    GPU_MEM_GEOMETRY,      /* vertex, index and surface data */
    GPU_MEM_RADIOSITY,     /* atlases, shooter tables */
    GPU_MEM_RENDER_TARGET, /* hemicubes, display targets, depth */
    GPU_MEM_STAGING,       /* upload and readback */
    GPU_MEM_REDISTRIBUTION, /* incremental and cross: what only moving objects need */
    GPU_MEM_OTHER,
    GPU_MEM_CATEGORY_COUNT
} gpu_mem_category;

const char *gpu_mem_category_name(gpu_mem_category c);

/* Where the bytes should live. */
typedef enum gpu_mem_usage {
    GPU_MEM_DEVICE,   /* device-local; host access not needed */
    GPU_MEM_UPLOAD,   /* host-visible, coherent, mapped; written by the host */
    GPU_MEM_READBACK, /* host-visible, coherent, mapped; preferably cached */
} gpu_mem_usage;

struct gpu_block;

typedef struct gpu_allocation {
    VkDeviceMemory memory;
    VkDeviceSize offset, size;
    void *mapped; /* host pointer to offset, NULL unless host-visible */
    uint32_t type;
    gpu_mem_category category;
    struct gpu_block *block;
} gpu_allocation;

typedef struct gpu_memory_stats {
    uint64_t category_bytes[GPU_MEM_CATEGORY_COUNT]; /* requested sizes of live allocations */
    uint64_t category_peak[GPU_MEM_CATEGORY_COUNT];  /* their most since the last reset */
    uint64_t total_bytes, total_peak;                /* all categories */
    uint64_t heap_bytes[VK_MAX_MEMORY_HEAPS];        /* VkDeviceMemory held, per heap */
    uint64_t heap_size[VK_MAX_MEMORY_HEAPS];
    uint64_t heap_budget[VK_MAX_MEMORY_HEAPS]; /* VK_EXT_memory_budget, else 3/4 of the heap */
    uint32_t heap_count;
    uint32_t blocks;      /* VkDeviceMemory objects */
    uint32_t allocations; /* live sub-allocations */
} gpu_memory_stats;

typedef struct gpu_memory gpu_memory;

xrad_status gpu_memory_create(struct xrad_context *ctx, gpu_memory **out, xrad_error *err);
/* All allocations must have been freed. Accepts NULL; sets *mem to NULL. */
void gpu_memory_destroy(struct xrad_context *ctx, gpu_memory **mem);

/* Sub-allocates (or, for sizes over a quarter block, dedicates) memory that
 * satisfies `req`. `linear`: for buffers and linear images. */
xrad_status gpu_memory_alloc(struct xrad_context *ctx, const VkMemoryRequirements *req,
                             gpu_mem_usage usage, bool linear, gpu_mem_category category,
                             gpu_allocation *out, xrad_error *err);

/* Accepts a zeroed allocation; zeroes it. */
void gpu_memory_free(struct xrad_context *ctx, gpu_allocation *a);

void gpu_memory_get_stats(struct xrad_context *ctx, gpu_memory_stats *stats);

/* Peaks restart from the live sizes. */
void gpu_memory_reset_peak(struct xrad_context *ctx);

/* XRAD_ERROR_SYSTEM, before anything is allocated, when `bytes` more on
 * the heap that `usage` would use exceeds that heap's budget. */
xrad_status gpu_memory_check_budget(struct xrad_context *ctx, uint64_t bytes,
                                    gpu_mem_usage usage, const char *what, xrad_error *err);

#endif
