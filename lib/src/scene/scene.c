/*
 * scene.c - the scene object: errors, loading, accessors, and building a
 * world from the validated description.
 */
#include "scene/scene_internal.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

char *rbs__strdup(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d != NULL) {
        memcpy(d, s, n);
    }
    return d;
}

rbs_scene *rbs__scene_new(void)
{
    rbs_scene *scene = calloc(1, sizeof *scene);
    rbs_world_def def;
    if (scene == NULL) {
        return NULL;
    }
    rbs_world_def_init(&def);
    scene->slop = def.slop; /* the world's defaults */
    scene->max_sweeps = def.max_sweeps;
    scene->max_substeps = def.max_substeps;
    scene->soft_substeps = def.soft_substeps;
    scene->soft_tolerance = def.soft_tolerance;
    scene->dt = 0.001;
    scene->gravity.z = -9.81;
    scene->gravity_mode = RBS_GRAVITY_ACCELERATION;
    scene->method = RBS_METHOD_AUTO;
    scene->tolerance = 1e-9;
    scene->restitution = 0.5;
    scene->gravity_constant = 6.674e-11;
    return scene;
}

int32_t rbs__scene_add_file(rbs_scene *scene, const char *name)
{
    char *copy;
    if (scene->file_count >= RBS__SCENE_FILES_MAX) {
        return -1;
    }
    copy = rbs__strdup(name != NULL ? name : "<scene>");
    if (copy == NULL) {
        return -1;
    }
    scene->files[scene->file_count] = copy;
    return scene->file_count++;
}

/* Make a piece of an error message safe to print, in place: each character
 * rbs_text_shown_len() does not show (a control such as ESC, DEL, a C1
 * control, a bidirectional override, ...) and each byte of invalid UTF-8
 * becomes one '?'.  Keys, names and types from the input reach the
 * messages through key paths and values; written raw they could move the
 * cursor, recolour or reorder the terminal that shows them. */
static void clean_for_display(char *s)
{
    char *in = s, *out = s;
    size_t left = strlen(s); /* bytes from in to the end */
    while (left > 0) {
        size_t skip, n = rbs_text_shown_len(in, left, &skip);
        if (n > 0)
            memmove(out, in, n); /* (never ahead of in) */
        else
            *out = '?';
        out += n > 0 ? n : 1;
        in += skip;
        left -= skip;
    }
    *out = '\0';
}

/* Record an error or a warning in list (kept, counted). */
static void record(rbs_scene *scene, rbs__scene_err *list, uint32_t *kept, uint32_t *count,
                   rbs__loc at, const char *path, const char *fmt, va_list ap)
{
    char message[512], head[64], where[512];
    const char *file;
    size_t nt, nf, np, nm;
    char *buf;
    rbs__scene_err *e;
    (*count)++;
    if (*kept >= RBS_SCENE_ERRORS_MAX) {
        return;
    }
    rbs__vsnprintf_c(message, sizeof message, fmt, ap);
    if (path == NULL) {
        path = "";
    }
    file = at.file >= 0 && at.file < scene->file_count ? scene->files[at.file]
                                                       : "command line";
    if (at.line > 0) {
        snprintf(head, sizeof head, ":%ld:%ld", (long)at.line, (long)at.column);
    } else {
        head[0] = '\0';
    }
    snprintf(where, sizeof where, "%s", path);
    clean_for_display(where);
    clean_for_display(message);
    path = where;
    nf = strlen(file);
    np = strlen(path);
    nm = strlen(message);
    nt = nf + strlen(head) + 2 + np + (np ? 2 : 0) + nm;
    buf = malloc(nt + 1 + nf + 1 + np + 1 + nm + 1);
    if (buf == NULL) {
        return; /* counted, not kept */
    }
    snprintf(buf, nt + 1, "%s%s: %s%s%s", file, head, path, np ? ": " : "", message);
    clean_for_display(buf); /* (a file named in a config.txt; e->pub.file keeps it as given) */
    memcpy(buf + nt + 1, file, nf + 1);
    memcpy(buf + nt + 1 + nf + 1, path, np + 1);
    memcpy(buf + nt + 1 + nf + 1 + np + 1, message, nm + 1);
    e = &list[(*kept)++];
    e->buf = buf;
    e->file = at.file;
    e->pub.text = buf;
    e->pub.file = buf + nt + 1;
    e->pub.path = buf + nt + 1 + nf + 1;
    e->pub.message = buf + nt + 1 + nf + 1 + np + 1;
    e->pub.line = at.line;
    e->pub.column = at.column;
}

