/*
 * out.c - output files written a whole frame at a time, the shortest
 * round-trip number format, and the check of a dumper's entry.
 */
#include "dump_internal.h"
#include "c_locale.h"
#include "shown.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

size_t rbsf__format_double(char *buf, size_t size, double x)
{
    int prec, n = 0;
    if (size == 0)
        return 0;
    if (isnan(x))
        return (size_t)snprintf(buf, size, "nan");
    if (isinf(x))
        return (size_t)snprintf(buf, size, x > 0 ? "inf" : "-inf");
    if (x == floor(x) && fabs(x) < 1e15) {
        /* a whole number as one: 10, not the shorter 1e+01 (a frame's time,
         * a count); exact below 2^53, and -0 keeps its sign */
        n = snprintf(buf, size, "%.0f", x);
        return n < 0 || (size_t)n >= size ? 0 : (size_t)n;
    }
    /* The shortest precision that reads back as the same double (17
     * significant digits always do, for IEEE binary64).  Reading back is
     * monotonic in the precision -- the nearest (p+1)-digit decimal is no
     * farther from x than the nearest p-digit one, which is one of them --
     * so the search is a bisection: most values of a simulation need 16
     * or 17 digits (two or three tries where counting up took 17), round
     * ones are found in about five. */
    {
        int lo = 1, hi = 17, k = 0;
        /* first 15, the usual boundary; hi: the least precision known to
         * read back (17 by the standard), lo: the least not known to fail */
        for (prec = 15;; prec = lo + (hi - lo) / 2) {
            n = snprintf(buf, size, "%.*g", prec, x);
            if (n < 0 || (size_t)n >= size)
                return 0;
            if (strtod(buf, NULL) == x)
                hi = prec;
            else
                lo = prec + 1;
            if (lo >= hi || ++k > 8)
                break;
        }
        if (prec != hi) { /* the buffer holds a precision that failed: print hi */
            n = snprintf(buf, size, "%.*g", hi, x);
            if (n < 0 || (size_t)n >= size)
                return 0;
        }
    }
    return (size_t)n;
}

size_t rbsf_format_double(char *buf, size_t size, double x)
{
    rbsf__locale l;
    size_t n;
    rbsf__c_locale_push(&l);
    n = rbsf__format_double(buf, size, x);
    rbsf__c_locale_pop(&l);
    return n;
}

/* open(path, O_WRONLY | O_CREAT | O_TRUNC) in the stopper (it blocks for a
 * FIFO until a reader comes): the descriptor, or -1 with errno, EINTR when
 * the stopper ended it. */
static int open_output(rbsf_stopper *stopper, const char *path)
{
    for (;;) {
        int slot = rbsf__stopper_enter(stopper);
        int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0666);
        int e = errno;
        rbsf__stopper_leave(stopper, slot);
        if (fd >= 0 || e != EINTR || rbsf__stopper_stopped(stopper)) {
            errno = e;
            return fd;
        }
    }
}

