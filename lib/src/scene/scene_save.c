/*
 * scene_save.c - write a scene description as JSON or as the text format.
 *
 * Numbers are written with the fewest digits that read back to the same
 * double, so saving and loading again gives a bit-identical scene.
 */
#include "scene/scene_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/world_internal.h" /* rbs__link_target */

/* A file being written: the target (through any symbolic link), its
 * temporary beside it and the stream to the temporary.  A save writes all
 * its files to temporaries and renames them into place only when every one
 * is complete, so a failed save leaves what was there before; a device,
 * FIFO or folder in a target's place is refused, never replaced. */
typedef struct staged {
    char *path;
    char *tmp;
    FILE *f;
    char *made_dir; /* the missing folder stage_open made, removed on failure */
} staged;

/* Report of a failed save: "cannot write 'PATH': REASON". */
typedef struct save_report {
    char *text;
    size_t size;
} save_report;

static rbs_status report(save_report *r, rbs_status st, const char *path, const char *why)
{
    if (r->text != NULL && r->size > 0 && r->text[0] == '\0') {
        snprintf(r->text, r->size, "cannot write '%s': %s", path, why);
    }
    return st;
}

/* Why a file at path could not be made when open() said e (ENOENT or
 * ENOTDIR), in why (n bytes): the part of its folder that is not a folder,
 * or the folder that does not exist (a save makes one missing folder, not
 * more).  Else the system's reason. */
static void folder_reason(const char *path, int e, char *why, size_t n)
{
    const char *slash = strrchr(path, '/');
    char *dir;
    struct stat sb;
    size_t d;
    int depth = 0;
    snprintf(why, n, "%s", strerror(e));
    if ((e != ENOENT && e != ENOTDIR) || slash == NULL || slash == path)
        return;
    d = (size_t)(slash - path);
    if ((dir = malloc(d + 1)) == NULL)
        return;
    memcpy(dir, path, d);
    dir[d] = '\0';
    while (stat(dir, &sb) != 0) {
        char *up = strrchr(dir, '/');
        if (errno != ENOENT && errno != ENOTDIR) {
            free(dir);
            return;
        }
        if (up == NULL)
            strcpy(dir, "."); /* (dir holds at least one byte and its NUL) */
        else
            up[up == dir] = '\0'; /* ("/x" goes up to "/") */
        depth++;
    }
    if (!S_ISDIR(sb.st_mode)) {
        snprintf(why, n, "'%s' is not a folder", dir);
    } else if (depth > 0) {
        char *missing = malloc(d + 1);
        if (missing != NULL) {
            memcpy(missing, path, d);
            missing[d] = '\0';
            if (depth > 1)
                snprintf(why, n, "folder '%s' does not exist (a save makes one missing "
                                 "folder, not more)", missing);
            else
                snprintf(why, n, "folder '%s' does not exist and could not be made in "
                                 "'%s'", missing, dir);
            free(missing);
        }
    }
    free(dir);
}

/* The file scene s was read from that the file at `file` (stat'ed) is, as
 * the scene names it, or NULL if none. */
static const char *read_from(const rbs_scene *s, const struct stat *file)
{
    int32_t i;
    for (i = 0; i < s->file_count; i++) {
        struct stat sb;
        if (s->files[i] != NULL && stat(s->files[i], &sb) == 0 && sb.st_dev == file->st_dev &&
            sb.st_ino == file->st_ino)
            return s->files[i];
    }
    return NULL;
}

/* Open o's temporary for path; a missing parent folder (one level) is made.
 * An existing target is refused if it is a file scene s was read from (a
 * convert onto its own input, or a text config onto its materials.txt) or
 * has no write permission at all (mode 444: not replaced behind its back). */