void rbs__scene_error(rbs_scene *scene, rbs__loc at, const char *path,
                      const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    record(scene, scene->errors, &scene->error_kept, &scene->error_count, at, path, fmt, ap);
    va_end(ap);
}

void rbs__scene_warning(rbs_scene *scene, rbs__loc at, const char *path,
                        const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    record(scene, scene->warnings, &scene->warning_kept, &scene->warning_count, at, path, fmt,
           ap);
    va_end(ap);
}

static int error_before(const rbs__scene_err *a, const rbs__scene_err *b)
{
    if (a->file != b->file) {
        return a->file < b->file;
    }
    if (a->pub.line != b->pub.line) {
        return a->pub.line < b->pub.line;
    }
    return a->pub.column < b->pub.column;
}

void rbs__scene_sort_errors(rbs_scene *scene)
{
    /* insertion sort: at most RBS_SCENE_ERRORS_MAX, stable */
    uint32_t i, j;
    for (i = 1; i < scene->error_kept; i++) {
        rbs__scene_err e = scene->errors[i];
        for (j = i; j > 0 && error_before(&e, &scene->errors[j - 1]); j--) {
            scene->errors[j] = scene->errors[j - 1];
        }
        scene->errors[j] = e;
    }
}

size_t rbs__edit_distance(const char *a, const char *b)
{
    /* Levenshtein distance over at most 64 bytes of each word. */
    size_t row[65];
    size_t la = strlen(a), lb = strlen(b), i, j;
    if (la > 64) {
        la = 64;
    }
    if (lb > 64) {
        lb = 64;
    }
    for (j = 0; j <= lb; j++) {
        row[j] = j;
    }
    for (i = 1; i <= la; i++) {
        size_t diag = row[0];
        row[0] = i;
        for (j = 1; j <= lb; j++) {
            size_t up = row[j];
            size_t best = diag + (a[i - 1] == b[j - 1] ? 0 : 1);
            if (up + 1 < best) {
                best = up + 1;
            }
            if (row[j - 1] + 1 < best) {
                best = row[j - 1] + 1;
            }
            row[j] = best;
            diag = up;
        }
    }
    return row[lb];
}

const char *rbs__suggest(const char *word, const char *const *candidates, size_t n)
{
    const char *best = NULL;
    size_t best_d = (size_t)-1, i, limit;
    limit = strlen(word) / 3;
    if (limit < 2) {
        limit = 2;
    }
    for (i = 0; i < n; i++) {
        size_t d = rbs__edit_distance(word, candidates[i]);
        if (d < best_d) {
            best_d = d;
            best = candidates[i];
        }
    }
    if (best_d <= limit) {
        return best;
    }
    /* an abbreviation ("accel" for "acceleration") */
    if (strlen(word) >= 3) {
        for (i = 0; i < n; i++) {
            if (strncmp(word, candidates[i], strlen(word)) == 0) {
                return candidates[i];
            }
        }
    }
    return NULL;
}

const char *rbs_scene_suggest(const char *word, const char *const *candidates, size_t n)
{
    size_t i;
    if (word == NULL || candidates == NULL) {
        return NULL;
    }
    for (i = 0; i < n; i++) {
        if (candidates[i] == NULL) {
            return NULL;
        }
    }
    return rbs__suggest(word, candidates, n);
}

/* Record "cannot <verb> 'path': <strerror(err)>". */
static void io_error(rbs_scene *scene, rbs__loc at, const char *verb, const char *path,
                     int err)
{
    char why[128];
    if (strerror_r(err, why, sizeof why) != 0) {
        snprintf(why, sizeof why, "error %d", err);
    }
    rbs__scene_error(scene, at, "", "cannot %s '%s': %s", verb, path, why);
}

