/*
 * checkpoint.c - exact checkpoints of a world.
 *
 * A world is one block whose arrays are laid out by its definition alone, so
 * a checkpoint is: a header (magic, format version, byte order, sizes), the
 * definition, the world's counters, and the block's arrays verbatim -- every
 * double bit for bit -- followed by an FNV-1a 64-bit checksum of all that
 * precedes it.  Reading checks everything before it builds anything.
 *
 * Format version CKPT_VERSION (little or big endian as written; a reader on
 * the other byte order rejects it as foreign; see CKPT_VERSION for the
 * earlier ones):
 *   char     magic[8]   "RBSCKPT\0"
 *   uint32   version    CKPT_VERSION
 *   uint32   endian     0x01020304
 *   uint32   def_size   sizeof(rbs_world_def)
 *   uint32   reserved   0
 *   uint64   arrays     bytes of the arrays region
 *   rbs_world_def def
 *   counters (see struct counters)
 *   arrays
 *   uint64   checksum
 */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/world_internal.h"

/* The arrays are the world's block verbatim, so the version changes with
 * its layout: 1 lost the warm table's extent; 2 carried it; 3 has contacts
 * of 136 bytes (levers along n, the pair's row) and a default pair row; 4
 * adds the name index and the time base of rbs_world_set_dt; 5 has
 * rbs_world_def.soft_substeps; 6 has contacts of 120 bytes (restitution
 * from the pair row, a's lever from its radius); 7 has
 * rbs_world_def.soft_tolerance; 8 has the soft step's gathered layout (its
 * slabs, records order, chunks sharing the contacts' room, the team's
 * words); 9 has the warm table's index by slot (warm_at), and the table
 * may be in the soft step's buckets; 10 has the same layout, but the soft
 * step's model changed (its contact spring at a third of the sub-step
 * rate, exact flight of a body no contact touches), so a 9 file would
 * resume on other physics than the run that wrote it; 11 has contacts of
 * 128 bytes (jslip: kinetic friction for a contact that came in slipping);
 * 12 has the pressed marks (a byte a slot: spheres loaded by other moving
 * spheres) and their resting thresholds, the impact floor and the strict
 * work cap, so an 11 file would resume on other physics; 13 has the
 * resistance records' impact share (rbs__resist.impact: the soft step's
 * rolling and spinning rows take no impact as load), and the resting pass
 * takes an unloaded contact's friction back, so a 12 file would resume on
 * other physics too; 14 has a second warm-start table (warm_save: the
 * table at a step's start, which a failed step puts back). */
#define CKPT_VERSION 14u
static const char ckpt_magic[8] = {'R', 'B', 'S', 'C', 'K', 'P', 'T', '\0'};

typedef struct header {
    char magic[8];
    uint32_t version;
    uint32_t endian;
    uint32_t def_size;
    uint32_t reserved;
    uint64_t arrays;
} header;

typedef struct counters {
    uint64_t step_count;
    uint32_t slots, bodies, free_count, materials, pairs, contacts_high;
    uint32_t warm_used; /* the warm-start table's part in use (version 2) */
    uint32_t reserved;  /* 0 */
    double time_base;   /* the time at step_base (version 4: rbs_world_set_dt) */
    uint64_t step_base;
} counters;

static uint64_t fnv1a(uint64_t h, const unsigned char *p, size_t n)
{
    size_t i;
    for (i = 0; i < n; ++i) {
        h ^= p[i];
        h *= 1099511628211ull;
    }
    return h;
}

static size_t arrays_offset(void) { return (sizeof(rbs_world) + 15u) & ~(size_t)15u; }

size_t rbs_world_checkpoint_size(const rbs_world *w)
{
    if (w == NULL || w->bytes == 0)
        return 0;
    return sizeof(header) + sizeof(rbs_world_def) + sizeof(counters) +
           (w->bytes - arrays_offset()) + sizeof(uint64_t);
}

