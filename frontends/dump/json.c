/*
 * json.c - the JSON Lines format: one object per frame, built with cJSON.
 * cJSON prints numbers with %.15g/%.17g, so each number goes in as a raw
 * item formatted here in shortest round-trip form (non-finite ones, which
 * JSON cannot hold, as null).
 */
#include "dump_internal.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

static cJSON *number(double x)
{
    char b[40];
    if (!isfinite(x))
        return cJSON_CreateNull();
    /* negative zero as -0.0: a reader that maps "-0" to the integer 0
     * (Python's json) would lose its sign */
    if (x == 0.0 && signbit(x))
        return cJSON_CreateRaw("-0.0");
    rbsf__format_double(b, sizeof b, x);
    return cJSON_CreateRaw(b);
}

static cJSON *uinteger(unsigned long long v)
{
    char b[24];
    snprintf(b, sizeof b, "%llu", v);
    return cJSON_CreateRaw(b);
}

/* Add an array of n numbers under key; 0 if out of memory. */
static int add_vector(cJSON *obj, const char *key, const double *x, int n)
{
    cJSON *arr = cJSON_AddArrayToObject(obj, key);
    int i;
    if (arr == NULL)
        return 0;
    for (i = 0; i < n; i++) {
        cJSON *v = number(x[i]);
        if (v == NULL || !cJSON_AddItemToArray(arr, v)) {
            cJSON_Delete(v);
            return 0;
        }
    }
    return 1;
}

static int add_item(cJSON *obj, const char *key, cJSON *item)
{
    if (item == NULL)
        return 0;
    if (!cJSON_AddItemToObject(obj, key, item)) {
        cJSON_Delete(item);
        return 0;
    }
    return 1;
}

static rbs_status json_frame(rbsf__out *out, const rbs_frame *f, void *scratch)
{
    cJSON *root = cJSON_CreateObject(), *bodies;
    uint32_t i;
    int ok;
    size_t room, n;
    (void)scratch;

    ok = root != NULL && add_item(root, "frame", uinteger(f->number)) &&
         add_item(root, "t", number(f->time)) &&
         (bodies = cJSON_AddArrayToObject(root, "bodies")) != NULL;
    for (i = 0; ok && i < f->body_count; i++) {
        const rbs_frame_body *b = &f->bodies[i];
        cJSON *body = cJSON_CreateObject();
        ok = body != NULL && cJSON_AddItemToArray(bodies, body);
        if (!ok) {
            cJSON_Delete(body);
            break;
        }
        ok = add_item(body, "body", uinteger(b->slot)) &&
             cJSON_AddStringToObject(body, "name", b->name ? b->name : "") &&
             add_vector(body, "position", b->position, 3) &&
             add_vector(body, "orientation", b->orientation, 4) &&
             add_vector(body, "velocity", b->velocity, 3) &&
             add_vector(body, "angular_velocity", b->angular_velocity, 3);
    }
    if (!ok) {
        cJSON_Delete(root);
        return RBS_E_MEMORY; /* building the tree failed */
    }
    /* Print straight into the frame buffer, then end the line. */
    room = out->cap - out->len;
    ok = room > 8 &&
         cJSON_PrintPreallocated(root, out->buf + out->len,
                                 (int)(room - 8 > 0x7fffffff ? 0x7fffffff
                                                             : room - 8),
                                 0) != 0;
    cJSON_Delete(root);
    if (!ok)
        return RBS_E_CAPACITY;
    n = strlen(out->buf + out->len);
    out->len += n;
    return rbsf__out_put(out, "\n", 1);
}

/* Per body: a name escaped (at most 6 bytes a byte), 13 numbers, keys. */
const rbsf__format rbsf__json_format = {
    "json", NULL, 6 * RBS_NAME_MAX + 13 * 26 + 128, json_frame};