static void too_large(rbs_scene *scene, rbs__loc at, const char *path)
{
    rbs__scene_error(scene, at, "", "cannot read '%s': larger than %lu bytes", path,
                     (unsigned long)RBS__SCENE_FILE_MAX);
}

rbs_status rbs__read_file(rbs_scene *scene, const char *path, rbs__loc at,
                          char **text, size_t *len, int *stream)
{
    FILE *f;
    char *buf = NULL;
    size_t n = 0, cap;
    struct stat st;
    *text = NULL;
    *len = 0;
    if (stream != NULL) {
        *stream = 0;
    }
    /* One open, one pass: a pipe, FIFO or /dev/stdin cannot be read twice. */
    f = fopen(path, "rb");
    if (f == NULL) {
        io_error(scene, at, "open", path, errno);
        return RBS_E_IO;
    }
    if (fstat(fileno(f), &st) != 0) {
        io_error(scene, at, "read", path, errno);
        fclose(f);
        return RBS_E_IO;
    }
    if (S_ISDIR(st.st_mode)) {
        rbs__scene_error(scene, at, "", "cannot read '%s': is a directory", path);
        fclose(f);
        return RBS_E_IO;
    }
    /* A regular file's size is known: refuse it unread if too large, else
     * read it in one buffer (+1 so that the end shows without a regrowth).
     * A stream (or a file of size 0, as in /proc) grows its buffer. */
    if (S_ISREG(st.st_mode) && (uintmax_t)st.st_size > RBS__SCENE_FILE_MAX) {
        too_large(scene, at, path);
        fclose(f);
        return RBS_E_IO;
    }
    if (stream != NULL) {
        *stream = !S_ISREG(st.st_mode);
    }
    cap = S_ISREG(st.st_mode) && st.st_size > 0 ? (size_t)st.st_size + 1 : 65536;
    for (;;) {
        size_t got;
        if (buf == NULL || n == cap) {
            /* the first buffer, or full: double, but never past the limit
             * + 1 byte, the byte that tells a stream over the limit */
            char *bigger;
            if (buf != NULL) {
                cap = cap > (RBS__SCENE_FILE_MAX + 1) / 2 ? RBS__SCENE_FILE_MAX + 1
                                                          : cap * 2;
            }
            bigger = realloc(buf, cap + 1);
            if (bigger == NULL) {
                rbs__scene_error(scene, at, "", "cannot read '%s': out of memory", path);
                free(buf);
                fclose(f);
                return RBS_E_MEMORY;
            }
            buf = bigger;
        }
        got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (n > RBS__SCENE_FILE_MAX) {
            too_large(scene, at, path); /* read no further */
            free(buf);
            fclose(f);
            return RBS_E_IO;
        }
        if (n < cap) {
            break; /* fread stops short only at the end or on an error */
        }
    }
    if (ferror(f)) {
        io_error(scene, at, "read", path, errno);
        free(buf);
        fclose(f);
        return RBS_E_IO;
    }
    fclose(f);
    buf[n] = '\0';
    *text = buf;
    *len = n;
    return RBS_OK;
}

/* Parse JSON text into an existing scene (file already registered). */
static void scene_parse_json_into(rbs_scene *scene, const char *text, size_t len,
                                  int32_t file)
{
    rbs__src src;
    rbs__posmap map;
    cJSON *tree = NULL;
    memset(&map, 0, sizeof map);
    if (rbs__src_init(&src, text, len) != 0) {
        rbs__loc none = {file, 0, 0};
        rbs__scene_error(scene, none, "", "out of memory");
        return;
    }
    if (rbs__json_parse(scene, &src, file, &map, &tree) == 0) {
        rbs__scene_validate(scene, tree, &map, &src, 1);
    }
    cJSON_Delete(tree);
    rbs__posmap_fini(&map);
    rbs__src_fini(&src);
}

static rbs_status scene_result(rbs_scene *scene, rbs_status io, rbs_scene **out)
{
    if (io != RBS_OK && io != RBS_E_IO && io != RBS_E_SCENE) {
        rbs_scene_free(scene); /* e.g. RBS_E_MEMORY: no scene, as documented */
        *out = NULL;
        return io;
    }
    *out = scene;
    if (io != RBS_OK) {
        return io;
    }
    return scene->error_count > 0 ? RBS_E_SCENE : RBS_OK;
}