static rbs_status stage_open(staged *o, const rbs_scene *s, const char *path, save_report *r)
{
    struct stat sb, file;
    size_t n;
    int fd = -1, attempt, have = 0;
    o->f = NULL;
    o->tmp = NULL;
    o->made_dir = NULL;
    o->path = rbs__link_target(path);
    if (o->path == NULL) {
        return errno == ENOMEM ? RBS_E_MEMORY
                               : report(r, RBS_E_IO, path, "a loop of symbolic links");
    }
    if (stat(o->path, &file) == 0) {
        const char *src = S_ISREG(file.st_mode) ? read_from(s, &file) : NULL;
        if (src != NULL) {
            /* (named as the caller wrote it, and as the scene was read) */
            char why[600];
            if (strcmp(src, path) == 0)
                snprintf(why, sizeof why, "it is a file this scene was read from; write elsewhere");
            else
                snprintf(why, sizeof why, "it is '%.500s', a file this scene was read from; write elsewhere",
                         src);
            return report(r, RBS_E_OWN_INPUT, path, why);
        }
        if (S_ISREG(file.st_mode) && !(file.st_mode & 0222))
            return report(r, RBS_E_IO, o->path, "it is read-only (no write permission): not replaced");
        if (!S_ISREG(file.st_mode)) {
            return report(r, RBS_E_IO, o->path,
                          S_ISDIR(file.st_mode) ? "is a folder"
                                                : "exists and is not a regular file");
        }
        have = 1;
    }
    {
        /* a missing parent folder (one level) is made */
        const char *slash = strrchr(o->path, '/');
        if (slash != NULL && slash != o->path) {
            size_t d = (size_t)(slash - o->path);
            char *dir = malloc(d + 1);
            if (dir == NULL) {
                return RBS_E_MEMORY;
            }
            memcpy(dir, o->path, d);
            dir[d] = '\0';
            if (stat(dir, &sb) != 0 && errno == ENOENT && mkdir(dir, 0777) == 0) {
                o->made_dir = dir; /* a failed save removes it again */
            } else {
                free(dir);
            }
        }
    }
    n = strlen(o->path) + 32;
    if ((o->tmp = malloc(n)) == NULL) {
        return RBS_E_MEMORY;
    }
    /* O_EXCL: never another writer's temporary (pid and attempt in the name) */
    for (attempt = 0; attempt < 100 && fd < 0; attempt++) {
        snprintf(o->tmp, n, "%s.tmp%ld.%d", o->path, (long)getpid(), attempt);
        fd = open(o->tmp, O_WRONLY | O_CREAT | O_EXCL, 0666);
        if (fd < 0 && errno != EEXIST) {
            break;
        }
    }
    if (fd < 0) {
        char why[400];
        folder_reason(o->path, errno, why, sizeof why);
        free(o->tmp);
        o->tmp = NULL;
        return report(r, RBS_E_IO, o->path, why);
    }
    if (have) {
        (void)fchmod(fd, file.st_mode & 07777); /* the replaced file's permissions */
    }
    if ((o->f = fdopen(fd, "w")) == NULL) {
        close(fd);
        return RBS_E_MEMORY;
    }
    return RBS_OK;
}

/* Close o's stream (its data complete on RBS_OK). */
static rbs_status stage_close(staged *o, save_report *r)
{
    int bad, e = 0;
    if (o->f == NULL) {
        return RBS_OK;
    }
    bad = fflush(o->f) != 0 || ferror(o->f);
    if (bad) {
        e = errno;
    }
    if (fclose(o->f) != 0 && !bad) {
        bad = 1;
        e = errno;
    }
    o->f = NULL;
    return bad ? report(r, RBS_E_IO, o->path, e != 0 ? strerror(e) : "write error") : RBS_OK;
}

/* Rename the temporaries into place if st is RBS_OK, else remove them;
 * frees the files either way. */
static rbs_status stage_finish(staged *o, int n, rbs_status st, save_report *r)
{
    int i;
    for (i = 0; i < n; i++) {
        rbs_status c = stage_close(&o[i], r);
        if (st == RBS_OK) {
            st = c;
        }
    }
    for (i = 0; i < n; i++) {
        if (o[i].tmp != NULL && st == RBS_OK && rename(o[i].tmp, o[i].path) != 0) {
            st = report(r, RBS_E_IO, o[i].path, strerror(errno));
        }
        if (o[i].tmp != NULL && st != RBS_OK) {
            (void)unlink(o[i].tmp);
        }
        free(o[i].tmp);
        free(o[i].path);
        o[i].tmp = o[i].path = NULL;
    }
    /* the folder a failed save made goes too, once its temporaries have */
    for (i = n - 1; i >= 0; i--) {
        if (o[i].made_dir != NULL && st != RBS_OK) {
            (void)rmdir(o[i].made_dir);
        }
        free(o[i].made_dir);
        o[i].made_dir = NULL;
    }
    return st;
}