rbs_status rbs_world_checkpoint_write(const rbs_world *w, void *buf, size_t size, size_t *written)
{
    size_t need = rbs_world_checkpoint_size(w), at = 0;
    unsigned char *out = (unsigned char *)buf;
    header h;
    counters c;
    uint64_t sum;
    if (need == 0 || buf == NULL)
        return RBS_E_INVALID;
    if (size < need)
        return RBS_E_MEMORY;
    memset(&h, 0, sizeof h);
    memcpy(h.magic, ckpt_magic, sizeof h.magic);
    h.version = CKPT_VERSION;
    h.endian = 0x01020304u;
    h.def_size = (uint32_t)sizeof(rbs_world_def);
    h.arrays = (uint64_t)(w->bytes - arrays_offset());
    memset(&c, 0, sizeof c);
    c.step_count = w->step_count;
    c.time_base = w->time_base;
    c.step_base = w->step_base;
    c.slots = w->slots;
    c.bodies = w->bodies;
    c.free_count = w->free_count;
    c.materials = w->materials;
    c.pairs = w->pairs;
    c.contacts_high = w->contacts_high;
    c.warm_used = w->warm_used;
    memcpy(out + at, &h, sizeof h);
    at += sizeof h;
    memcpy(out + at, &w->def, sizeof w->def);
    at += sizeof w->def;
    memcpy(out + at, &c, sizeof c);
    at += sizeof c;
    memcpy(out + at, (const unsigned char *)w + arrays_offset(), (size_t)h.arrays);
    at += (size_t)h.arrays;
    sum = fnv1a(14695981039346656037ull, out, at);
    memcpy(out + at, &sum, sizeof sum);
    at += sizeof sum;
    if (written)
        *written = at;
    return RBS_OK;
}

/* Check a checkpoint buffer; on success *def and *c hold its contents. */
static rbs_status ckpt_check(const unsigned char *in, size_t size, rbs_world_def *def, counters *c,
                             uint64_t *arrays, char *msg, size_t len)
{
    header h;
    uint64_t sum, want;
    size_t body, need;
    if (size < sizeof h) {
        snprintf(msg, len, "truncated: %zu bytes is shorter than a checkpoint header", size);
        return RBS_E_CORRUPT;
    }
    memcpy(&h, in, sizeof h);
    if (memcmp(h.magic, ckpt_magic, sizeof h.magic) != 0) {
        snprintf(msg, len, "not an rbsim checkpoint (bad magic)");
        return RBS_E_CORRUPT;
    }
    if (h.endian != 0x01020304u) {
        snprintf(msg, len, "written on a machine of the other byte order");
        return RBS_E_CORRUPT;
    }
    if (h.version != CKPT_VERSION) {
        snprintf(msg, len, "format version %u, this library reads version %u", (unsigned)h.version,
                 CKPT_VERSION);
        return RBS_E_VERSION;
    }
    if (h.def_size != sizeof(rbs_world_def)) {
        snprintf(msg, len, "written by a library with another world definition (%u bytes, here %zu)",
                 (unsigned)h.def_size, sizeof(rbs_world_def));
        return RBS_E_VERSION;
    }
    body = sizeof h + sizeof(rbs_world_def) + sizeof(counters);
    if (h.arrays > (uint64_t)size || size < body + (size_t)h.arrays + sizeof sum) {
        snprintf(msg, len, "truncated: %zu bytes, expected %llu", size,
                 (unsigned long long)(body + h.arrays + sizeof sum));
        return RBS_E_CORRUPT;
    }
    need = body + (size_t)h.arrays;
    memcpy(&sum, in + need, sizeof sum);
    want = fnv1a(14695981039346656037ull, in, need);
    if (sum != want) {
        snprintf(msg, len, "checksum mismatch: the file is corrupt");
        return RBS_E_CORRUPT;
    }
    if (size != need + sizeof sum) {
        snprintf(msg, len, "%zu trailing bytes after the checkpoint", size - need - sizeof sum);
        return RBS_E_CORRUPT;
    }
    memcpy(def, in + sizeof h, sizeof *def);
    memcpy(c, in + sizeof h + sizeof *def, sizeof *c);
    /* (the time may be infinite: steps of a huge dt overflow it) */
    if (!(c->time_base >= 0.0) || c->step_base > c->step_count) {
        rbs__snprintf_c(msg, len, "its time base is not a time (%g s at step %llu of %llu)", c->time_base,
                 (unsigned long long)c->step_base, (unsigned long long)c->step_count);
        return RBS_E_CORRUPT;
    }
    *arrays = h.arrays;
    return RBS_OK;
}