static rbs_status scene_parse_json(const char *text, size_t len, const char *name,
                                   rbs_scene **out)
{
    rbs_scene *scene;
    int32_t file;
    if (out == NULL) {
        return RBS_E_INVALID;
    }
    *out = NULL;
    if (text == NULL && len > 0) {
        return RBS_E_INVALID;
    }
    scene = rbs__scene_new();
    if (scene == NULL) {
        return RBS_E_MEMORY;
    }
    file = rbs__scene_add_file(scene, name != NULL ? name : "<json>");
    if (file < 0) {
        rbs_scene_free(scene);
        return RBS_E_MEMORY;
    }
    scene_parse_json_into(scene, text != NULL ? text : "", len, file);
    rbs__scene_sort_errors(scene);
    return scene_result(scene, RBS_OK, out);
}

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcmp(s + n - m, suffix) == 0;
}

/* The index of text's first byte after blanks (and a UTF-8 byte order
 * mark); len if there is none. */
static size_t skip_blanks(const char *text, size_t len)
{
    size_t i = len >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
    while (i < len &&
           (text[i] == ' ' || text[i] == '\t' || text[i] == '\r' || text[i] == '\n'))
        i++;
    return i;
}

/* Whether text holds nothing but blanks (and a byte order mark). */
static int is_blank(const char *text, size_t len) { return skip_blanks(text, len) == len; }

/* The first byte after blanks (and a UTF-8 byte order mark) is '{': a JSON
 * scene, whatever its name.  A text scene's first line is a comment or
 * "key = value". */
static int starts_like_json(const char *text, size_t len)
{
    const size_t i = skip_blanks(text, len);
    return i < len && text[i] == '{';
}

static rbs_status scene_load(const char *path, rbs_scene_format format, rbs_scene **out)
{
    rbs_scene *scene;
    struct stat st;
    char *dirpath = NULL, *text = NULL;
    size_t len = 0;
    int stream = 0;
    int32_t file;
    rbs__loc at = {0, 0, 0};
    rbs_status status;
    if (out == NULL) {
        return RBS_E_INVALID;
    }
    *out = NULL;
    if (path == NULL || (format != RBS_SCENE_AUTO && format != RBS_SCENE_JSON &&
                         format != RBS_SCENE_TEXT)) {
        return RBS_E_INVALID;
    }
    scene = rbs__scene_new();
    if (scene == NULL) {
        return RBS_E_MEMORY;
    }
    /* a folder stands for its config.txt */
    if (format != RBS_SCENE_JSON && stat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
        size_t n = strlen(path);
        dirpath = malloc(n + sizeof "/config.txt");
        if (dirpath == NULL) {
            rbs_scene_free(scene);
            return RBS_E_MEMORY;
        }
        memcpy(dirpath, path, n);
        memcpy(dirpath + n, (n > 0 && path[n - 1] == '/') ? "config.txt" : "/config.txt",
               (n > 0 && path[n - 1] == '/') ? sizeof "config.txt" : sizeof "/config.txt");
        path = dirpath;
        format = RBS_SCENE_TEXT;
    }
    /* The file is read once, then its format told from the bytes read: a
     * pipe or FIFO cannot be opened and read a second time. */
    file = rbs__scene_add_file(scene, path); /* file 0 in either format */
    if (file != 0) {
        free(dirpath);
        rbs_scene_free(scene);
        return RBS_E_MEMORY;
    }
    scene->file_read[0] = 1;
    status = rbs__read_file(scene, path, at, &text, &len, &stream);
    if (status == RBS_OK && format == RBS_SCENE_AUTO && is_blank(text, len) &&
        !ends_with(path, ".json") && !ends_with(path, ".JSON")) {
        /* Nothing to tell the format by (an empty pipe, a closed standard
         * input: "rbsim run -" with nothing piped): say so, where it said
         * "missing objects = FILE" as for a config.txt without that line (a
         * probe of session 46). */
        rbs__loc first = {0, 1, 1};
        rbs__scene_error(scene, first, "",
                         "empty input: expected a scene (a JSON object, or the "
                         "lines of a config.txt)");
        free(text);
    } else if (status == RBS_OK) {
        if (format == RBS_SCENE_AUTO) {
            format = ends_with(path, ".json") || ends_with(path, ".JSON") ||
                             starts_like_json(text, len)
                         ? RBS_SCENE_JSON
                         : RBS_SCENE_TEXT;
        }
        if (format == RBS_SCENE_JSON) {
            scene_parse_json_into(scene, text, len, file);
            free(text);
        } else {
            status = rbs__text_load(scene, path, text, len, stream); /* owns text */
        }
    }
    free(dirpath);
    rbs__scene_sort_errors(scene);
    return scene_result(scene, status, out);
}

