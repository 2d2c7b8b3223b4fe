/*
 * sort.c - an in-place heap sort (Williams, "Algorithm 232: Heapsort",
 * CACM 7(6), 1964) for the core's scratch arrays: no allocation (the C
 * library's qsort may allocate), O(n log n) at worst.
 */
#include <string.h>

#include "core/world_internal.h"

/* Swap two elements of size bytes, a bounded chunk at a time. */
static void swap(unsigned char *x, unsigned char *y, size_t size)
{
    unsigned char t[64];
    while (size > 0) {
        size_t k = size < sizeof t ? size : sizeof t;
        memcpy(t, x, k);
        memcpy(x, y, k);
        memcpy(y, t, k);
        x += k;
        y += k;
        size -= k;
    }
}

/* Element i down the heap [0, n) of its larger children. */
static void sift(unsigned char *base, size_t size, uint32_t i, uint32_t n, rbs__greater_fn greater)
{
    for (;;) {
        uint32_t c = 2 * i + 1;
        if (c >= n)
            return;
        if (c + 1 < n && greater(base + (size_t)(c + 1) * size, base + (size_t)c * size))
            c++;
        if (!greater(base + (size_t)c * size, base + (size_t)i * size))
            return;
        swap(base + (size_t)i * size, base + (size_t)c * size, size);
        i = c;
    }
}

void rbs__heap_sort(void *base, uint32_t n, size_t size, rbs__greater_fn greater)
{
    unsigned char *b = (unsigned char *)base;
    uint32_t i;
    for (i = n / 2; i-- > 0;)
        sift(b, size, i, n, greater);
    for (i = n; i-- > 1;) {
        swap(b, b + (size_t)i * size, size);
        sift(b, size, 0, i, greater);
    }
}