static rbs_status create_from(const void *buf, size_t size, rbs_world **out, char *msg, size_t len)
{
    const unsigned char *in = (const unsigned char *)buf;
    rbs_world_def def;
    counters c;
    uint64_t arrays;
    rbs_world *w;
    rbs_status st;
    if (out == NULL || buf == NULL)
        return RBS_E_INVALID;
    *out = NULL;
    st = ckpt_check(in, size, &def, &c, &arrays, msg, len);
    if (st != RBS_OK)
        return st;
    def.struct_size = (uint32_t)sizeof def;
    st = rbs_world_create(&def, &w);
    if (st != RBS_OK) {
        snprintf(msg, len, "its world definition is not valid here (%s)", rbs_status_string(st));
        return st == RBS_E_MEMORY ? st : RBS_E_CORRUPT;
    }
    if (w->bytes - arrays_offset() != arrays || c.slots > def.max_bodies ||
        c.materials > def.max_materials || c.pairs > def.max_pairs || c.bodies > c.slots ||
        c.free_count > c.slots || c.warm_used > w->warm_size) {
        rbs_world_destroy(w);
        snprintf(msg, len, "its layout does not match its definition");
        return RBS_E_CORRUPT;
    }
    memcpy((unsigned char *)w + arrays_offset(),
           in + sizeof(header) + sizeof(rbs_world_def) + sizeof(counters), (size_t)arrays);
    w->step_count = c.step_count;
    w->time_base = c.time_base;
    w->step_base = c.step_base;
    w->slots = c.slots;
    w->bodies = c.bodies;
    w->free_count = c.free_count;
    w->materials = c.materials;
    w->pairs = c.pairs;
    w->contacts_high = c.contacts_high;
    w->warm_used = c.warm_used;
    /* (the table may be in the soft step's buckets, and its index is not
     * kept: sorted before a search by key, indexed again before the soft
     * step's) */
    w->warm_ranked = 1;
    w->warm_indexed = 0;
    w->plan_dirty = 1;
    rbs__rebuild_lists(w); /* derived lists */
    rbs__rebuild_pair_table(w);
    *out = w;
    return RBS_OK;
}

rbs_status rbs_world_create_from_checkpoint(const void *buf, size_t size, rbs_world **out)
{
    char msg[256];
    return create_from(buf, size, out, msg, sizeof msg);
}

rbs_status rbs_world_create_from_checkpoint_v2(const void *buf, size_t size, rbs_world **out, char *message,
                                               size_t message_size)
{
    char msg[256] = "";
    rbs_status st = create_from(buf, size, out, msg, sizeof msg);
    if (message != NULL && message_size > 0)
        snprintf(message, message_size, "%s", st == RBS_OK ? "" : msg[0] ? msg : rbs_status_string(st));
    return st;
}