void rbs_scene_free(rbs_scene *scene)
{
    uint32_t i;
    int32_t f;
    if (scene == NULL) {
        return;
    }
    for (i = 0; i < scene->error_kept; i++) {
        free(scene->errors[i].buf);
    }
    for (i = 0; i < scene->warning_kept; i++) {
        free(scene->warnings[i].buf);
    }
    for (f = 0; f < scene->file_count; f++) {
        free(scene->files[f]);
    }
    for (i = 0; i < scene->renderer_count; i++) {
        free(scene->renderers[i].type);
        free(scene->renderers[i].json);
    }
    free(scene->description);
    free(scene->materials);
    free(scene->pairs);
    free(scene->bodies);
    free(scene);
}

uint32_t rbs_scene_error_count(const rbs_scene *scene)
{
    return scene != NULL ? scene->error_count : 0;
}

rbs_status rbs_scene_error_get(const rbs_scene *scene, uint32_t i, rbs_scene_error *out)
{
    if (scene == NULL || out == NULL) {
        return RBS_E_INVALID;
    }
    if (i >= scene->error_kept) {
        return RBS_E_NOT_FOUND;
    }
    *out = scene->errors[i].pub;
    return RBS_OK;
}

uint32_t rbs_scene_warning_count(const rbs_scene *scene)
{
    return scene != NULL ? scene->warning_count : 0;
}

rbs_status rbs_scene_warning_get(const rbs_scene *scene, uint32_t i, rbs_scene_error *out)
{
    if (scene == NULL || out == NULL) {
        return RBS_E_INVALID;
    }
    if (i >= scene->warning_kept) {
        return RBS_E_NOT_FOUND;
    }
    *out = scene->warnings[i].pub;
    return RBS_OK;
}

rbs_status rbs_scene_world_def(const rbs_scene *scene, rbs_world_def *out)
{
    uint32_t n;
    if (scene == NULL || out == NULL) {
        return RBS_E_INVALID;
    }
    if (scene->error_count > 0) {
        return RBS_E_SCENE;
    }
    rbs_world_def_init(out);
    n = scene->body_count > 0 ? scene->body_count : 1;
    out->max_bodies = n;
    out->max_materials = scene->material_count > 0 ? scene->material_count : 1;
    out->max_pairs = scene->pair_count > 0 ? scene->pair_count : 1;
    out->max_contacts = scene->max_contacts > 0           ? scene->max_contacts
                        : n > (UINT32_MAX - 16) / 4 ? UINT32_MAX
                                                    : 4 * n + 16;
    out->dt = scene->dt;
    out->gravity = scene->gravity;
    out->gravity_mode = scene->gravity_mode;
    out->restitution = scene->restitution;
    out->method = scene->method;
    out->tolerance = scene->tolerance;
    out->slop = scene->slop;
    out->max_sweeps = scene->max_sweeps;
    out->max_substeps = scene->max_substeps;
    out->soft_substeps = scene->soft_substeps;
    out->soft_tolerance = scene->soft_tolerance;
    out->mutual_gravity = scene->mutual_gravity;
    out->gravity_constant = scene->gravity_constant;
    out->softening = scene->softening;
    return RBS_OK;
}

