/*
 * sdl_config.c - the "sdl" scene entry: parse with cJSON, validate every key,
 * and report the first problem as "key: what is wrong, got what".
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "sdl_internal.h"

/* Keys of the entry and of a camera (anything else is an error). */
static const char *const entry_keys[] = {
    "type", "path", "every", "width", "height", "window",
    "tile", "contact_sheet", "camera", "views", NULL};
static const char *const camera_keys[] = {
    "mode", "position", "target", "up", "fov", "near",
    "far", "mount", "offset", "path", NULL};
static const char *const path_keys[] = {"t", "position", "target", NULL};

static rbs_status fail(char *err, size_t errlen, const char *fmt, ...)
{
    if (err != NULL && errlen > 0) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err, errlen, fmt, ap);
        va_end(ap);
    }
    return RBS_E_INVALID;
}

/* JSON type name for messages. */
static const char *json_kind(const cJSON *item)
{
    if (cJSON_IsObject(item)) return "an object";
    if (cJSON_IsArray(item)) return "an array";
    if (cJSON_IsString(item)) return "a string";
    if (cJSON_IsNumber(item)) return "a number";
    if (cJSON_IsBool(item)) return "a boolean";
    if (cJSON_IsNull(item)) return "null";
    return "invalid JSON";
}

static int key_known(const char *key, const char *const *keys)
{
    for (; *keys != NULL; keys++)
        if (strcmp(key, *keys) == 0) return 1;
    return 0;
}

/* Reject unknown (and duplicate) keys of an object. */
static rbs_status check_keys(const cJSON *object, const char *const *keys,
                             const char *where, char *err, size_t errlen)
{
    const cJSON *item, *other;
    cJSON_ArrayForEach(item, object) {
        if (item->string == NULL || !key_known(item->string, keys)) {
            return fail(err, errlen, "%s%s: unknown key", where,
                        item->string != NULL ? item->string : "?");
        }
        for (other = object->child; other != item; other = other->next) {
            if (strcmp(other->string, item->string) == 0)
                return fail(err, errlen, "%s%s: duplicate key", where,
                            item->string);
        }
    }
    return RBS_OK;
}

/* A positive integer in [lo, hi]. */
static rbs_status get_uint(const cJSON *item, const char *where,
                           const char *key, uint32_t lo, uint32_t hi,
                           uint32_t *out, char *err, size_t errlen)
{
    double v;
    if (!cJSON_IsNumber(item))
        return fail(err, errlen, "%s%s: must be an integer, got %s", where,
                    key, json_kind(item));
    v = item->valuedouble;
    if (!(v == floor(v)) || v < (double)lo || v > (double)hi) {
        /* the value in its shortest exact form (3000000000, not 3e+09) */
        char got[40];
        int prec;
        for (prec = 15; prec <= 17; prec++) {
            snprintf(got, sizeof got, "%.*g", prec, v);
            if (strtod(got, NULL) == v)
                break;
        }
        return fail(err, errlen, "%s%s: must be an integer in [%u, %u], got %s",
                    where, key, lo, hi, got);
    }
    *out = (uint32_t)v;
    return RBS_OK;
}

static rbs_status get_bool(const cJSON *item, const char *where,
                           const char *key, int *out, char *err, size_t errlen)
{
    if (!cJSON_IsBool(item))
        return fail(err, errlen, "%s%s: must be true or false, got %s", where,
                    key, json_kind(item));
    *out = cJSON_IsTrue(item) ? 1 : 0;
    return RBS_OK;
}

static rbs_status get_number(const cJSON *item, const char *where,
                             const char *key, double *out, char *err,
                             size_t errlen)
{
    if (!cJSON_IsNumber(item))
        return fail(err, errlen, "%s%s: must be a number, got %s", where, key,
                    json_kind(item));
    if (!isfinite(item->valuedouble))
        return fail(err, errlen, "%s%s: must be finite", where, key);
    *out = item->valuedouble;
    return RBS_OK;
}

