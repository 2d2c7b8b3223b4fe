/*
 * scene_save.c - write a scene description as JSON or as the text format.
 *
 * Numbers are written with the fewest digits that read back to the same
 * double, so saving and loading again gives a bit-identical scene.
 */
#include "scene/scene_internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* fopen for writing; a missing parent folder (one level) is made. */
static FILE *open_out(const char *path)
{
    FILE *f = fopen(path, "w");
    const char *slash;
    if (f != NULL || errno != ENOENT || (slash = strrchr(path, '/')) == NULL ||
        slash == path) {
        return f;
    }
    {
        size_t n = (size_t)(slash - path);
        char *dir = malloc(n + 1);
        if (dir == NULL) {
            return NULL;
        }
        memcpy(dir, path, n);
        dir[n] = '\0';
        (void)mkdir(dir, 0777);
        free(dir);
    }
    return fopen(path, "w");
}

/* Shortest "%.{15,16,17}g" that reads back exactly. */
static void fmt_num(char *out, size_t n, double x)
{
    int p;
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

static void put_vec(FILE *f, rbs_vec3 v, const char *sep)
{
    put_num(f, v.x);
    fputs(sep, f);
    put_num(f, v.y);
    fputs(sep, f);
    put_num(f, v.z);
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

static rbs_status finish(FILE *f)
{
    int bad = ferror(f);
    if (fclose(f) != 0 || bad) {
        return RBS_E_IO;
    }
    return RBS_OK;
}

rbs_status rbs__scene_save_json(const rbs_scene *s, const char *path)
{
    FILE *f = open_out(path);
    uint32_t i;
    if (f == NULL) {
        return RBS_E_IO;
    }
    fputs("{\n  \"format\": 1,\n", f);
    if (s->description != NULL) {
        fputs("  \"description\": ", f);
        put_json_string(f, s->description);
        fputs(",\n", f);
    }
    fprintf(f, "  \"simulation\": {\"steps\": %llu, \"dt\": ", (unsigned long long)s->steps);
    put_num(f, s->dt);
    fputs(", \"gravity\": [", f);
    put_vec(f, s->gravity, ", ");
    fprintf(f, "], \"gravity_mode\": \"%s\",\n    \"method\": \"%s\", \"tolerance\": ",
            s->gravity_mode == RBS_GRAVITY_FORCE ? "force" : "acceleration",
            rbs_method_name(s->method) != NULL ? rbs_method_name(s->method) : "euler");
    put_num(f, s->tolerance);
    fputs(", \"restitution\": ", f);
    put_num(f, s->restitution);
    fprintf(f, ", \"pause_on_collision\": %s,\n    \"mutual_gravity\": ",
            s->pause_on_collision ? "true" : "false");
    if (s->mutual_gravity) {
        fputs("{\"G\": ", f);
        put_num(f, s->gravity_constant);
        fputs(", \"softening\": ", f);
        put_num(f, s->softening);
        fputs("}},\n", f);
    } else {
        fputs("false},\n", f);
    }
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
        if (b->type == RBS_BODY_SPHERE) {
            fputs(", \"type\": \"sphere\", \"radius\": ", f);
            put_num(f, b->radius);
            if (b->density > 0) {
                fputs(", \"density\": ", f);
                put_num(f, b->density);
            } else {
                fputs(", \"mass\": ", f);
                put_num(f, b->mass);
            }
            if (b->inertia_kind == RBS_INERTIA_PRINCIPAL) {
                fputs(", \"inertia\": [", f);
                put_vec(f, b->inertia, ", ");
                fputs("]", f);
            } else {
                fprintf(f, ", \"inertia\": \"%s\"",
                        b->inertia_kind == RBS_INERTIA_HOLLOW ? "hollow" : "solid");
            }
            fputs(",\n      \"position\": [", f);
            put_vec(f, b->position, ", ");
            fputs("], \"orientation\": [", f);
            put_num(f, b->orientation.w);
            fputs(", ", f);
            put_num(f, b->orientation.x);
            fputs(", ", f);
            put_num(f, b->orientation.y);
            fputs(", ", f);
            put_num(f, b->orientation.z);
            fputs("],\n      \"velocity\": [", f);
            put_vec(f, b->velocity, ", ");
            fputs("], \"angular_velocity\": [", f);
            put_vec(f, b->angular_velocity, ", ");
            fputs("], \"center_of_mass\": [", f);
            put_vec(f, b->center_of_mass, ", ");
            fputs("],\n      \"force\": [", f);
            put_vec(f, b->force, ", ");
            fputs("], \"torque\": [", f);
            put_vec(f, b->torque, ", ");
            fprintf(f, "], \"fixed\": %s", b->fixed ? "true" : "false");
        } else {
            fputs(", \"type\": \"plane\", \"point\": [", f);
            put_vec(f, b->point, ", ");
            fputs("], \"normal\": [", f);
            put_vec(f, b->normal, ", ");
            fputs("]", f);
        }
        if (b->material >= 0) {
            fputs(", \"material\": ", f);
            put_json_string(f, s->materials[b->material]);
        }
        fprintf(f, ", \"color\": \"#%06lx\", \"texture\": \"%s\"}",
                (unsigned long)(b->color & 0xffffffu), texture_name(b->texture));
    }
    fputs(s->body_count ? "\n  ],\n" : "],\n", f);
    fputs("  \"renderers\": [", f);
    for (i = 0; i < s->renderer_count; i++) {
        fputs(i ? ",\n    " : "\n    ", f);
        fputs(s->renderers[i].json, f);
    }
    fputs(s->renderer_count ? "\n  ]\n}\n" : "]\n}\n", f);
    return finish(f);
}

/* ---- text --------------------------------------------------------------- */

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

static int key_is_simple(const char *k)
{
    if (*k == '\0' || strlen(k) >= RBS_NAME_MAX) {
        return 0;
    }
    for (; *k; k++) {
        unsigned char u = (unsigned char)*k;
        if (u <= 0x20 || u == 0x7f || u == '.' || u == '[' || u == ']' || u == '=' ||
            u == '"' || u == '#' || u == ',') {
            return 0;
        }
    }
    return 1;
}

/* Flatten a renderer entry's value into " prefix=value" words. */
static int flatten(FILE *f, char *prefix, size_t plen, size_t cap, const cJSON *item)
{
    const cJSON *c;
    if (cJSON_IsObject(item)) {
        if (item->child == NULL) {
            fprintf(f, " %s={}", prefix);
            return 0;
        }
        for (c = item->child; c != NULL; c = c->next) {
            int w;
            if (!key_is_simple(c->string)) {
                return -1;
            }
            w = snprintf(prefix + plen, cap - plen, "%s%s", plen ? "." : "", c->string);
            if (w < 0 || (size_t)w >= cap - plen || flatten(f, prefix, plen + (size_t)w, cap, c) != 0) {
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
            int w = snprintf(prefix + plen, cap - plen, "[%d]", k);
            if (w < 0 || (size_t)w >= cap - plen || flatten(f, prefix, plen + (size_t)w, cap, c) != 0) {
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

static rbs_status put_renderer(FILE *f, const rbs__scene_renderer *r)
{
    cJSON *root = rbs__json_tree(r->json, strlen(r->json));
    const cJSON *c;
    char prefix[512];
    rbs_status st = RBS_OK;
    if (root == NULL) {
        return RBS_E_MEMORY;
    }
    fputs("renderer = ", f);
    put_text_string(f, r->type);
    for (c = root->child; c != NULL && st == RBS_OK; c = c->next) {
        if (strcmp(c->string, "type") == 0) {
            continue;
        }
        if (!key_is_simple(c->string)) {
            st = RBS_E_UNSUPPORTED;
            break;
        }
        snprintf(prefix, sizeof prefix, "%s", c->string);
        if (flatten(f, prefix, strlen(prefix), sizeof prefix, c) != 0) {
            st = RBS_E_UNSUPPORTED;
        }
    }
    fputc('\n', f);
    cJSON_Delete(root);
    return st;
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

rbs_status rbs__scene_save_text(const rbs_scene *s, const char *path)
{
    char *mpath = sibling(path, "materials.txt");
    char *opath = sibling(path, "objects.txt");
    const char *mbase, *obase;
    FILE *f;
    uint32_t i;
    rbs_status st = RBS_OK, st2;
    if (mpath == NULL || opath == NULL) {
        free(mpath);
        free(opath);
        return RBS_E_MEMORY;
    }
    mbase = strrchr(mpath, '/') != NULL ? strrchr(mpath, '/') + 1 : mpath;
    obase = strrchr(opath, '/') != NULL ? strrchr(opath, '/') + 1 : opath;
    /* config.txt */
    f = open_out(path);
    if (f == NULL) {
        free(mpath);
        free(opath);
        return RBS_E_IO;
    }
    fputs("# rbsim scene, text format version 1 (see scenes/FORMAT.md)\n", f);
    if (s->description != NULL) {
        fputs("description = ", f);
        {
            /* always quoted, so that it reads back exactly */
            const char *c;
            fputc('"', f);
            for (c = s->description; *c; c++) {
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
            fputs("\"\n", f);
        }
    }
    fprintf(f, "steps = %llu\ndt = ", (unsigned long long)s->steps);
    put_num(f, s->dt);
    fputs("\ngravity = ", f);
    put_vec(f, s->gravity, " ");
    fprintf(f, "\ngravity_mode = %s\nmethod = %s\ntolerance = ",
            s->gravity_mode == RBS_GRAVITY_FORCE ? "force" : "acceleration",
            rbs_method_name(s->method) != NULL ? rbs_method_name(s->method) : "euler");
    put_num(f, s->tolerance);
    fputs("\nrestitution = ", f);
    put_num(f, s->restitution);
    fprintf(f, "\npause_on_collision = %s\nmutual_gravity = ",
            s->pause_on_collision ? "true" : "false");
    if (s->mutual_gravity) {
        fputs("G=", f);
        put_num(f, s->gravity_constant);
        fputs(" softening=", f);
        put_num(f, s->softening);
    } else {
        fputs("false", f);
    }
    fputs("\nmaterials = ", f);
    put_text_string(f, mbase);
    fputs("\nobjects = ", f);
    put_text_string(f, obase);
    fputc('\n', f);
    for (i = 0; i < s->renderer_count; i++) {
        st2 = put_renderer(f, &s->renderers[i]);
        if (st2 != RBS_OK && st == RBS_OK) {
            st = st2;
        }
    }
    st2 = finish(f);
    if (st2 != RBS_OK && st == RBS_OK) {
        st = st2;
    }
    /* materials.txt */
    f = open_out(mpath);
    if (f == NULL) {
        free(mpath);
        free(opath);
        return RBS_E_IO;
    }
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
    st2 = finish(f);
    if (st2 != RBS_OK && st == RBS_OK) {
        st = st2;
    }
    /* objects.txt */
    f = open_out(opath);
    free(mpath);
    free(opath);
    if (f == NULL) {
        return RBS_E_IO;
    }
    fputs("# one block per body: \"sphere NAME\" or \"plane NAME\", then \"key value\" "
          "lines\n",
          f);
    for (i = 0; i < s->body_count; i++) {
        const rbs__scene_body *b = &s->bodies[i];
        fputs(i ? "\n" : "", f);
        fputs(b->type == RBS_BODY_SPHERE ? "sphere " : "plane ", f);
        put_text_string(f, b->name);
        fputc('\n', f);
        if (b->type == RBS_BODY_SPHERE) {
            fputs("  radius ", f);
            put_num(f, b->radius);
            fputs(b->density > 0 ? "\n  density " : "\n  mass ", f);
            put_num(f, b->density > 0 ? b->density : b->mass);
            fputs("\n  inertia ", f);
            if (b->inertia_kind == RBS_INERTIA_PRINCIPAL) {
                put_vec(f, b->inertia, " ");
            } else {
                fputs(b->inertia_kind == RBS_INERTIA_HOLLOW ? "hollow" : "solid", f);
            }
            fputs("\n  position ", f);
            put_vec(f, b->position, " ");
            fputs("\n  orientation ", f);
            put_num(f, b->orientation.w);
            fputc(' ', f);
            put_num(f, b->orientation.x);
            fputc(' ', f);
            put_num(f, b->orientation.y);
            fputc(' ', f);
            put_num(f, b->orientation.z);
            fputs("\n  velocity ", f);
            put_vec(f, b->velocity, " ");
            fputs("\n  angular_velocity ", f);
            put_vec(f, b->angular_velocity, " ");
            fputs("\n  center_of_mass ", f);
            put_vec(f, b->center_of_mass, " ");
            fputs("\n  force ", f);
            put_vec(f, b->force, " ");
            fputs("\n  torque ", f);
            put_vec(f, b->torque, " ");
            fprintf(f, "\n  fixed %s\n", b->fixed ? "true" : "false");
        } else {
            fputs("  point ", f);
            put_vec(f, b->point, " ");
            fputs("\n  normal ", f);
            put_vec(f, b->normal, " ");
            fputc('\n', f);
        }
        if (b->material >= 0) {
            fputs("  material ", f);
            put_text_string(f, s->materials[b->material]);
            fputc('\n', f);
        }
        fprintf(f, "  color #%06lx\n  texture %s\n", (unsigned long)(b->color & 0xffffffu),
                texture_name(b->texture));
    }
    st2 = finish(f);
    if (st2 != RBS_OK && st == RBS_OK) {
        st = st2;
    }
    return st;
}