/* Shortest "%.{15,16,17}g" that reads back exactly. */
static void fmt_num(char *out, size_t n, double x)
{
    int p;
    if (x == 0.0 && signbit(x)) {
        /* "-0" is the integer 0 to JSON readers that keep integers (Python's
         * json): "-0.0" keeps the sign for them, and reads back here as -0 */
        snprintf(out, n, "-0.0");
        return;
    }
    for (p = 15; p <= 17; p++) {
        snprintf(out, n, "%.*g", p, x);
        if (strtod(out, NULL) == x) {
            return;
        }
    }
}

static void put_num(FILE *f, double x)
{
    char buf[40];
    fmt_num(buf, sizeof buf, x);
    fputs(buf, f);
}

static void put_json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\') {
            fputc('\\', f);
            fputc(c, f);
        } else if (c == '\n') {
            fputs("\\n", f);
        } else if (c == '\t') {
            fputs("\\t", f);
        } else if (c == '\r') {
            fputs("\\r", f);
        } else if (c < 0x20 || c == 0x7f) {
            fprintf(f, "\\u%04x", c);
        } else {
            fputc(c, f);
        }
    }
    fputc('"', f);
}

static const char *texture_name(rbs_texture t)
{
    return t == RBS_TEXTURE_NONE ? "none" : t == RBS_TEXTURE_STRIPES ? "stripes" : "checker";
}


/* ---- keys and values, in either format --------------------------------- */

static void put_text_string(FILE *f, const char *str);

/* How a writer spells the keys of one group: what stands before the first
 * key, before a next key (on the same line or a new one) and after a key. */
typedef struct key_style {
    int json; /* words quoted, lists in brackets */
    const char *first, *next, *next_line, *after;
} key_style;

enum { KEY_FIRST, KEY_NEXT, KEY_NEXT_LINE };

static const key_style json_simulation = {1, "{\"", ", \"", ",\n    \"", "\": "};
static const key_style json_gravity = {1, "{\"", ", \"", ", \"", "\": "};
static const key_style json_body = {1, ", \"", ", \"", ",\n      \"", "\": "};
static const key_style text_config = {0, "", "\n", "\n", " = "};
static const key_style text_gravity = {0, "", " ", " ", "="};
static const key_style text_body = {0, "\n  ", "\n  ", "\n  ", " "};

/* where: KEY_FIRST, KEY_NEXT or KEY_NEXT_LINE. */
static void put_key(FILE *f, const key_style *k, const char *key, int where)
{
    fputs(where == KEY_FIRST ? k->first : where == KEY_NEXT ? k->next : k->next_line, f);
    fputs(key, f);
    fputs(k->after, f);
}

/* A word: quoted in JSON, bare in text. */
static void put_word(FILE *f, const key_style *k, const char *word)
{
    if (k->json) {
        fputc('"', f);
    }
    fputs(word, f);
    if (k->json) {
        fputc('"', f);
    }
}

/* Numbers: a JSON array, or words in text. */
static void put_list(FILE *f, const key_style *k, const double *x, int n)
{
    int i;
    if (k->json) {
        fputc('[', f);
    }
    for (i = 0; i < n; i++) {
        if (i > 0) {
            fputs(k->json ? ", " : " ", f);
        }
        put_num(f, x[i]);
    }
    if (k->json) {
        fputc(']', f);
    }
}

static void put_vec_field(FILE *f, const key_style *k, const char *key, int where, rbs_vec3 v)
{
    const double x[3] = {v.x, v.y, v.z};
    put_key(f, k, key, where);
    put_list(f, k, x, 3);
}

/* The simulation settings, from "steps" to "mutual_gravity" (its G and
 * softening in the style g). */
