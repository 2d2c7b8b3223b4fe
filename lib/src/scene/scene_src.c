/*
 * scene_src.c - source texts with line tables, and the map from cJSON items
 * to their places in the text (cJSON keeps no positions).
 */
#include "scene/scene_internal.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int rbs__src_init(rbs__src *src, const char *text, size_t len)
{
    size_t n = 1, i, k = 0;
    src->text = text;
    src->len = len;
    src->lines = NULL;
    src->line_count = 0;
    for (i = 0; i < len; i++) {
        if (text[i] == '\n') {
            n++;
        }
    }
    src->lines = malloc(n * sizeof *src->lines);
    if (src->lines == NULL) {
        return -1;
    }
    src->lines[k++] = 0;
    for (i = 0; i < len; i++) {
        if (text[i] == '\n') {
            src->lines[k++] = i + 1;
        }
    }
    src->line_count = n;
    return 0;
}

void rbs__src_fini(rbs__src *src)
{
    free(src->lines);
    src->lines = NULL;
    src->line_count = 0;
}

rbs__loc rbs__src_loc(const rbs__src *src, int32_t file, size_t off)
{
    rbs__loc at;
    size_t lo = 0, hi = src->line_count;
    at.file = file;
    at.line = 0;
    at.column = 0;
    if (src->lines == NULL || src->line_count == 0) {
        return at;
    }
    if (off > src->len) {
        off = src->len;
    }
    /* last line start <= off */
    while (hi - lo > 1) {
        size_t mid = lo + (hi - lo) / 2;
        if (src->lines[mid] <= off) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    at.line = lo + 1 > INT32_MAX ? INT32_MAX : (int32_t)(lo + 1);
    at.column = off - src->lines[lo] + 1 > INT32_MAX
                    ? INT32_MAX
                    : (int32_t)(off - src->lines[lo] + 1);
    return at;
}

static size_t posmap_hash(const cJSON *item, size_t cap)
{
    /* MurmurHash3's 64-bit finalizer (A. Appleby): both rounds, so every
     * bit of the pointer reaches the low bits the table uses */
    uint64_t h = (uint64_t)(uintptr_t)item;
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdULL;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ULL;
    h ^= h >> 33;
    return (size_t)h & (cap - 1);
}

int rbs__posmap_init(rbs__posmap *map, size_t expected)
{
    size_t cap = 64;
    while (cap < expected * 2 + 16) {
        if (cap > SIZE_MAX / 4 / sizeof(rbs__pos)) {
            return -1;
        }
        cap *= 2;
    }
    map->slots = calloc(cap, sizeof *map->slots);
    map->cap = map->slots == NULL ? 0 : cap;
    map->count = 0;
    return map->slots == NULL ? -1 : 0;
}

void rbs__posmap_fini(rbs__posmap *map)
{
    free(map->slots);
    map->slots = NULL;
    map->cap = 0;
    map->count = 0;
}

static int posmap_grow(rbs__posmap *map)
{
    rbs__posmap bigger;
    size_t i;
    if (map->cap > SIZE_MAX / 4 / sizeof(rbs__pos)) {
        return -1;
    }
    bigger.slots = calloc(map->cap * 2, sizeof *bigger.slots);
    if (bigger.slots == NULL) {
        return -1;
    }
    bigger.cap = map->cap * 2;
    bigger.count = 0;
    for (i = 0; i < map->cap; i++) {
        if (map->slots[i].item != NULL) {
            (void)rbs__posmap_put(&bigger, &map->slots[i]);
        }
    }
    free(map->slots);
    *map = bigger;
    return 0;
}

int rbs__posmap_put(rbs__posmap *map, const rbs__pos *pos)
{
    size_t i;
    if ((map->count + 1) * 2 > map->cap && posmap_grow(map) != 0) {
        return -1;
    }
    i = posmap_hash(pos->item, map->cap);
    while (map->slots[i].item != NULL && map->slots[i].item != pos->item) {
        i = (i + 1) & (map->cap - 1);
    }
    if (map->slots[i].item == NULL) {
        map->count++;
    }
    map->slots[i] = *pos;
    return 0;
}

const rbs__pos *rbs__posmap_get(const rbs__posmap *map, const cJSON *item)
{
    size_t i;
    if (map->cap == 0 || item == NULL) {
        return NULL;
    }
    i = posmap_hash(item, map->cap);
    while (map->slots[i].item != NULL) {
        if (map->slots[i].item == item) {
            return &map->slots[i];
        }
        i = (i + 1) & (map->cap - 1);
    }
    return NULL;
}