rbs_status rbsf__out_open(rbsf__out *out, const char *path, size_t cap,
                          rbsf_stopper *stopper, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    out->fd = -1;
    out->stopper = stopper;
    out->path = malloc(strlen(path) + 1);
    out->buf = malloc(cap);
    if (out->path == NULL || out->buf == NULL) {
        rbsf__out_free(out);
        snprintf(err, errlen, "out of memory for a %lu-byte frame buffer",
                 (unsigned long)cap);
        return RBS_E_MEMORY;
    }
    strcpy(out->path, path);
    out->cap = cap;
    if (strcmp(path, "-") == 0) {
        out->fd = STDOUT_FILENO;
        out->owned = 0;
        return RBS_OK;
    }
    out->fd = open_output(stopper, path);
    if (out->fd < 0 && errno == ENOENT) {
        /* the one missing folder rbsf_check_output_file allowed */
        char *slash = strrchr(out->path, '/');
        if (slash != NULL && slash != out->path) {
            *slash = '\0';
            if (mkdir(out->path, 0777) != 0 && errno != EEXIST) {
                snprintf(err, errlen, "cannot create folder '%s': %s", out->path, strerror(errno));
                *slash = '/';
                rbsf__out_free(out);
                return RBS_E_IO;
            }
            *slash = '/';
            out->fd = open_output(stopper, path);
        }
    }
    if (out->fd < 0 && errno == EINTR) {
        snprintf(err, errlen, "opening '%s' given up: the run was stopped while "
                              "it waited (a FIFO waits for a reader)", path);
        rbsf__out_free(out);
        return RBS_E_CLOSED;
    }
    if (out->fd < 0) {
        snprintf(err, errlen, "cannot create '%s': %s", path, strerror(errno));
        rbsf__out_free(out);
        return RBS_E_IO;
    }
    out->owned = 1;
    return RBS_OK;
}

rbs_status rbsf__out_put(rbsf__out *out, const char *s, size_t n)
{
    if (n > out->cap - out->len)
        return RBS_E_CAPACITY;
    memcpy(out->buf + out->len, s, n);
    out->len += n;
    return RBS_OK;
}

rbs_status rbsf__out_num(rbsf__out *out, double x)
{
    char b[40];
    size_t n = rbsf__format_double(b, sizeof b, x);
    return rbsf__out_put(out, b, n);
}

rbs_status rbsf__out_uint(rbsf__out *out, unsigned long long v)
{
    char b[24];
    int n = snprintf(b, sizeof b, "%llu", v);
    return rbsf__out_put(out, b, (size_t)n);
}

void rbsf__out_discard(rbsf__out *out)
{
    out->len = 0;
}

rbs_status rbsf__out_commit(rbsf__out *out, char *err, size_t errlen)
{
    size_t done = 0;
    if (out->failed) {
        snprintf(err, errlen, "'%s': an earlier write failed", out->path);
        return RBS_E_IO;
    }
    while (done < out->len) {
        int slot = rbsf__stopper_enter(out->stopper);
        ssize_t w = write(out->fd, out->buf + done, out->len - done);
        int e = w < 0 ? errno : EIO, given_up;
        rbsf__stopper_leave(out->stopper, slot);
        given_up = w < 0 && e == EINTR && rbsf__stopper_stopped(out->stopper);
        if (w < 0 && e == EINTR && !given_up)
            continue;
        if (w <= 0) {
            out->failed = 1;
            /* Cut the frame's partial bytes off again: the file ends on the
             * last whole frame (a pipe keeps what it took). */
            if (done > 0 && out->owned && ftruncate(out->fd, out->good) == 0)
                lseek(out->fd, out->good, SEEK_SET);
            if (given_up)
                snprintf(err, errlen, "write to '%s' given up: the run was "
                                      "stopped while it blocked (%lu of the "
                                      "frame's %lu bytes written)",
                         out->path, (unsigned long)done, (unsigned long)out->len);
            else
                snprintf(err, errlen, "write to '%s' failed: %s", out->path,
                         strerror(e));
            out->len = 0;
            return given_up ? RBS_E_CLOSED : RBS_E_IO;
        }
        done += (size_t)w;
    }
    out->good += (off_t)out->len;
    out->len = 0;
    return RBS_OK;
}

/* Is the file written still at out->path?  A file removed during the run
 * (rm -rf of its folder) takes every write to the end without an error, into
 * an inode with no name that goes when it is closed; one moved or replaced
 * is not where the output was asked for.  Either is an output lost, as a
 * failed write is: RBS_E_IO naming the path.  Regular files only (a device
 * or a pipe keeps nothing to lose). */