static void put_simulation(FILE *f, const key_style *k, const key_style *g, const rbs_scene *s)
{
    const char *method = rbs_method_name(s->method);
    rbs_world_def def;
    rbs_world_def_init(&def);
    put_key(f, k, "steps", KEY_FIRST);
    fprintf(f, "%llu", (unsigned long long)s->steps);
    put_key(f, k, "dt", KEY_NEXT);
    put_num(f, s->dt);
    put_vec_field(f, k, "gravity", KEY_NEXT, s->gravity);
    put_key(f, k, "gravity_mode", KEY_NEXT);
    put_word(f, k, s->gravity_mode == RBS_GRAVITY_FORCE ? "force" : "acceleration");
    put_key(f, k, "method", KEY_NEXT_LINE);
    put_word(f, k, method != NULL ? method : "euler");
    put_key(f, k, "tolerance", KEY_NEXT);
    put_num(f, s->tolerance);
    put_key(f, k, "slop", KEY_NEXT);
    put_num(f, s->slop);
    put_key(f, k, "max_sweeps", KEY_NEXT);
    fprintf(f, "%u", (unsigned)s->max_sweeps);
    if (s->max_contacts > 0) {
        /* (only when given: the default follows the bodies) */
        put_key(f, k, "max_contacts", KEY_NEXT);
        fprintf(f, "%u", (unsigned)s->max_contacts);
    }
    if (s->max_substeps != def.max_substeps) {
        /* (only when not the default: files without it stay as they were) */
        put_key(f, k, "max_substeps", KEY_NEXT);
        fprintf(f, "%u", (unsigned)s->max_substeps);
    }
    put_key(f, k, "soft_substeps", KEY_NEXT);
    fprintf(f, "%u", (unsigned)s->soft_substeps);
    put_key(f, k, "soft_tolerance", KEY_NEXT);
    put_num(f, s->soft_tolerance);
    put_key(f, k, "restitution", KEY_NEXT);
    put_num(f, s->restitution);
    put_key(f, k, "pause_on_collision", KEY_NEXT);
    fputs(s->pause_on_collision ? "true" : "false", f);
    put_key(f, k, "mutual_gravity", KEY_NEXT_LINE);
    if (s->mutual_gravity) {
        put_key(f, g, "G", KEY_FIRST);
        put_num(f, s->gravity_constant);
        put_key(f, g, "softening", KEY_NEXT);
        put_num(f, s->softening);
        if (g->json) {
            fputc('}', f);
        }
    } else {
        fputs("false", f);
    }
}

/* Everything after a body's name and type, the same sequence in both
 * formats (see put_key); each writer adds its own framing. */
static void put_body(FILE *f, const key_style *k, const rbs_scene *s,
                     const rbs__scene_body *b)
{
    char color[24];
    if (b->type == RBS_BODY_SPHERE) {
        const double q[4] = {b->orientation.w, b->orientation.x, b->orientation.y,
                             b->orientation.z};
        put_key(f, k, "radius", KEY_NEXT);
        put_num(f, b->radius);
        put_key(f, k, b->density > 0 ? "density" : "mass", KEY_NEXT);
        put_num(f, b->density > 0 ? b->density : b->mass);
        if (b->inertia_kind == RBS_INERTIA_PRINCIPAL) {
            put_vec_field(f, k, "inertia", KEY_NEXT, b->inertia);
        } else {
            put_key(f, k, "inertia", KEY_NEXT);
            put_word(f, k, b->inertia_kind == RBS_INERTIA_HOLLOW ? "hollow" : "solid");
        }
        put_vec_field(f, k, "position", KEY_NEXT_LINE, b->position);
        put_key(f, k, "orientation", KEY_NEXT);
        put_list(f, k, q, 4);
        put_vec_field(f, k, "velocity", KEY_NEXT_LINE, b->velocity);
        put_vec_field(f, k, "angular_velocity", KEY_NEXT, b->angular_velocity);
        put_vec_field(f, k, "center_of_mass", KEY_NEXT, b->center_of_mass);
        put_vec_field(f, k, "force", KEY_NEXT_LINE, b->force);
        put_vec_field(f, k, "torque", KEY_NEXT, b->torque);
        put_key(f, k, "fixed", KEY_NEXT);
        fputs(b->fixed ? "true" : "false", f);
    } else {
        put_vec_field(f, k, "point", KEY_NEXT, b->point);
        put_vec_field(f, k, "normal", KEY_NEXT, b->normal);
    }
    if (b->material >= 0) {
        put_key(f, k, "material", KEY_NEXT);
        if (k->json) {
            put_json_string(f, s->materials[b->material]);
        } else {
            put_text_string(f, s->materials[b->material]);
        }
    }
    snprintf(color, sizeof color, "#%06lx", (unsigned long)(b->color & 0xffffffu));
    put_key(f, k, "color", KEY_NEXT);
    put_word(f, k, color);
    put_key(f, k, "texture", KEY_NEXT);
    put_word(f, k, texture_name(b->texture));
}