static rbs_status get_vec3(const cJSON *item, const char *where,
                           const char *key, rbs_vec3 *out, char *err,
                           size_t errlen)
{
    double v[3];
    int i = 0;
    const cJSON *e;
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != 3)
        return fail(err, errlen, "%s%s: must be an array of 3 numbers [x, y, z]",
                    where, key);
    cJSON_ArrayForEach(e, item) {
        if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble))
            return fail(err, errlen, "%s%s[%d]: must be a finite number, got %s",
                        where, key, i, json_kind(e));
        v[i++] = e->valuedouble;
    }
    out->x = v[0];
    out->y = v[1];
    out->z = v[2];
    return RBS_OK;
}

static double vlen(rbs_vec3 a) { return sqrt(a.x * a.x + a.y * a.y + a.z * a.z); }

/* Limits that keep every square of the ray caster finite and nonzero (the
 * same as sdl_camera.c and the scene check; see scenes/FORMAT.md). */
static const double kCoordMax = 1e100; /* m, |each coordinate| */
static const double kDistMin = 1e-100; /* m, eye to target, |offset| */
static const double kFovMin = 1e-6;    /* degrees */

/* A position, target or offset: each coordinate within +-kCoordMax m. */
static rbs_status check_coords(rbs_vec3 p, const char *where, const char *key,
                               char *err, size_t errlen)
{
    if (fabs(p.x) <= kCoordMax && fabs(p.y) <= kCoordMax && fabs(p.z) <= kCoordMax)
        return RBS_OK;
    return fail(err, errlen, "%s%s: coordinates must be within +-1e100 m, got "
                "[%g, %g, %g]", where, key, p.x, p.y, p.z);
}

/* Sine of the angle between up and the view direction (1 = perpendicular). */
static double up_sine(rbs_vec3 from, rbs_vec3 to, rbs_vec3 up)
{
    rbs_vec3 d = {to.x - from.x, to.y - from.y, to.z - from.z};
    rbs_vec3 c = {d.y * up.z - d.z * up.y, d.z * up.x - d.x * up.z,
                  d.x * up.y - d.y * up.x};
    double ld = vlen(d);
    return ld > 0.0 ? vlen(c) / ld : 0.0;
}

/* A position/target pair must define a direction not along up. */
static rbs_status check_aim(rbs_vec3 position, rbs_vec3 target, rbs_vec3 up,
                            const char *where, const char *key, char *err,
                            size_t errlen)
{
    rbs_vec3 d = {target.x - position.x, target.y - position.y,
                  target.z - position.z};
    if (d.x == 0.0 && d.y == 0.0 && d.z == 0.0)
        return fail(err, errlen, "%s%s: target equals position", where, key);
    if (!(vlen(d) >= kDistMin))
        return fail(err, errlen, "%s%s: target within 1e-100 m of position "
                    "(too close to aim)", where, key);
    if (up_sine(position, target, up) < 1e-6)
        return fail(err, errlen,
                    "%s%s: the view direction is parallel to up; choose "
                    "another up or position",
                    where, key);
    return RBS_OK;
}

