/* The sub-allocator's bookkeeping, without a device: alignment, no overlap,
 * free + coalesce, exhaustion, double-free detection. */
#include <stdint.h>

#include "gpu/memory.h"
#include "harness.h"

typedef struct live {
    uint64_t offset, size;
} live;

static int overlaps(const live *a, const live *b)
{
    return a->offset < b->offset + b->size && b->offset < a->offset + a->size;
}

/* Every free range lies inside the allocator, ranges are sorted and not
 * adjacent, no live allocation touches free space, and the bytes add up. */
static void check_invariants(const gpu_suballoc *sa, const live *l, int n)
{
    uint64_t free_bytes = 0, live_bytes = 0;
    for (uint32_t i = 0; i < sa->count; i++) {
        const gpu_range *r = &sa->free[i];
        CHECK(r->size > 0 && r->offset + r->size <= sa->size, "free range %u out of bounds", i);
        if (i)
            CHECK(sa->free[i - 1].offset + sa->free[i - 1].size < r->offset,
                  "free ranges %u and %u unsorted or not coalesced", i - 1, i);
        free_bytes += r->size;
        for (int k = 0; k < n; k++) {
            live fr = {r->offset, r->size};
            CHECK(!overlaps(&fr, &l[k]), "allocation %d overlaps free range %u", k, i);
        }
    }
    for (int k = 0; k < n; k++)
        live_bytes += l[k].size;
    CHECK(live_bytes == sa->used, "used %llu, live sizes sum %llu",
          (unsigned long long)sa->used, (unsigned long long)live_bytes);
    CHECK(free_bytes + live_bytes <= sa->size, "free + used exceeds the size");
    CHECK(sa->count <= (uint32_t)n + 1, "%u free ranges for %d allocations", sa->count, n);
}

static void test_basic(void)
{
    gpu_suballoc sa;
    CHECK(gpu_suballoc_init(&sa, 1024), "init");
    uint64_t a, b, c;
    CHECK(gpu_suballoc_alloc(&sa, 100, 1, &a) == GPU_SUBALLOC_OK && a == 0, "a at %llu",
          (unsigned long long)a);
    CHECK(gpu_suballoc_alloc(&sa, 10, 64, &b) == GPU_SUBALLOC_OK && b == 128, "b at %llu",
          (unsigned long long)b);
    /* The 28-byte gap before b is still usable. */
    CHECK(gpu_suballoc_alloc(&sa, 28, 4, &c) == GPU_SUBALLOC_OK && c == 100, "c at %llu",
          (unsigned long long)c);
    live l[3] = {{a, 100}, {b, 10}, {c, 28}};
    check_invariants(&sa, l, 3);
    CHECK(!gpu_suballoc_free(&sa, 2000, 8), "free out of bounds refused");
    CHECK(!gpu_suballoc_free(&sa, 500, 8), "free of free space refused");
    CHECK(gpu_suballoc_free(&sa, b, 10), "free b");
    CHECK(!gpu_suballoc_free(&sa, b, 10), "double free refused");
    CHECK(gpu_suballoc_free(&sa, a, 100) && gpu_suballoc_free(&sa, c, 28), "free a, c");
    CHECK(sa.count == 1 && sa.free[0].offset == 0 && sa.free[0].size == 1024 && sa.used == 0,
          "everything coalesced back into one range (%u ranges)", sa.count);
    CHECK(gpu_suballoc_alloc(&sa, 0, 1, &a) == GPU_SUBALLOC_FULL, "size 0 refused");
    CHECK(gpu_suballoc_alloc(&sa, 8, 3, &a) == GPU_SUBALLOC_FULL, "non-power-of-two alignment");
    CHECK(gpu_suballoc_alloc(&sa, 1025, 1, &a) == GPU_SUBALLOC_FULL, "too large");
    CHECK(gpu_suballoc_alloc(&sa, 1024, 1024, &a) == GPU_SUBALLOC_OK && a == 0, "whole range");
    CHECK(gpu_suballoc_alloc(&sa, 1, 1, &b) == GPU_SUBALLOC_FULL, "exhausted");
    CHECK(gpu_suballoc_largest_free(&sa) == 0, "nothing free");
    gpu_suballoc_finish(&sa);
}

