/*
 * dumper.c - the renderer functions shared by every dump format: open the
 * file with a frame buffer sized for the world, write the header, then each
 * kept frame whole; finish closes and reports any error.
 */
#include "dump_internal.h"
#include "c_locale.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PATH_MAX_BYTES 4096

typedef struct rbsf_dump_type dump_type; /* a class's context (dump.h) */

typedef struct dumper {
    const rbsf__format *format;
    rbsf__out out;
    int finished;
} dumper;

static rbs_status dumper_check(void *context, const rbs_renderer_config *config,
                               const rbs_world *world, char *err, size_t errlen)
{
    const dump_type *type = context;
    const rbsf__format *format = type->format;
    (void)world;
    return rbsf__dump_check(format->name, config, err, errlen);
}

static rbs_status dumper_create(void *context, const rbs_renderer_config *config,
                                const rbs_world *world, void **instance,
                                char *err, size_t errlen)
{
    const dump_type *type = context;
    const rbsf__format *format = type->format;
    rbs_world_def wd;
    char path[PATH_MAX_BYTES];
    dumper *d;
    rbs_status st;

    *instance = NULL;
    st = rbsf__dump_check(format->name, config, err, errlen);
    if (st != RBS_OK)
        return st;
    st = rbsf__dump_path(config, path, sizeof path, err, errlen);
    if (st != RBS_OK)
        return st;
    rbs_world_def_init(&wd);
    if (world == NULL || rbs_world_get_def(world, &wd) != RBS_OK) {
        snprintf(err, errlen, "no world");
        return RBS_E_INVALID;
    }
    d = calloc(1, sizeof *d);
    if (d == NULL) {
        snprintf(err, errlen, "out of memory");
        return RBS_E_MEMORY;
    }
    d->format = format;
    st = rbsf__out_open(&d->out, path,
                        rbsf__frame_bytes(wd.max_bodies, format->per_body),
                        type->stopper, err, errlen);
    if (st != RBS_OK) {
        free(d);
        return st;
    }
    if (format->header != NULL) {
        rbsf__out_put(&d->out, format->header, strlen(format->header));
        char why[512];
        st = rbsf__out_commit(&d->out, why, sizeof why);
        if (st != RBS_OK) {
            /* before frame 0: say it was the header line */
            snprintf(err, errlen, "header line: %s", why);
            rbsf__out_free(&d->out);
            free(d);
            return st;
        }
    }
    *instance = d;
    return RBS_OK;
}

static rbs_status dumper_draw(void *instance, const rbs_frame *frame, char *err,
                              size_t errlen)
{
    dumper *d = instance;
    rbsf__locale l;
    rbs_status st;
    /* the whole frame in the "C" locale: one switch a frame, not one a
     * number (the CSV of a 1,000-sphere run formats 13 numbers a body) */
    rbsf__c_locale_push(&l);
    st = d->format->frame(&d->out, frame, NULL);
    rbsf__c_locale_pop(&l);
    if (st != RBS_OK) {
        rbsf__out_discard(&d->out);
        if (st == RBS_E_CAPACITY)
            snprintf(err, errlen, "frame %llu does not fit the frame buffer of "
                     "'%s' (%lu bytes)", (unsigned long long)frame->number,
                     d->out.path, (unsigned long)d->out.cap);
        else
            snprintf(err, errlen, "out of memory formatting frame %llu for '%s'",
                     (unsigned long long)frame->number, d->out.path);
        return st;
    }
    return rbsf__out_commit(&d->out, err, errlen);
}

static rbs_status dumper_finish(void *instance, char *err, size_t errlen)
{
    dumper *d = instance;
    if (d->finished)
        return RBS_OK;
    d->finished = 1;
    return rbsf__out_close(&d->out, err, errlen);
}

static void dumper_destroy(void *instance)
{
    dumper *d = instance;
    if (d == NULL)
        return;
    rbsf__out_free(&d->out);
    free(d);
}

/* The classes: one table per format, its type (the format, no stopper) as
 * context. */
#define DUMPER_CLASS(name, type)                                               \
    {                                                                          \
        sizeof(rbs_renderer_class), name, (void *)&(type), dumper_create,      \
            dumper_draw, dumper_finish, dumper_destroy, NULL, 0, dumper_check  \
    }

static const dump_type csv_type = {&rbsf__csv_format, NULL};
static const dump_type json_type = {&rbsf__json_format, NULL};
static const dump_type stats_type = {&rbsf__stats_format, NULL};

static const rbs_renderer_class csv_class = DUMPER_CLASS("csv", csv_type);
static const rbs_renderer_class json_class = DUMPER_CLASS("json", json_type);
static const rbs_renderer_class stats_class =
    DUMPER_CLASS("stats", stats_type);

const rbs_renderer_class *rbsf_csv_class(void) { return &csv_class; }
const rbs_renderer_class *rbsf_json_class(void) { return &json_class; }
const rbs_renderer_class *rbsf_stats_class(void) { return &stats_class; }

rbs_status rbsf_dump_bind(rbsf_dump_bound *bound, const rbs_renderer_class *dump_class,
                          rbsf_stopper *stopper)
{
    if (bound == NULL || (dump_class != &csv_class && dump_class != &json_class &&
                          dump_class != &stats_class))
        return RBS_E_INVALID;
    bound->cls = *dump_class;
    bound->type = *(const dump_type *)dump_class->context;
    bound->type.stopper = stopper;
    bound->cls.context = &bound->type;
    return RBS_OK;
}