static rbs_status parse_path(const cJSON *item, const char *where,
                             rbsf__camera_def *cam, char *err, size_t errlen)
{
    int n, i = 0;
    const cJSON *key;
    char sub[96];
    rbs_status st;
    if (!cJSON_IsArray(item) || (n = cJSON_GetArraySize(item)) < 1)
        return fail(err, errlen,
                    "%spath: must be a non-empty array of {\"t\", \"position\", "
                    "\"target\"}",
                    where);
    if (n > 100000)
        return fail(err, errlen, "%spath: at most 100000 keys, got %d", where, n);
    cam->path = (rbsf__path_key *)calloc((size_t)n, sizeof *cam->path);
    if (cam->path == NULL) {
        snprintf(err, errlen, "%spath: out of memory", where);
        return RBS_E_MEMORY;
    }
    cJSON_ArrayForEach(key, item) {
        rbsf__path_key *k = &cam->path[i];
        const cJSON *f;
        snprintf(sub, sizeof sub, "%spath[%d].", where, i);
        if (!cJSON_IsObject(key))
            return fail(err, errlen, "%spath[%d]: must be an object, got %s",
                        where, i, json_kind(key));
        if ((st = check_keys(key, path_keys, sub, err, errlen)) != RBS_OK)
            return st;
        if ((f = cJSON_GetObjectItemCaseSensitive(key, "t")) == NULL)
            return fail(err, errlen, "%st: missing (time, s)", sub);
        if ((st = get_number(f, sub, "t", &k->t, err, errlen)) != RBS_OK)
            return st;
        if (i > 0 && !(k->t > cam->path[i - 1].t))
            return fail(err, errlen,
                        "%st: times must increase, got %g after %g", sub, k->t,
                        cam->path[i - 1].t);
        if ((f = cJSON_GetObjectItemCaseSensitive(key, "position")) == NULL)
            return fail(err, errlen, "%sposition: missing", sub);
        if ((st = get_vec3(f, sub, "position", &k->position, err, errlen)) != RBS_OK)
            return st;
        if ((f = cJSON_GetObjectItemCaseSensitive(key, "target")) == NULL)
            return fail(err, errlen, "%starget: missing", sub);
        if ((st = get_vec3(f, sub, "target", &k->target, err, errlen)) != RBS_OK)
            return st;
        i++;
        cam->path_count = (uint32_t)i;
    }
    return RBS_OK;
}

static void camera_defaults(rbsf__camera_def *cam)
{
    memset(cam, 0, sizeof *cam);
    cam->mode = RBSF__CAMERA_FIXED;
    cam->up.z = 1.0;
    cam->fov = 50.0;
    cam->znear = 0.05;
    cam->zfar = 100.0;
}