/* Best fit takes the smallest hole that fits. */
static void test_best_fit(void)
{
    gpu_suballoc sa;
    CHECK(gpu_suballoc_init(&sa, 1000), "init");
    uint64_t o[5];
    const uint64_t sizes[5] = {100, 50, 100, 30, 100};
    for (int i = 0; i < 5; i++)
        CHECK(gpu_suballoc_alloc(&sa, sizes[i], 1, &o[i]) == GPU_SUBALLOC_OK, "alloc %d", i);
    gpu_suballoc_free(&sa, o[1], 50);
    gpu_suballoc_free(&sa, o[3], 30);
    uint64_t x;
    CHECK(gpu_suballoc_alloc(&sa, 25, 1, &x) == GPU_SUBALLOC_OK && x == o[3],
          "25 bytes went to %llu, the 30-byte hole is at %llu", (unsigned long long)x,
          (unsigned long long)o[3]);
    gpu_suballoc_finish(&sa);
}

/* Exhaustion with alignment: allocations of 48 bytes at 64-byte alignment
 * fill 4096 bytes with exactly 64 of them, all aligned, none overlapping. */
static void test_exhaustion(void)
{
    gpu_suballoc sa;
    CHECK(gpu_suballoc_init(&sa, 4096), "init");
    live l[80];
    int n = 0;
    uint64_t off;
    while (n < 80 && gpu_suballoc_alloc(&sa, 48, 64, &off) == GPU_SUBALLOC_OK) {
        CHECK(off % 64 == 0, "offset %llu not aligned", (unsigned long long)off);
        l[n++] = (live){off, 48};
    }
    CHECK(n == 64, "%d allocations of 48 at 64-byte alignment fit in 4096, want 64", n);
    for (int i = 0; i < n; i++)
        for (int k = i + 1; k < n; k++)
            CHECK(!overlaps(&l[i], &l[k]), "allocations %d and %d overlap", i, k);
    check_invariants(&sa, l, n);
    /* 16-byte pieces still fit in the alignment gaps. */
    CHECK(gpu_suballoc_alloc(&sa, 16, 16, &off) == GPU_SUBALLOC_OK, "gap allocation");
    gpu_suballoc_free(&sa, off, 16);
    for (int i = 0; i < n; i++)
        CHECK(gpu_suballoc_free(&sa, l[i].offset, l[i].size), "free %d", i);
    CHECK(sa.count == 1 && sa.free[0].size == 4096, "coalesced after exhaustion");
    gpu_suballoc_finish(&sa);
}

/* A deterministic random workload; invariants after every step. */
static void test_random(void)
{
    enum { SLOTS = 64 };
    gpu_suballoc sa;
    CHECK(gpu_suballoc_init(&sa, 1 << 16), "init");
    live l[SLOTS];
    int n = 0;
    uint32_t rng = 12345;
    for (int step = 0; step < 4000; step++) {
        rng = rng * 1664525u + 1013904223u;
        if (n < SLOTS && (n == 0 || (rng >> 16) % 3 != 0)) {
            uint64_t size = 1 + (rng >> 8) % 3000, align = 1ull << ((rng >> 4) % 9), off;
            gpu_suballoc_result r = gpu_suballoc_alloc(&sa, size, align, &off);
            CHECK(r != GPU_SUBALLOC_NOMEM, "host memory");
            if (r == GPU_SUBALLOC_OK) {
                CHECK(off % align == 0, "misaligned");
                l[n++] = (live){off, size};
            }
        } else {
            int k = (int)((rng >> 12) % (uint32_t)n);
            CHECK(gpu_suballoc_free(&sa, l[k].offset, l[k].size), "free");
            l[k] = l[--n];
        }
        if (step % 50 == 0)
            check_invariants(&sa, l, n);
        for (int i = 0; i < n && step % 200 == 0; i++)
            for (int k = i + 1; k < n; k++)
                CHECK(!overlaps(&l[i], &l[k]), "overlap");
    }
    for (; n > 0; n--)
        CHECK(gpu_suballoc_free(&sa, l[n - 1].offset, l[n - 1].size), "final free");
    CHECK(sa.count == 1 && sa.free[0].size == 1 << 16 && sa.live == 0, "all coalesced");
    gpu_suballoc_finish(&sa);
}

int main(void)
{
    test_basic();
    test_best_fit();
    test_exhaustion();
    test_random();
    return test_finish();
}