static rbs_status out_still_there(const rbsf__out *out, char *err, size_t errlen)
{
    struct stat fd_sb, path_sb;
    if (fstat(out->fd, &fd_sb) != 0 || !S_ISREG(fd_sb.st_mode))
        return RBS_OK;
    if (fd_sb.st_nlink == 0) {
        snprintf(err, errlen, "'%s' was removed during the run (the file or its "
                              "folder): what was written to it is lost", out->path);
        return RBS_E_IO;
    }
    if (stat(out->path, &path_sb) != 0) {
        snprintf(err, errlen, "'%s' was moved or removed during the run (%s): "
                              "what was written to it is not there",
                 out->path, strerror(errno));
        return RBS_E_IO;
    }
    if (path_sb.st_dev != fd_sb.st_dev || path_sb.st_ino != fd_sb.st_ino) {
        snprintf(err, errlen, "'%s' was replaced by another file during the run: "
                              "what was written to it is not there", out->path);
        return RBS_E_IO;
    }
    return RBS_OK;
}

rbs_status rbsf__out_close(rbsf__out *out, char *err, size_t errlen)
{
    rbs_status st = RBS_OK;
    if (out->fd >= 0 && out->owned) {
        if (!out->failed)
            st = out_still_there(out, err, errlen);
        if (close(out->fd) != 0 && !out->failed && st == RBS_OK) {
            snprintf(err, errlen, "closing '%s' failed: %s", out->path,
                     strerror(errno));
            st = RBS_E_IO;
        }
    }
    out->fd = -1;
    return st;
}

void rbsf__out_free(rbsf__out *out)
{
    if (out->fd >= 0 && out->owned)
        close(out->fd);
    out->fd = -1;
    free(out->buf);
    free(out->path);
    out->buf = NULL;
    out->path = NULL;
}

size_t rbsf__frame_bytes(uint32_t max_bodies, size_t per_body)
{
    return 1024 + (size_t)max_bodies * per_body;
}

const char *rbsf_shown_path(const char *path, char *buf, size_t size)
{
    size_t n = strlen(path), half = (size - 4) / 2;
    if (n < size) {
        memcpy(buf, path, n + 1);
    } else {
        memcpy(buf, path, half);
        memcpy(buf + half, "...", 3);
        memcpy(buf + half + 3, path + n - half, half);
        buf[2 * half + 3] = '\0';
    }
    /* (a control character or an override in the path as '?', shown.h; a
     * character cut at "..." too) */
    return rbsf__shown(buf, buf, size);
}

/* Whether a file can be made in the folder dir (strlen(dir) + 15 bytes
 * of room after it): a temporary file is made and removed again, which
 * proves what access() cannot (root may "write" in /proc and /sys, where
 * nothing can be created).  Says why not in err. */
static int can_create_in(char *dir, const char *shown, char *err,
                         size_t errlen)
{
    char shown_dir[160];
    size_t len = strlen(dir);
    int fd, e;
    strcpy(dir + len, "/.rbsim-XXXXXX");
    fd = mkstemp(dir);
    e = errno;
    if (fd >= 0) {
        close(fd);
        unlink(dir);
    }
    dir[len] = '\0';
    if (fd < 0) {
        snprintf(err, errlen, "cannot create '%s' in '%s': %s", shown,
                 rbsf_shown_path(dir, shown_dir, sizeof shown_dir),
                 strerror(e));
        return 0;
    }
    return 1;
}

/* Why the folder dir, which is not one, cannot hold a new file, in err: the
 * deepest part of it that exists is not a folder (base.json/x.csv,
 * /dev/null/x.csv), or more than its last part is missing (more likely a
 * typo).  Returns 1 when dir is just one missing folder inside a folder
 * where one can be made (it is made when the file is opened).  dir is
 * changed (its parts taken off) and needs 15 bytes of room after it. */