static rbs_status parse_camera(const cJSON *obj, const char *where,
                               rbsf__camera_def *cam, char *err, size_t errlen)
{
    const cJSON *f;
    rbs_status st;
    double len;
    int i;
    if (!cJSON_IsObject(obj))
        return fail(err, errlen, "%s: must be an object, got %s", where,
                    json_kind(obj));
    {
        char prefix[64];
        snprintf(prefix, sizeof prefix, "%s.", where);
        if ((st = check_keys(obj, camera_keys, prefix, err, errlen)) != RBS_OK)
            return st;
    }
    {
        char w[64];
        snprintf(w, sizeof w, "%s.", where);

        /* Without "mode", a camera with "mount" is mounted. */
        if (cJSON_GetObjectItemCaseSensitive(obj, "mode") == NULL &&
            cJSON_GetObjectItemCaseSensitive(obj, "mount") != NULL)
            cam->mode = RBSF__CAMERA_MOUNTED;
        if ((f = cJSON_GetObjectItemCaseSensitive(obj, "mode")) != NULL) {
            if (!cJSON_IsString(f))
                return fail(err, errlen, "%smode: must be \"fixed\", \"mounted\" "
                            "or \"free\", got %s", w, json_kind(f));
            if (strcmp(f->valuestring, "fixed") == 0)
                cam->mode = RBSF__CAMERA_FIXED;
            else if (strcmp(f->valuestring, "mounted") == 0)
                cam->mode = RBSF__CAMERA_MOUNTED;
            else if (strcmp(f->valuestring, "free") == 0)
                cam->mode = RBSF__CAMERA_FREE;
            else
                return fail(err, errlen, "%smode: must be \"fixed\", \"mounted\" "
                            "or \"free\", got \"%s\"", w, f->valuestring);
        }
        if ((f = cJSON_GetObjectItemCaseSensitive(obj, "position")) != NULL) {
            if ((st = get_vec3(f, w, "position", &cam->position, err, errlen)) != RBS_OK ||
                (st = check_coords(cam->position, w, "position", err, errlen)) != RBS_OK)
                return st;
            cam->has_position = 1;
        }
        if ((f = cJSON_GetObjectItemCaseSensitive(obj, "target")) != NULL) {
            if ((st = get_vec3(f, w, "target", &cam->target, err, errlen)) != RBS_OK ||
                (st = check_coords(cam->target, w, "target", err, errlen)) != RBS_OK)
                return st;
            cam->has_target = 1;
        }
        if ((f = cJSON_GetObjectItemCaseSensitive(obj, "up")) != NULL) {
            if ((st = get_vec3(f, w, "up", &cam->up, err, errlen)) != RBS_OK)
                return st;
            /* Scale by the largest component first, so tiny ups do not
             * underflow. */
            len = fmax(fabs(cam->up.x), fmax(fabs(cam->up.y), fabs(cam->up.z)));
            if (len > 0.0) {
                cam->up.x /= len;
                cam->up.y /= len;
                cam->up.z /= len;
            }
            len = vlen(cam->up);
            if (!(len > 0.0))
                return fail(err, errlen, "%sup: must be a nonzero vector", w);
            cam->up.x /= len;
            cam->up.y /= len;
            cam->up.z /= len;
        }
        if ((f = cJSON_GetObjectItemCaseSensitive(obj, "fov")) != NULL) {
            if ((st = get_number(f, w, "fov", &cam->fov, err, errlen)) != RBS_OK)
                return st;
            if (!(cam->fov >= kFovMin && cam->fov < 180.0))
                return fail(err, errlen, "%sfov: must be in [1e-6, 180) degrees, "
                            "got %g", w, cam->fov);
        }
        if ((f = cJSON_GetObjectItemCaseSensitive(obj, "near")) != NULL) {
            if ((st = get_number(f, w, "near", &cam->znear, err, errlen)) != RBS_OK)
                return st;
            if (!(cam->znear > 0.0))
                return fail(err, errlen, "%snear: must be > 0 m, got %g", w,
                            cam->znear);
        }
        if ((f = cJSON_GetObjectItemCaseSensitive(obj, "far")) != NULL) {
            if ((st = get_number(f, w, "far", &cam->zfar, err, errlen)) != RBS_OK)
                return st;
            cam->has_far = 1;
        }
        if (!(cam->zfar > cam->znear))
            return fail(err, errlen, "%sfar: must be > near (%g m), got %g", w,
                        cam->znear, cam->zfar);
        if ((f = cJSON_GetObjectItemCaseSensitive(obj, "mount")) != NULL) {
            if (!cJSON_IsString(f) || f->valuestring[0] == '\0')
                return fail(err, errlen, "%smount: must be a body name", w);
            if (strlen(f->valuestring) >= RBS_NAME_MAX)
                return fail(err, errlen, "%smount: name longer than %d bytes", w,
                            RBS_NAME_MAX - 1);
            if (cam->mode != RBSF__CAMERA_MOUNTED)
                return fail(err, errlen,
                            "%smount: only with \"mode\": \"mounted\"", w);
            strcpy(cam->mount, f->valuestring);
        }
        if ((f = cJSON_GetObjectItemCaseSensitive(obj, "offset")) != NULL) {
            if (cam->mode != RBSF__CAMERA_MOUNTED)
                return fail(err, errlen,
                            "%soffset: only with \"mode\": \"mounted\"", w);
            if ((st = get_vec3(f, w, "offset", &cam->offset, err, errlen)) != RBS_OK ||
                (st = check_coords(cam->offset, w, "offset", err, errlen)) != RBS_OK)
                return st;
            if (cam->offset.x == 0.0 && cam->offset.y == 0.0 && cam->offset.z == 0.0)
                return fail(err, errlen, "%soffset: must be nonzero (the camera "
                            "would sit inside the body)", w);
            if (!(vlen(cam->offset) >= kDistMin))
                return fail(err, errlen, "%soffset: shorter than 1e-100 m (too "
                            "close to the body to aim), got [%g, %g, %g]", w,
                            cam->offset.x, cam->offset.y, cam->offset.z);
            /* (an offset along up -- the camera straight above or below
             * its body -- is drawn by the along-up rule of sdl_camera.c,
             * as check accepts it) */
            cam->has_offset = 1;
        }
        if (cam->mode == RBSF__CAMERA_MOUNTED) {
            if (cam->mount[0] == '\0')
                return fail(err, errlen,
                            "%smount: missing (a mounted camera needs a body name)",
                            w);
            if (cam->has_position || cam->has_target)
                return fail(err, errlen,
                            "%s%s: not used by a mounted camera (it looks at the "
                            "body from \"offset\")",
                            w, cam->has_position ? "position" : "target");
        }
        if ((f = cJSON_GetObjectItemCaseSensitive(obj, "path")) != NULL) {
            if (cam->mode != RBSF__CAMERA_FIXED)
                return fail(err, errlen, "%spath: only with \"mode\": \"fixed\"", w);
            if (cam->has_position || cam->has_target)
                return fail(err, errlen,
                            "%s%s: a camera with a path takes it from the path",
                            w, cam->has_position ? "position" : "target");
            if ((st = parse_path(f, w, cam, err, errlen)) != RBS_OK)
                return st;
            for (i = 0; i < (int)cam->path_count; i++) {
                char k[64];
                snprintf(k, sizeof k, "path[%d].position", i);
                if ((st = check_coords(cam->path[i].position, w, k, err, errlen)) != RBS_OK)
                    return st;
                snprintf(k, sizeof k, "path[%d].target", i);
                if ((st = check_coords(cam->path[i].target, w, k, err, errlen)) != RBS_OK)
                    return st;
                if ((st = check_aim(cam->path[i].position, cam->path[i].target,
                                    cam->up, w, k, err, errlen)) != RBS_OK)
                    return st;
            }
        }
        if (cam->has_position && cam->has_target &&
            (st = check_aim(cam->position, cam->target, cam->up, w, "target",
                            err, errlen)) != RBS_OK)
            return st;
    }
    return RBS_OK;
}