/* ---- JSON --------------------------------------------------------------- */

rbs_status rbs__scene_save_json(const rbs_scene *s, const char *path, char *message,
                                size_t message_size)
{
    save_report r = {message, message_size};
    staged o;
    FILE *f;
    uint32_t i;
    rbs_status st = stage_open(&o, s, path, &r);
    if (st != RBS_OK) {
        return stage_finish(&o, 1, st, &r);
    }
    f = o.f;
    fputs("{\n  \"format\": 1,\n", f);
    if (s->description != NULL) {
        fputs("  \"description\": ", f);
        put_json_string(f, s->description);
        fputs(",\n", f);
    }
    fputs("  \"simulation\": ", f);
    put_simulation(f, &json_simulation, &json_gravity, s);
    fputs("},\n", f);
    fputs("  \"materials\": [", f);
    for (i = 0; i < s->pair_count; i++) {
        const rbs__scene_pair *p = &s->pairs[i];
        fputs(i ? ",\n    {\"pair\": [" : "\n    {\"pair\": [", f);
        put_json_string(f, p->a >= 0 ? s->materials[p->a] : "*");
        fputs(", ", f);
        put_json_string(f, p->b >= 0 ? s->materials[p->b] : "*");
        fputs("], \"static\": ", f);
        put_num(f, p->static_friction);
        fputs(", \"kinetic\": ", f);
        put_num(f, p->kinetic_friction);
        if (p->restitution >= 0) {
            fputs(", \"restitution\": ", f);
            put_num(f, p->restitution);
        }
        fputs(", \"rolling\": ", f);
        put_num(f, p->rolling);
        fputs(", \"spinning\": ", f);
        put_num(f, p->spinning);
        fputs("}", f);
    }
    fputs(s->pair_count ? "\n  ],\n" : "],\n", f);
    fputs("  \"bodies\": [", f);
    for (i = 0; i < s->body_count; i++) {
        const rbs__scene_body *b = &s->bodies[i];
        fputs(i ? ",\n    {\"name\": " : "\n    {\"name\": ", f);
        put_json_string(f, b->name);
        fputs(b->type == RBS_BODY_SPHERE ? ", \"type\": \"sphere\"" : ", \"type\": \"plane\"",
              f);
        put_body(f, &json_body, s, b);
        fputc('}', f);
    }
    fputs(s->body_count ? "\n  ],\n" : "],\n", f);
    fputs("  \"renderers\": [", f);
    for (i = 0; i < s->renderer_count; i++) {
        fputs(i ? ",\n    " : "\n    ", f);
        fputs(s->renderers[i].json, f);
    }
    fputs(s->renderer_count ? "\n  ]\n}\n" : "]\n}\n", f);
    return stage_finish(&o, 1, RBS_OK, &r);
}

/* ---- text --------------------------------------------------------------- */

/* A quoted string token, escaped. */
static void put_quoted(FILE *f, const char *str)
{
    const char *c;
    fputc('"', f);
    for (c = str; *c; c++) {
        if (*c == '"' || *c == '\\') {
            fputc('\\', f);
            fputc(*c, f);
        } else if (*c == '\n') {
            fputs("\\n", f);
        } else if (*c == '\t') {
            fputs("\\t", f);
        } else if (*c == '\r') {
            fputs("\\r", f);
        } else {
            fputc(*c, f);
        }
    }
    fputc('"', f);
}