static int one_missing_folder(char *dir, const char *shown, char *err,
                              size_t errlen)
{
    struct stat sb;
    char shown_dir[160], shown_missing[160];
    int depth = 0;
    rbsf_shown_path(dir, shown_missing, sizeof shown_missing);
    /* Walk up to the deepest part that exists. */
    while (stat(dir, &sb) != 0) {
        char *up = strrchr(dir, '/');
        if (errno != ENOENT && errno != ENOTDIR) {
            snprintf(err, errlen, "cannot create '%s': '%s': %s", shown,
                     rbsf_shown_path(dir, shown_dir, sizeof shown_dir),
                     strerror(errno));
            return 0;
        }
        while (up != NULL && up > dir && up[-1] == '/')
            up--;
        if (up == NULL)
            strcpy(dir, ".");
        else
            up[up == dir] = '\0'; /* ("/x" goes up to "/") */
        depth++;
    }
    if (!S_ISDIR(sb.st_mode)) {
        snprintf(err, errlen, "cannot create '%s': '%s' is not a folder",
                 shown, rbsf_shown_path(dir, shown_dir, sizeof shown_dir));
        return 0;
    }
    if (depth > 1) {
        snprintf(err, errlen, "cannot create '%s': folder '%s' does not exist "
                              "(one missing folder is made, not more)",
                 shown, shown_missing);
        return 0;
    }
    if (access(dir, W_OK) != 0) {
        snprintf(err, errlen, "cannot create '%s': folder '%s' does not exist "
                              "and cannot be made in '%s': %s",
                 shown, shown_missing,
                 rbsf_shown_path(dir, shown_dir, sizeof shown_dir),
                 strerror(errno));
        return 0;
    }
    return can_create_in(dir, shown, err, errlen);
}

rbs_status rbsf_check_output_file(const char *path, char *err, size_t errlen)
{
    struct stat sb;
    char *dir;
    const char *slash;
    char shown[160], shown_dir[160];
    size_t n;
    int ok;

    if (path == NULL || path[0] == '\0') {
        snprintf(err, errlen, "no output path given");
        return RBS_E_IO;
    }
    if (strcmp(path, "-") == 0)
        return RBS_OK;
    /* (paths are shown shortened: the reason must fit the message) */
    rbsf_shown_path(path, shown, sizeof shown);
#ifdef PATH_MAX
    if (strlen(path) >= (size_t)PATH_MAX) {
        snprintf(err, errlen, "'%s': path too long: %lu bytes, past the system's "
                              "limit of %d bytes for a path",
                 shown, (unsigned long)strlen(path), PATH_MAX - 1);
        return RBS_E_IO;
    }
#endif
    if (stat(path, &sb) == 0) {
        if (S_ISDIR(sb.st_mode)) {
            snprintf(err, errlen, "'%s' is a folder, expected a file name", shown);
            return RBS_E_IO;
        }
        if (access(path, W_OK) != 0) {
            snprintf(err, errlen, "cannot write '%s': %s", shown, strerror(errno));
            return RBS_E_IO;
        }
        return RBS_OK;
    }
    if (errno == ENAMETOOLONG) { /* a name in it past the file system's limit */
        snprintf(err, errlen, "cannot create '%s': %s", shown, strerror(errno));
        return RBS_E_IO;
    }
    /* The file does not exist yet: its folder must (room for the probe's
     * "/.rbsim-XXXXXX" after it). */
    slash = strrchr(path, '/');
    n = slash == NULL ? 1 : (slash == path ? 1 : (size_t)(slash - path));
    dir = malloc(n + 16);
    if (dir == NULL) {
        snprintf(err, errlen, "out of memory");
        return RBS_E_MEMORY;
    }
    if (slash == NULL)
        strcpy(dir, ".");
    else {
        memcpy(dir, path, n);
        dir[n] = '\0';
    }
    if (stat(dir, &sb) == 0 && S_ISDIR(sb.st_mode)) {
        ok = access(dir, W_OK) == 0;
        if (!ok)
            snprintf(err, errlen, "cannot create '%s' in '%s': %s", shown,
                     rbsf_shown_path(dir, shown_dir, sizeof shown_dir),
                     strerror(errno));
        else
            ok = can_create_in(dir, shown, err, errlen);
    } else {
        /* One missing folder (the scenes' "out/") is made when the run
         * starts, if its own parent is a writable folder; a deeper missing
         * path is more likely a typo, and a file on the way (base.json/x.csv,
         * /dev/null/x.csv) can never hold one: both are refused. */
        ok = one_missing_folder(dir, shown, err, errlen);
    }
    free(dir);
    return ok ? RBS_OK : RBS_E_IO;
}