rbs_status rbs_scene_populate(const rbs_scene *scene, rbs_world *world)
{
    rbs_material_id *ids;
    rbs_material_id none = {0, 0};
    rbs_status st = RBS_OK;
    uint32_t i;
    if (scene == NULL || world == NULL) {
        return RBS_E_INVALID;
    }
    if (scene->error_count > 0) {
        return RBS_E_SCENE;
    }
    ids = calloc(scene->material_count + 1, sizeof *ids);
    if (ids == NULL) {
        return RBS_E_MEMORY;
    }
    for (i = 0; i < scene->material_count && st == RBS_OK; i++) {
        st = rbs_world_add_material(world, scene->materials[i], &ids[i]);
    }
    for (i = 0; i < scene->pair_count && st == RBS_OK; i++) {
        const rbs__scene_pair *p = &scene->pairs[i];
        rbs_pair_def def;
        rbs_pair_def_init(&def);
        def.a = p->a >= 0 ? ids[p->a] : none;
        def.b = p->b >= 0 ? ids[p->b] : none;
        def.static_friction = p->static_friction;
        def.kinetic_friction = p->kinetic_friction;
        def.restitution = p->restitution;
        def.rolling = p->rolling;
        def.spinning = p->spinning;
        st = rbs_world_set_pair(world, &def);
    }
    for (i = 0; i < scene->body_count && st == RBS_OK; i++) {
        const rbs__scene_body *b = &scene->bodies[i];
        rbs_body_id id;
        if (b->type == RBS_BODY_SPHERE) {
            rbs_sphere_def def;
            rbs_sphere_def_init(&def);
            def.name = b->name;
            def.radius = b->radius;
            def.mass = b->density > 0 ? 0.0 : b->mass;
            def.density = b->density;
            def.inertia_kind = b->inertia_kind;
            def.inertia = b->inertia;
            def.position = b->position;
            def.orientation = b->orientation;
            def.velocity = b->velocity;
            def.angular_velocity = b->angular_velocity;
            def.center_of_mass = b->center_of_mass;
            def.force = b->force;
            def.torque = b->torque;
            def.material = b->material >= 0 ? ids[b->material] : none;
            def.color = b->color;
            def.texture = b->texture;
            def.fixed = b->fixed;
            st = rbs_world_add_sphere(world, &def, &id);
        } else {
            rbs_plane_def def;
            rbs_plane_def_init(&def);
            def.name = b->name;
            def.point = b->point;
            def.normal = b->normal;
            def.material = b->material >= 0 ? ids[b->material] : none;
            def.color = b->color;
            def.texture = b->texture;
            st = rbs_world_add_plane(world, &def, &id);
        }
    }
    free(ids);
    return st;
}

rbs_status rbs_scene_build(const rbs_scene *scene, rbs_world **out)
{
    rbs_world_def def;
    rbs_world *world = NULL;
    rbs_status st;
    if (out == NULL) {
        return RBS_E_INVALID;
    }
    *out = NULL;
    st = rbs_scene_world_def(scene, &def);
    if (st != RBS_OK) {
        return st;
    }
    st = rbs_world_create(&def, &world);
    if (st != RBS_OK) {
        return st;
    }
    st = rbs_scene_populate(scene, world);
    if (st != RBS_OK) {
        rbs_world_destroy(world);
        return st;
    }
    *out = world;
    return RBS_OK;
}

uint64_t rbs_scene_steps(const rbs_scene *scene)
{
    return scene != NULL ? scene->steps : 0;
}

double rbs_scene_dt(const rbs_scene *scene)
{
    return scene != NULL ? scene->dt : 0.0;
}

const char *rbs_scene_description(const rbs_scene *scene)
{
    return scene != NULL && scene->description != NULL ? scene->description : "";
}

int32_t rbs_scene_pause_on_collision(const rbs_scene *scene)
{
    return scene != NULL ? scene->pause_on_collision : 0;
}

/* --method event on a scene outside that method's scope (as the scene's own
 * "method": "event" would be reported at load, rbs__scene_validate): the
 * first thing it refuses, which its step would refuse. */