/* A string token that reads back as the same string: bare when safe. */
static void put_text_string(FILE *f, const char *str)
{
    int safe = str[0] != '\0';
    const char *c;
    size_t n = strlen(str);
    for (c = str; *c && safe; c++) {
        unsigned char u = (unsigned char)*c;
        if (u <= 0x20 || u == 0x7f || u == '"' || u == ',' || u == '#' || u == '=' ||
            u == '\\') {
            safe = 0;
        }
    }
    if (safe) {
        /* words that would read as something else */
        char *end;
        (void)strtod(str, &end);
        if ((*end == '\0') || strcmp(str, "true") == 0 || strcmp(str, "false") == 0 ||
            strcmp(str, "null") == 0 || strcmp(str, "[]") == 0 || strcmp(str, "{}") == 0 ||
            strcmp(str, "sphere") == 0 || strcmp(str, "plane") == 0 || str[0] == '-') {
            safe = 0;
        }
    }
    if (n == 7 && str[0] == '#') {
        safe = 1; /* a colour */
        for (c = str + 1; *c; c++) {
            if (!((*c >= '0' && *c <= '9') || (*c >= 'a' && *c <= 'f') ||
                  (*c >= 'A' && *c <= 'F'))) {
                safe = 0;
            }
        }
    }
    if (safe) {
        fputs(str, f);
        return;
    }
    put_quoted(f, str);
}

/* Why key k cannot be a word of a renderer line ("key=value", names joined
 * by '.' and [index]), or NULL when it can. */
static const char *key_unwritable(const char *k)
{
    if (*k == '\0') {
        return "an empty key";
    }
    if (strlen(k) >= RBS_NAME_MAX) {
        return "a key of 63 bytes or more";
    }
    for (; *k; k++) {
        unsigned char u = (unsigned char)*k;
        if (u <= 0x20 || u == 0x7f) {
            return "a key with a blank or a control character";
        }
        if (u == '.' || u == '[' || u == ']' || u == '=' || u == '"' || u == '#' || u == ',') {
            return "a key with one of . [ ] = \" # ,";
        }
    }
    return NULL;
}

/* What a renderer entry holds that the text format cannot write. */
typedef struct unwritable {
    char key[600]; /* the key path, as far as it was made */
    const char *why;
} unwritable;

static void unwritable_at(unwritable *u, const char *prefix, const char *key, const char *why)
{
    snprintf(u->key, sizeof u->key, "%s%s%s", prefix, prefix[0] && key[0] != '[' ? "." : "", key);
    u->why = why;
}

/* Flatten a renderer entry's value into " prefix=value" words; -1 (with
 * *u filled) for what the text format cannot write. */