rbs_status rbsf__dump_check(const char *name, const rbs_renderer_config *config,
                            char *err, size_t errlen)
{
    static const char *const keys[] = {"type", "path", "every", NULL};
    if (config->json != NULL) {
        cJSON *root = cJSON_Parse(config->json);
        const cJSON *item;
        if (root == NULL || !cJSON_IsObject(root)) {
            cJSON_Delete(root);
            snprintf(err, errlen, "the entry must be a JSON object");
            return RBS_E_SCENE;
        }
        cJSON_ArrayForEach(item, root) {
            int i, known = 0;
            for (i = 0; keys[i]; i++)
                known |= strcmp(item->string, keys[i]) == 0;
            if (!known) {
                snprintf(err, errlen,
                         "unknown key '%s' in a %s entry (expected type, path, "
                         "every)",
                         item->string, name);
                cJSON_Delete(root);
                return RBS_E_SCENE;
            }
        }
        item = cJSON_GetObjectItemCaseSensitive(root, "path");
        if (item != NULL && (!cJSON_IsString(item) || item->valuestring[0] == 0)) {
            snprintf(err, errlen, "path: must be a file name (a non-empty string)");
            cJSON_Delete(root);
            return RBS_E_SCENE;
        }
        {
            const cJSON *every = cJSON_GetObjectItemCaseSensitive(root, "every");
            if (every != NULL &&
                (!cJSON_IsNumber(every) || every->valuedouble < 1 ||
                 every->valuedouble > 4294967295.0 ||
                 every->valuedouble != floor(every->valuedouble))) {
                snprintf(err, errlen, "every: must be a whole number >= 1");
                cJSON_Delete(root);
                return RBS_E_SCENE;
            }
        }
        if (config->path == NULL && item != NULL) {
            /* Only the JSON names the file. */
            rbs_status st = rbsf_check_output_file(item->valuestring, err, errlen);
            cJSON_Delete(root);
            return st;
        }
        cJSON_Delete(root);
    }
    if (config->path == NULL) {
        snprintf(err, errlen, "a %s renderer needs \"path\": a file name", name);
        return RBS_E_SCENE;
    }
    return rbsf_check_output_file(config->path, err, errlen);
}

rbs_status rbsf__dump_path(const rbs_renderer_config *config, char *buf,
                           size_t n, char *err, size_t errlen)
{
    cJSON *root;
    const cJSON *item;
    if (config->path != NULL) {
        if (strlen(config->path) >= n) {
            snprintf(err, errlen, "path too long (at most %lu bytes)",
                     (unsigned long)n - 1);
            return RBS_E_INVALID;
        }
        strcpy(buf, config->path);
        return RBS_OK;
    }
    root = config->json ? cJSON_Parse(config->json) : NULL;
    item = cJSON_GetObjectItemCaseSensitive(root, "path");
    if (!cJSON_IsString(item) || strlen(item->valuestring) >= n ||
        item->valuestring[0] == '\0') {
        cJSON_Delete(root);
        snprintf(err, errlen, "no output path given (or longer than %lu bytes)",
                 (unsigned long)n - 1);
        return RBS_E_INVALID;
    }
    strcpy(buf, item->valuestring);
    cJSON_Delete(root);
    return RBS_OK;
}