char *rbs__link_target(const char *path)
{
    char *cur = NULL;
    int hops;
    size_t n = strlen(path);
    struct stat sb;
    if ((cur = (char *)malloc(n + 1)) == NULL)
        return NULL;
    memcpy(cur, path, n + 1);
    for (hops = 0; hops < 40; ++hops) {
        char buf[4096], *next, *slash;
        ssize_t k;
        size_t dir;
        if (lstat(cur, &sb) != 0 || !S_ISLNK(sb.st_mode))
            return cur;
        k = readlink(cur, buf, sizeof buf - 1);
        if (k < 0)
            break;
        buf[k] = '\0';
        slash = strrchr(cur, '/');
        dir = (buf[0] != '/' && slash != NULL) ? (size_t)(slash - cur) + 1 : 0;
        if ((next = (char *)malloc(dir + (size_t)k + 1)) == NULL)
            break;
        memcpy(next, cur, dir);
        memcpy(next + dir, buf, (size_t)k + 1);
        free(cur);
        cur = next;
    }
    free(cur);
    return NULL;
}

/* "PATH: why" into message (if any), and st. */
static rbs_status save_fail(char *message, size_t size, rbs_status st, const char *path, const char *why)
{
    if (message != NULL && size > 0)
        snprintf(message, size, "%s: %s", path, why);
    return st;
}

rbs_status rbs_world_save_v2(const rbs_world *w, const char *path, char *message, size_t message_size)
{
    size_t n = rbs_world_checkpoint_size(w), len;
    unsigned char *buf;
    char *tmp, *target = NULL;
    int fd;
    struct stat sb;
    rbs_status st = RBS_OK;
    const char *why = NULL;
    if (message != NULL && message_size > 0)
        message[0] = '\0';
    if (n == 0 || path == NULL || path[0] == '\0')
        return save_fail(message, message_size, RBS_E_INVALID, path ? path : "(null)",
                         n == 0 ? "not a world" : "no path");
    /* The rename would replace whatever the path names: refuse what is
     * not a regular file (a device such as /dev/null, a FIFO, a folder);
     * through a symbolic link, write the file it points to (the link
     * stays). */
    if (stat(path, &sb) == 0 && !S_ISREG(sb.st_mode))
        return save_fail(message, message_size, RBS_E_IO, path,
                         S_ISDIR(sb.st_mode) ? "is a folder, not a regular file"
                                             : "exists and is not a regular file (never replaced)");
    if (lstat(path, &sb) == 0 && S_ISLNK(sb.st_mode)) {
        target = rbs__link_target(path);
        if (target == NULL)
            return save_fail(message, message_size, RBS_E_IO, path,
                             "a loop of symbolic links (or out of memory)");
        path = target;
    }
    len = strlen(path);
    /* saving is not part of stepping: it may allocate */
    buf = (unsigned char *)malloc(n);
    tmp = (char *)malloc(len + 16);
    if (buf == NULL || tmp == NULL) {
        free(buf);
        free(tmp);
        st = save_fail(message, message_size, RBS_E_MEMORY, path, "out of memory");
        free(target);
        return st;
    }
    rbs_world_checkpoint_write(w, buf, n, NULL);
    snprintf(tmp, len + 16, "%s.tmp%ld", path, (long)getpid());
    fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) {
        st = RBS_E_IO;
        why = errno == ENOENT ? "its folder does not exist" : strerror(errno);
    } else {
        size_t at = 0;
        while (at < n) {
            ssize_t k = write(fd, buf + at, n - at);
            if (k < 0 && errno == EINTR)
                continue;
            if (k <= 0) {
                st = RBS_E_IO;
                why = k < 0 ? strerror(errno) : "no room to write";
                break;
            }
            at += (size_t)k;
        }
        if (st == RBS_OK && fsync(fd) != 0) {
            st = RBS_E_IO;
            why = strerror(errno);
        }
        if (close(fd) != 0 && st == RBS_OK) {
            st = RBS_E_IO;
            why = strerror(errno);
        }
        if (st == RBS_OK && rename(tmp, path) != 0) {
            st = RBS_E_IO;
            why = strerror(errno);
        }
        if (st != RBS_OK)
            unlink(tmp);
    }
    if (st != RBS_OK)
        (void)save_fail(message, message_size, st, path, why ? why : "cannot be written");
    free(buf);
    free(tmp);
    free(target);
    return st;
}