static int flatten(FILE *f, char *prefix, size_t plen, size_t cap, const cJSON *item,
                   unwritable *u)
{
    const cJSON *c;
    if (cJSON_IsObject(item)) {
        if (item->child == NULL) {
            fprintf(f, " %s={}", prefix);
            return 0;
        }
        for (c = item->child; c != NULL; c = c->next) {
            int w;
            const char *why = key_unwritable(c->string);
            if (why != NULL) {
                unwritable_at(u, prefix, c->string, why);
                return -1;
            }
            w = snprintf(prefix + plen, cap - plen, "%s%s", plen ? "." : "", c->string);
            if (w < 0 || (size_t)w >= cap - plen) {
                prefix[plen] = '\0';
                unwritable_at(u, prefix, c->string, "a key path of 512 bytes or more");
                return -1;
            }
            if (flatten(f, prefix, plen + (size_t)w, cap, c, u) != 0) {
                return -1;
            }
            prefix[plen] = '\0';
        }
        return 0;
    }
    if (cJSON_IsArray(item)) {
        int all_numbers = 1, k = 0;
        if (item->child == NULL) {
            fprintf(f, " %s=[]", prefix);
            return 0;
        }
        for (c = item->child; c != NULL; c = c->next) {
            all_numbers &= cJSON_IsNumber(c) ? 1 : 0;
        }
        if (all_numbers) {
            fprintf(f, " %s=", prefix);
            for (c = item->child; c != NULL; c = c->next) {
                if (c != item->child) {
                    fputc(',', f);
                }
                put_num(f, c->valuedouble);
            }
            if (item->child->next == NULL) {
                fputc(',', f); /* "x=1," is a one-element array */
            }
            return 0;
        }
        for (c = item->child; c != NULL; c = c->next, k++) {
            char index[24];
            int w = snprintf(prefix + plen, cap - plen, "[%d]", k);
            if (w < 0 || (size_t)w >= cap - plen) {
                prefix[plen] = '\0';
                snprintf(index, sizeof index, "[%d]", k);
                unwritable_at(u, prefix, index, "a key path of 512 bytes or more");
                return -1;
            }
            if (flatten(f, prefix, plen + (size_t)w, cap, c, u) != 0) {
                return -1;
            }
            prefix[plen] = '\0';
        }
        return 0;
    }
    fprintf(f, " %s=", prefix);
    if (cJSON_IsNumber(item)) {
        put_num(f, item->valuedouble);
    } else if (cJSON_IsString(item)) {
        put_text_string(f, item->valuestring);
    } else if (cJSON_IsTrue(item)) {
        fputs("true", f);
    } else if (cJSON_IsFalse(item)) {
        fputs("false", f);
    } else {
        fputs("null", f);
    }
    return 0;
}

/* Renderer entry r (renderers[index]) as a config.txt line; for a key the
 * text format cannot write, RBS_E_UNSUPPORTED with a message naming the
 * entry, the key and why. */
static rbs_status put_renderer(FILE *f, const rbs__scene_renderer *r, uint32_t index,
                               save_report *rep)
{
    cJSON *root = rbs__json_tree(r->json, strlen(r->json));
    char prefix[512];
    unwritable u;
    if (root == NULL) {
        return RBS_E_MEMORY;
    }
    fputs("renderer = ", f);
    put_text_string(f, r->type);
    prefix[0] = '\0';
    u.key[0] = '\0';
    u.why = NULL;
    {
        /* (the type is the line's first word, not a key=value word) */
        cJSON *type = cJSON_DetachItemFromObjectCaseSensitive(root, "type");
        cJSON_Delete(type);
    }
    if (root->child != NULL && flatten(f, prefix, 0, sizeof prefix, root, &u) != 0) {
        if (rep->text != NULL && rep->size > 0 && rep->text[0] == '\0') {
            int cut = strlen(u.key) > 160;
            snprintf(rep->text, rep->size,
                     "renderers[%lu] (%.64s): key \"%.160s%s\" cannot be written in the text "
                     "format: %s (its keys are names of 1 to 62 bytes without blanks or "
                     ". [ ] = \" # , in paths under 512 bytes); keep this scene as JSON",
                     (unsigned long)index, r->type, u.key, cut ? "..." : "", u.why);
        }
        fputc('\n', f);
        cJSON_Delete(root);
        return RBS_E_UNSUPPORTED;
    }
    fputc('\n', f);
    cJSON_Delete(root);
    return RBS_OK;
}

static char *sibling(const char *config, const char *suffix)
{
    const char *slash = strrchr(config, '/');
    const char *base = slash != NULL ? slash + 1 : config;
    size_t d = (size_t)(base - config), n;
    char *out;
    if (strcmp(base, "config.txt") == 0) {
        n = d + strlen(suffix) + 1;
        out = malloc(n);
        if (out != NULL) {
            memcpy(out, config, d);
            memcpy(out + d, suffix, strlen(suffix) + 1);
        }
        return out;
    }
    {
        /* other names: "NAME.materials.txt" beside "NAME.txt" */
        const char *dot = strrchr(base, '.');
        size_t stem = dot != NULL && dot != base ? (size_t)(dot - config) : strlen(config);
        n = stem + 1 + strlen(suffix) + 1;
        out = malloc(n);
        if (out != NULL) {
            memcpy(out, config, stem);
            out[stem] = '.';
            memcpy(out + stem + 1, suffix, strlen(suffix) + 1);
        }
        return out;
    }
}