void rbsf__config_defaults(rbsf__config *config)
{
    uint32_t i;
    memset(config, 0, sizeof *config);
    config->every = 1;
    config->width = 640;
    config->height = 480;
    config->window = RBSF__WINDOW_AUTO;
    config->contact_sheet = 1;
    config->view_count = 1;
    for (i = 0; i < RBSF__VIEWS_MAX; i++)
        camera_defaults(&config->cameras[i]);
    /* The default camera can be moved by commands and the mouse. */
    config->cameras[0].mode = RBSF__CAMERA_FREE;
}

void rbsf__config_free(rbsf__config *config)
{
    uint32_t i;
    if (config == NULL) return;
    free(config->path);
    config->path = NULL;
    for (i = 0; i < RBSF__VIEWS_MAX; i++) {
        free(config->cameras[i].path);
        config->cameras[i].path = NULL;
        config->cameras[i].path_count = 0;
    }
}

static rbs_status parse_entry(const cJSON *root, rbsf__config *config,
                              char *err, size_t errlen)
{
    const cJSON *f;
    rbs_status st;
    if (!cJSON_IsObject(root))
        return fail(err, errlen, "entry: must be a JSON object, got %s",
                    json_kind(root));
    if ((st = check_keys(root, entry_keys, "", err, errlen)) != RBS_OK)
        return st;
    if ((f = cJSON_GetObjectItemCaseSensitive(root, "type")) != NULL &&
        (!cJSON_IsString(f) || strcmp(f->valuestring, "sdl") != 0))
        return fail(err, errlen, "type: must be \"sdl\" for this renderer");
    if ((f = cJSON_GetObjectItemCaseSensitive(root, "path")) != NULL) {
        if (!cJSON_IsString(f) || f->valuestring[0] == '\0')
            return fail(err, errlen, "path: must be a folder name (a non-empty "
                        "string), got %s", json_kind(f));
        config->path = (char *)malloc(strlen(f->valuestring) + 1);
        if (config->path == NULL) {
            snprintf(err, errlen, "path: out of memory");
            return RBS_E_MEMORY;
        }
        strcpy(config->path, f->valuestring);
    }
    if ((f = cJSON_GetObjectItemCaseSensitive(root, "every")) != NULL &&
        (st = get_uint(f, "", "every", 1, RBS_EVERY_MAX, &config->every, err,
                       errlen)) != RBS_OK)
        return st;
    if ((f = cJSON_GetObjectItemCaseSensitive(root, "width")) != NULL &&
        (st = get_uint(f, "", "width", 16, RBSF__SIDE_MAX, &config->width, err,
                       errlen)) != RBS_OK)
        return st;
    if ((f = cJSON_GetObjectItemCaseSensitive(root, "height")) != NULL &&
        (st = get_uint(f, "", "height", 16, RBSF__SIDE_MAX, &config->height,
                       err, errlen)) != RBS_OK)
        return st;
    if ((f = cJSON_GetObjectItemCaseSensitive(root, "window")) != NULL) {
        if (cJSON_IsBool(f))
            config->window = cJSON_IsTrue(f) ? RBSF__WINDOW_ON : RBSF__WINDOW_OFF;
        else if (cJSON_IsString(f) && strcmp(f->valuestring, "auto") == 0)
            config->window = RBSF__WINDOW_AUTO;
        else
            return fail(err, errlen,
                        "window: must be \"auto\", true or false, got %s%s%s",
                        json_kind(f), cJSON_IsString(f) ? " " : "",
                        cJSON_IsString(f) ? f->valuestring : "");
    }
    if ((f = cJSON_GetObjectItemCaseSensitive(root, "tile")) != NULL &&
        (st = get_bool(f, "", "tile", &config->tile, err, errlen)) != RBS_OK)
        return st;
    if ((f = cJSON_GetObjectItemCaseSensitive(root, "contact_sheet")) != NULL &&
        (st = get_bool(f, "", "contact_sheet", &config->contact_sheet, err,
                       errlen)) != RBS_OK)
        return st;
    if (cJSON_GetObjectItemCaseSensitive(root, "camera") != NULL &&
        cJSON_GetObjectItemCaseSensitive(root, "views") != NULL)
        return fail(err, errlen, "views: give either \"camera\" or \"views\", "
                    "not both");
    if ((f = cJSON_GetObjectItemCaseSensitive(root, "camera")) != NULL) {
        camera_defaults(&config->cameras[0]);
        config->camera_given = 1;
        if ((st = parse_camera(f, "camera", &config->cameras[0], err, errlen)) != RBS_OK)
            return st;
    }
    if ((f = cJSON_GetObjectItemCaseSensitive(root, "views")) != NULL) {
        int n, i = 0;
        const cJSON *v;
        if (!cJSON_IsArray(f) || (n = cJSON_GetArraySize(f)) < 1 ||
            n > RBSF__VIEWS_MAX)
            return fail(err, errlen,
                        "views: must be an array of 1 to %d cameras, got %s%s",
                        RBSF__VIEWS_MAX, json_kind(f),
                        cJSON_IsArray(f) ? " of another length" : "");
        camera_defaults(&config->cameras[0]);
        config->camera_given = 1;
        config->view_count = (uint32_t)n;
        cJSON_ArrayForEach(v, f) {
            char where[32];
            snprintf(where, sizeof where, "views[%d]", i);
            if ((st = parse_camera(v, where, &config->cameras[i], err, errlen)) != RBS_OK)
                return st;
            i++;
        }
    }
    if ((uint64_t)config->width * config->height > 16u * 1024u * 1024u)
        return fail(err, errlen, "width: %u x %u pixels is too large (at most "
                    "16 Mpixel per view)", config->width, config->height);
    return RBS_OK;
}

rbs_status rbsf__config_parse(const char *json, rbsf__config *config,
                              char *err, size_t errlen)
{
    cJSON *root;
    const char *end = NULL;
    rbs_status st;
    rbsf__config_defaults(config);
    if (json == NULL) return RBS_OK;
    /* ParseWithOpts reports where parsing stopped through end (the global
     * cJSON_GetErrorPtr is not thread-safe). */
    root = cJSON_ParseWithOpts(json, &end, 1);
    if (root == NULL)
        return fail(err, errlen, "entry: not valid JSON at byte %ld",
                    end != NULL ? (long)(end - json) : 0L);
    st = parse_entry(root, config, err, errlen);
    cJSON_Delete(root);
    if (st != RBS_OK) rbsf__config_free(config);
    return st;
}