static void event_override(rbs_scene *scene)
{
    rbs__loc none = {-1, 0, 0};
    unsigned char *refused;
    uint32_t i;
    int n;
    if (scene->mutual_gravity && rbs__scene_mutual_acts(scene)) {
        rbs__scene_error(scene, none, "--method",
                         "method \"event\" does not support mutual gravity "
                         "(simulation.mutual_gravity; not a constant force); use \"adaptive\"");
        return;
    }
    refused = malloc(scene->pair_count + 1);
    n = refused != NULL ? rbs__event_rows(scene, refused) : -1;
    for (i = 0; n != 0 && i < scene->pair_count; i++) {
        const rbs__scene_pair *p = &scene->pairs[i];
        if (n > 0 && !refused[i]) {
            continue;
        }
        if (n < 0) {
            rbs__scene_error(scene, none, "--method", "out of memory");
        } else {
            rbs__scene_error(scene, none, "--method",
                             "method \"event\" does not support rolling and spinning resistance "
                             "(materials[%lu], pair \"%s\"/\"%s\"); use \"euler\"",
                             (unsigned long)i, p->a >= 0 ? scene->materials[p->a] : "*",
                             p->b >= 0 ? scene->materials[p->b] : "*");
        }
        free(refused);
        return;
    }
    free(refused);
    for (i = 0; i < scene->body_count; i++) {
        int why = rbs__event_sphere_refused(scene, i);
        if (why != 0) {
            rbs__scene_error(scene, none, "--method",
                             "method \"event\" does not support a moving sphere with %s "
                             "(bodies[%lu], \"%s\"); use \"euler\"",
                             why == 2 ? "an off-centre mass" : "anisotropic inertia",
                             (unsigned long)i, scene->bodies[i].name);
            return;
        }
    }
}

static rbs_status scene_override(rbs_scene *scene, uint64_t steps, double dt,
                                 const char *method)
{
    rbs__loc none = {-1, 0, 0};
    uint64_t new_steps;
    double new_dt;
    rbs_method new_method;
    uint32_t before;
    if (scene == NULL) {
        return RBS_E_INVALID;
    }
    before = scene->error_count;
    new_steps = steps != 0 ? steps : scene->steps;
    new_dt = scene->dt;
    new_method = scene->method;
    if (!(dt <= 0.0)) {
        if (!isfinite(dt)) {
            rbs__scene_error(scene, none, "--dt", "must be a finite number > 0, got %g",
                             dt);
        } else {
            new_dt = dt;
        }
    }
    if (new_steps > ((uint64_t)1 << 53)) { /* not (double)new_steps: 2^53 + 1 rounds */
        rbs__scene_error(scene, none, "--steps", "must be at most 2^53, got %llu",
                         (unsigned long long)new_steps);
    } else if (!isfinite((double)new_steps * new_dt)) {
        /* (named by the override that made it: --dt 1e306 alone was
         * blamed on --steps; a probe of session 45) */
        rbs__scene_error(scene, none, steps != 0 ? "--steps" : "--dt",
                         "steps * dt overflows (%llu * %g)",
                         (unsigned long long)new_steps, new_dt);
    }
    if (method != NULL && rbs_method_from_name(method, &new_method) != RBS_OK) {
        const char *names[RBS_METHOD_COUNT];
        const char *hint;
        char list[256];
        size_t used = 0;
        int k;
        /* the names and the list "euler, ... or soft" from the library's
         * own table, so that a new method is named here too */
        list[0] = '\0';
        for (k = 0; k < RBS_METHOD_COUNT; k++) {
            int w;
            names[k] = rbs_method_name((rbs_method)k);
            if (names[k] == NULL) {
                names[k] = "";
            }
            w = snprintf(list + used, sizeof list - used, "%s%s",
                         k == 0 ? "" : (k == RBS_METHOD_COUNT - 1 ? " or " : ", "),
                         names[k]);
            if (w > 0 && (size_t)w < sizeof list - used) {
                used += (size_t)w;
            }
        }
        hint = rbs__suggest(method, names, RBS_METHOD_COUNT);
        rbs__scene_error(scene, none, "--method",
                         "unknown method \"%.64s\"%s%s%s; expected %s", method,
                         hint ? " (did you mean \"" : "", hint ? hint : "",
                         hint ? "\"?)" : "", list);
    }
    if (scene->error_count == before && new_method == RBS_METHOD_EVENT &&
        scene->method != RBS_METHOD_EVENT) {
        event_override(scene);
    }
    if (scene->error_count != before) {
        return RBS_E_SCENE;
    }
    scene->steps = new_steps;
    scene->dt = new_dt;
    scene->method = new_method;
    return RBS_OK;
}