rbs_status rbs__scene_save_text(const rbs_scene *s, const char *path, char *message,
                                size_t message_size)
{
    save_report r = {message, message_size};
    staged o[3] = {{NULL, NULL, NULL, NULL}, {NULL, NULL, NULL, NULL}, {NULL, NULL, NULL, NULL}};
    char *mpath = sibling(path, "materials.txt");
    char *opath = sibling(path, "objects.txt");
    const char *mbase, *obase;
    FILE *f;
    uint32_t i;
    rbs_status st = RBS_OK;
    if (mpath == NULL || opath == NULL) {
        free(mpath);
        free(opath);
        return RBS_E_MEMORY;
    }
    mbase = strrchr(mpath, '/') != NULL ? strrchr(mpath, '/') + 1 : mpath;
    obase = strrchr(opath, '/') != NULL ? strrchr(opath, '/') + 1 : opath;
    /* all three files staged before any is written: none replaces what is
     * there unless every one can be */
    if ((st = stage_open(&o[0], s, path, &r)) != RBS_OK || (st = stage_open(&o[1], s, mpath, &r)) != RBS_OK ||
        (st = stage_open(&o[2], s, opath, &r)) != RBS_OK) {
        free(mpath);
        free(opath);
        return stage_finish(o, 3, st, &r);
    }
    /* config.txt */
    f = o[0].f;
    fputs("# rbsim scene, text format version 1 (see scenes/FORMAT.md)\n", f);
    if (s->description != NULL) {
        fputs("description = ", f);
        put_quoted(f, s->description); /* always, so that it reads back exactly */
        fputc('\n', f);
    }
    put_simulation(f, &text_config, &text_gravity, s);
    fputs("\nmaterials = ", f);
    put_text_string(f, mbase);
    fputs("\nobjects = ", f);
    put_text_string(f, obase);
    fputc('\n', f);
    for (i = 0; i < s->renderer_count && st == RBS_OK; i++) {
        st = put_renderer(f, &s->renderers[i], i, &r);
    }
    free(mpath);
    free(opath);
    /* Each file is flushed once complete, before the next is written: on a
     * full disk the one that filled it is named (a flush of all three at
     * the end failed at config.txt first, though objects.txt had filled
     * the disk). */
    if (st == RBS_OK) {
        st = stage_close(&o[0], &r);
    }
    /* materials.txt */
    f = o[1].f;
    fputs("# material_a material_b static kinetic restitution(- = the simulation's) "
          "rolling spinning\n",
          f);
    for (i = 0; i < s->pair_count; i++) {
        const rbs__scene_pair *p = &s->pairs[i];
        put_text_string(f, p->a >= 0 ? s->materials[p->a] : "*");
        fputc(' ', f);
        put_text_string(f, p->b >= 0 ? s->materials[p->b] : "*");
        fputc(' ', f);
        put_num(f, p->static_friction);
        fputc(' ', f);
        put_num(f, p->kinetic_friction);
        fputc(' ', f);
        if (p->restitution >= 0) {
            put_num(f, p->restitution);
        } else {
            fputc('-', f);
        }
        fputc(' ', f);
        put_num(f, p->rolling);
        fputc(' ', f);
        put_num(f, p->spinning);
        fputc('\n', f);
    }
    if (st == RBS_OK) {
        st = stage_close(&o[1], &r);
    }
    /* objects.txt */
    f = o[2].f;
    fputs("# one block per body: \"sphere NAME\" or \"plane NAME\", then \"key value\" "
          "lines\n",
          f);
    for (i = 0; i < s->body_count; i++) {
        const rbs__scene_body *b = &s->bodies[i];
        fputs(i ? "\n" : "", f);
        fputs(b->type == RBS_BODY_SPHERE ? "sphere " : "plane ", f);
        put_text_string(f, b->name);
        put_body(f, &text_body, s, b);
        fputc('\n', f);
    }
    return stage_finish(o, 3, st, &r);
}