rbs_status rbs_world_save(const rbs_world *w, const char *path)
{
    return rbs_world_save_v2(w, path, NULL, 0);
}

rbs_status rbs_world_load(const char *path, rbs_world **out, char *message, size_t message_size)
{
    char msg[256] = "";
    FILE *f;
    unsigned char *buf = NULL;
    long n;
    rbs_status st;
    if (out)
        *out = NULL;
    if (path == NULL || out == NULL) {
        if (message && message_size > 0)
            snprintf(message, message_size, "%s is NULL", path == NULL ? "path" : "out");
        return RBS_E_INVALID;
    }
    f = fopen(path, "rb");
    if (f == NULL) {
        snprintf(msg, sizeof msg, "%s: cannot open: %s", path, strerror(errno));
        st = RBS_E_IO;
        goto done;
    }
    {
        /* A folder opens on Linux and seeks to a nonsense size. */
        struct stat sb;
        if (fstat(fileno(f), &sb) == 0 && S_ISDIR(sb.st_mode)) {
            fclose(f);
            snprintf(msg, sizeof msg, "%s: is a folder, not a checkpoint file",
                     path);
            st = RBS_E_IO;
            goto done;
        }
    }
    /* Read to the end without seeking, so a pipe or FIFO does as a file
     * (cat ck.bin | ... /dev/stdin); the buffer grows as bytes come, and
     * reading stops 64 KiB past the size the header gives (room to count
     * trailing bytes), or after a header that is not a checkpoint's:
     * /dev/zero would never end. */
    {
        size_t cap = 0, limit = SIZE_MAX;
        n = 0;
        for (;;) {
            size_t want, got;
            if ((size_t)n >= limit)
                break;
            if ((size_t)n == cap) {
                size_t grow = cap < 65536 ? 65536 : cap;
                unsigned char *more;
                if (cap > (size_t)LONG_MAX - grow ||
                    (more = (unsigned char *)realloc(buf, cap + grow)) == NULL) {
                    fclose(f);
                    snprintf(msg, sizeof msg, "%s: out of memory after %ld bytes", path, n);
                    st = RBS_E_MEMORY;
                    goto done;
                }
                buf = more;
                cap += grow;
            }
            want = cap - (size_t)n;
            if (limit - (size_t)n < want)
                want = limit - (size_t)n;
            got = fread(buf + n, 1, want, f);
            n += (long)got;
            if (limit == SIZE_MAX && (size_t)n >= sizeof(header)) {
                header h;
                const size_t body = sizeof h + sizeof(rbs_world_def) + sizeof(counters) +
                                    sizeof(uint64_t);
                memcpy(&h, buf, sizeof h);
                limit = memcmp(h.magic, ckpt_magic, sizeof h.magic) != 0 ||
                                h.arrays > (uint64_t)(SIZE_MAX - body - 65536)
                            ? (size_t)n /* (not one: ckpt_check says why) */
                            : body + (size_t)h.arrays + 65536;
            }
            if (got < want) {
                if (ferror(f)) {
                    int e = errno;
                    fclose(f);
                    snprintf(msg, sizeof msg, "%s: read error after %ld bytes: %s", path, n,
                             strerror(e));
                    st = RBS_E_IO;
                    goto done;
                }
                break; /* end of file */
            }
        }
    }
    fclose(f);
    {
        char inner[200] = "";
        st = create_from(buf, (size_t)n, out, inner, sizeof inner);
        if (st != RBS_OK)
            snprintf(msg, sizeof msg, "%s: %s", path, inner);
    }
done:
    free(buf);
    if (message && message_size > 0)
        snprintf(message, message_size, "%s", msg);
    return st;
}