rbs_status rbs_scene_override_slop(rbs_scene *scene, double slop)
{
    rbs__loc none = {-1, 0, 0};
    if (scene == NULL) {
        return RBS_E_INVALID;
    }
    if (!(slop > 0.0 && slop < RBS__SCENE_SLOP_MAX)) {
        rbs__scene_error(scene, none, "--slop",
                         RBS__SCENE_SLOP_RANGE ", got %g", slop);
        return RBS_E_SCENE;
    }
    scene->slop = slop;
    return RBS_OK;
}

uint32_t rbs_scene_renderer_count(const rbs_scene *scene)
{
    return scene != NULL ? scene->renderer_count : 0;
}

rbs_status rbs_scene_renderer_get(const rbs_scene *scene, uint32_t i,
                                  rbs_scene_renderer *out)
{
    const rbs__scene_renderer *r;
    if (scene == NULL || out == NULL) {
        return RBS_E_INVALID;
    }
    if (i >= scene->renderer_count) {
        return RBS_E_NOT_FOUND;
    }
    r = &scene->renderers[i];
    out->type = r->type;
    out->json = r->json;
    out->file = r->at.file >= 0 && r->at.file < scene->file_count
                    ? scene->files[r->at.file]
                    : "";
    out->line = r->at.line;
    out->column = r->at.column;
    return RBS_OK;
}

const char *rbs_scene_source(const rbs_scene *scene, uint32_t i)
{
    int32_t f;
    if (scene == NULL) {
        return NULL;
    }
    for (f = 0; f < scene->file_count; f++) {
        if (scene->file_read[f] && i-- == 0) {
            return scene->files[f];
        }
    }
    return NULL;
}

static rbs_status scene_save(const rbs_scene *scene, const char *path,
                             rbs_scene_format format, char *message, size_t message_size)
{
    if (message != NULL && message_size > 0) {
        message[0] = '\0';
    }
    if (scene == NULL || path == NULL) {
        return RBS_E_INVALID;
    }
    if (scene->error_count > 0) {
        return RBS_E_SCENE;
    }
    if (format == RBS_SCENE_AUTO) {
        format = ends_with(path, ".json") || ends_with(path, ".JSON") ? RBS_SCENE_JSON
                                                                     : RBS_SCENE_TEXT;
    }
    if (format == RBS_SCENE_JSON) {
        return rbs__scene_save_json(scene, path, message, message_size);
    }
    if (format == RBS_SCENE_TEXT) {
        return rbs__scene_save_text(scene, path, message, message_size);
    }
    return RBS_E_INVALID;
}

/* The public entry points that read or write numbers, in the "C" locale. */

rbs_status rbs_scene_parse_json(const char *text, size_t len, const char *name,
                                rbs_scene **out)
{
    rbs__locale l;
    rbs_status st;
    rbs__c_locale_push(&l);
    st = scene_parse_json(text, len, name, out);
    rbs__c_locale_pop(&l);
    return st;
}

rbs_status rbs_scene_load(const char *path, rbs_scene_format format, rbs_scene **out)
{
    rbs__locale l;
    rbs_status st;
    rbs__c_locale_push(&l);
    st = scene_load(path, format, out);
    rbs__c_locale_pop(&l);
    return st;
}

rbs_status rbs_scene_save(const rbs_scene *scene, const char *path,
                          rbs_scene_format format)
{
    rbs__locale l;
    rbs_status st;
    rbs__c_locale_push(&l);
    st = scene_save(scene, path, format, NULL, 0);
    rbs__c_locale_pop(&l);
    return st;
}

rbs_status rbs_scene_save_v2(const rbs_scene *scene, const char *path, rbs_scene_format format,
                             char *message, size_t message_size)
{
    rbs__locale l;
    rbs_status st;
    rbs__c_locale_push(&l);
    st = scene_save(scene, path, format, message, message_size);
    rbs__c_locale_pop(&l);
    return st;
}

rbs_status rbs_scene_override(rbs_scene *scene, uint64_t steps, double dt,
                              const char *method)
{
    rbs__locale l;
    rbs_status st;
    rbs__c_locale_push(&l);
    st = scene_override(scene, steps, dt, method);
    rbs__c_locale_pop(&l);
    return st;
}
