/*
 * scene_text.c - the seed's text scene: config.txt with materials.txt and
 * objects.txt (see scenes/FORMAT.md, "Text format").
 *
 * The three files are turned into the same tree as a JSON scene, with the
 * file, line and column of every token recorded, and then checked by the one
 * validator; so both formats accept and reject exactly the same scenes.
 *
 * Lexical rules (all three files): '#' starts a comment when it begins a
 * token, unless it is a colour "#rrggbb"; tokens are separated by blanks and
 * commas; "double quotes" make one string token (escapes \" \\ \n \t \r).
 * A token is a number if it follows the JSON number grammar, true/false are
 * booleans, anything else is a string.
 */
#include "scene/scene_internal.h"
#include "core/world_internal.h" /* rbs__utf8_seq */

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h> /* access */

typedef struct tctx {
    rbs_scene *scene;
    rbs__posmap *map;
    rbs__src *srcs; /* indexed by file */
    int32_t file;   /* file being read */
    int failed;     /* out of memory */
    int stream;     /* config.txt came from a pipe, FIFO or device */
} tctx;

typedef struct ttok {
    size_t off, len; /* as written, quotes included */
    int quoted;
} ttok;

#define TOKS_MAX 64

static rbs__loc tloc(const tctx *t, size_t off)
{
    return rbs__src_loc(&t->srcs[t->file], t->file, off);
}

static void record(tctx *t, const cJSON *item, size_t value_off, size_t raw_len,
                   int has_key, size_t key_off)
{
    rbs__pos pos;
    memset(&pos, 0, sizeof pos);
    pos.item = item;
    pos.file = t->file;
    pos.value_off = (uint32_t)value_off;
    pos.raw_off = (uint32_t)value_off;
    pos.raw_len = (uint32_t)raw_len;
    pos.has_key = has_key;
    pos.key_off = (uint32_t)key_off;
    if (rbs__posmap_put(t->map, &pos) != 0) {
        t->failed = 1;
    }
}

static int is_blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

static int is_hex(char c)
{
    return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F');
}

/* '#' at s[i] begins a colour "#rrggbb" rather than a comment. */
static int is_color_at(const char *s, size_t i, size_t end)
{
    size_t k;
    if (i + 7 > end) {
        return 0;
    }
    for (k = 1; k <= 6; k++) {
        if (!is_hex(s[i + k])) {
            return 0;
        }
    }
    return i + 7 == end || is_blank(s[i + 7]) || s[i + 7] == ',';
}

/* After a key at s[i] (blanks skipped), a word that starts with '#' but is
 * no colour (so the tokenizer took it for a comment): "#d0303", "#red".  A
 * '#' followed by a blank or the line's end is a comment ("color # none"). */
static int bad_color_at(const char *s, size_t i, size_t end)
{
    while (i < end && is_blank(s[i])) {
        i++;
    }
    return i + 1 < end && s[i] == '#' && !is_blank(s[i + 1]) && !is_color_at(s, i, end);
}

/* Split [begin, end) into tokens; separators: blanks (and commas if commas).
 * Stops at a comment.  Returns the count, or -1 after reporting an error. */
static int tokenize(tctx *t, size_t begin, size_t end, int commas, ttok *toks,
                    int max)
{
    const char *s = t->srcs[t->file].text;
    size_t i = begin;
    int n = 0, open = 1; /* (open: no word since the start or the last comma) */
    while (i < end) {
        size_t start;
        if (commas && s[i] == ',') {
            if (open) {
                /* "1,,2" or ",1" was taken as two elements, silently */
                rbs__scene_error(t->scene, tloc(t, i), "",
                                 "element %d of a comma list is empty (%s): give its "
                                 "value or remove the comma",
                                 n + 1, n == 0 ? "a comma before the first value"
                                               : "nothing between two commas");
                return -1;
            }
            open = 1;
            i++;
            continue;
        }
        if (is_blank(s[i])) {
            i++;
            continue;
        }
        open = 0;
        if (s[i] == '#' && !is_color_at(s, i, end)) {
            break;
        }
        if (n == max) {
            rbs__scene_error(t->scene, tloc(t, i), "", "more than %d values on one line",
                             max);
            return -1;
        }
        start = i;
        if (s[i] == '"') {
            i++;
            while (i < end && s[i] != '"') {
                if (s[i] == '\\' && i + 1 < end) {
                    char e = s[i + 1];
                    if (e != '"' && e != '\\' && e != 'n' && e != 't' && e != 'r') {
                        rbs__scene_error(t->scene, tloc(t, i), "",
                                         "invalid escape \\%c in a quoted string; the "
                                         "escapes are \\\" \\\\ \\n \\t \\r",
                                         (unsigned char)e >= 0x21 && (unsigned char)e < 0x7f
                                             ? e
                                             : '?');
                        return -1;
                    }
                    i += 2;
                } else {
                    i++;
                }
            }
            if (i >= end) {
                rbs__scene_error(t->scene, tloc(t, start), "",
                                 "unterminated string: missing closing '\"'");
                return -1;
            }
            i++;
            toks[n].quoted = 1;
        } else {
            while (i < end && !is_blank(s[i]) && !(commas && s[i] == ',')) {
                i++;
            }
            toks[n].quoted = 0;
        }
        toks[n].off = start;
        toks[n].len = i - start;
        n++;
    }
    return n;
}

/* JSON number grammar, the whole token, of any length. */
static int number_grammar(const char *s, size_t n)
{
    size_t i = 0;
    if (i < n && s[i] == '-') {
        i++;
    }
    if (i >= n || s[i] < '0' || s[i] > '9') {
        return 0;
    }
    if (s[i] == '0') {
        i++;
    } else {
        while (i < n && s[i] >= '0' && s[i] <= '9') {
            i++;
        }
    }
    if (i < n && s[i] == '.') {
        i++;
        if (i >= n || s[i] < '0' || s[i] > '9') {
            return 0;
        }
        while (i < n && s[i] >= '0' && s[i] <= '9') {
            i++;
        }
    }
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        i++;
        if (i < n && (s[i] == '+' || s[i] == '-')) {
            i++;
        }
        if (i >= n || s[i] < '0' || s[i] > '9') {
            return 0;
        }
        while (i < n && s[i] >= '0' && s[i] <= '9') {
            i++;
        }
    }
    return i == n;
}

/* A number: JSON number grammar, the whole token, at most
 * RBS__SCENE_NUMBER_MAX characters. */
static int is_number(const char *s, size_t n)
{
    return n <= RBS__SCENE_NUMBER_MAX && number_grammar(s, n);
}

/* Decode a quoted token (quotes included) into a new string. */
static char *unquote(const char *s, size_t len)
{
    char *out = malloc(len + 1);
    size_t i, k = 0;
    if (out == NULL) {
        return NULL;
    }
    for (i = 1; i + 1 < len; i++) {
        char c = s[i];
        if (c == '\\' && i + 2 < len) {
            char e = s[++i];
            c = e == 'n' ? '\n' : e == 't' ? '\t' : e == 'r' ? '\r' : e;
        }
        out[k++] = c;
    }
    out[k] = '\0';
    return out;
}

/* A token as a tree value (recorded at its place). */
static cJSON *tok_value(tctx *t, const char *s, size_t off, size_t len, int quoted,
                        int has_key, size_t key_off)
{
    cJSON *item;
    const char *w = s + off;
    if (quoted) {
        char *str = unquote(w, len);
        item = str != NULL ? cJSON_CreateString(str) : NULL;
        free(str);
    } else if (len == 4 && memcmp(w, "true", 4) == 0) {
        item = cJSON_CreateTrue();
    } else if (len == 5 && memcmp(w, "false", 5) == 0) {
        item = cJSON_CreateFalse();
    } else if (len == 4 && memcmp(w, "null", 4) == 0) {
        item = cJSON_CreateNull();
    } else if (len == 2 && memcmp(w, "[]", 2) == 0) {
        item = cJSON_CreateArray();
    } else if (len == 2 && memcmp(w, "{}", 2) == 0) {
        item = cJSON_CreateObject();
    } else if (is_number(w, len)) {
        char buf[RBS__SCENE_NUMBER_MAX + 1];
        memcpy(buf, w, len);
        buf[len] = '\0';
        item = cJSON_CreateNumber(strtod(buf, NULL));
    } else if (number_grammar(w, len)) {
        /* (as the JSON reader says it; a string here was called "not a
         * number"): the error, and the number read, so that no other error
         * follows from it */
        char *buf = malloc(len + 1);
        rbs__scene_error(t->scene, tloc(t, off), "",
                         "number literal longer than %d characters (%lu)",
                         RBS__SCENE_NUMBER_MAX, (unsigned long)len);
        item = NULL;
        if (buf != NULL) {
            memcpy(buf, w, len);
            buf[len] = '\0';
            item = cJSON_CreateNumber(strtod(buf, NULL));
            free(buf);
        }
    } else {
        char *str = malloc(len + 1);
        if (str != NULL) {
            memcpy(str, w, len);
            str[len] = '\0';
        }
        item = str != NULL ? cJSON_CreateString(str) : NULL;
        free(str);
    }
    if (item == NULL) {
        t->failed = 1;
        return NULL;
    }
    record(t, item, off, len, has_key, key_off);
    return item;
}

/* Values of a "key value..." line: one token is a scalar, more an array. */
static cJSON *toks_value(tctx *t, const ttok *toks, int n, size_t key_off)
{
    const char *s = t->srcs[t->file].text;
    cJSON *arr;
    int k;
    if (n == 1) {
        return tok_value(t, s, toks[0].off, toks[0].len, toks[0].quoted, 1, key_off);
    }
    arr = cJSON_CreateArray();
    if (arr == NULL) {
        t->failed = 1;
        return NULL;
    }
    record(t, arr, toks[0].off, 0, 1, key_off);
    for (k = 0; k < n; k++) {
        cJSON *e = tok_value(t, s, toks[k].off, toks[k].len, toks[k].quoted, 0, 0);
        if (e == NULL) {
            cJSON_Delete(arr);
            return NULL;
        }
        cJSON_AddItemToArray(arr, e);
    }
    return arr;
}

/* Add item under key to obj (duplicates are kept: the validator names them). */
static void add(cJSON *obj, const char *key, cJSON *item)
{
    if (item != NULL) {
        cJSON_AddItemToObject(obj, key, item);
    }
}

/* ---- key=value lists (renderers, mutual_gravity) ------------------------ */

/* Walk a dotted key ("camera.position", "views[1].fov", "path[0].t") from obj,
 * creating objects/arrays, and add the value at the end.  The first
 * container it creates goes into *made (with its parent in *made_in), so a
 * key found bad part way can take back what it made. */
static int kv_walk(tctx *t, cJSON *obj, size_t key_off, size_t key_len, cJSON *value,
                   cJSON **made, cJSON **made_in)
{
    const char *s = t->srcs[t->file].text;
    size_t i = key_off, end = key_off + key_len, k;
    cJSON *cur = obj;
    int depth = 1; /* the renderer object itself */
    /* bound the nesting as the JSON parser does (cJSON frees recursively) */
    for (k = key_off; k < end; k++) {
        depth += s[k] == '.' || s[k] == '[';
    }
    if (depth >= RBS__SCENE_DEPTH_MAX) {
        rbs__scene_error(t->scene, tloc(t, key_off), "",
                         "key nests deeper than %d levels", RBS__SCENE_DEPTH_MAX);
        return -1;
    }
    for (;;) {
        size_t seg = i;
        char name[RBS_NAME_MAX];
        cJSON *next;
        while (i < end && s[i] != '.' && s[i] != '[') {
            i++;
        }
        if (i == seg || i - seg >= sizeof name) {
            rbs__scene_error(t->scene, tloc(t, seg), "",
                             "bad key \"%.*s\": expected names joined by '.' and [index]",
                             (int)key_len, s + key_off);
            return -1;
        }
        memcpy(name, s + seg, i - seg);
        name[i - seg] = '\0';
        if (i == end) {
            add(cur, name, value);
            return 0;
        }
        next = cJSON_GetObjectItemCaseSensitive(cur, name);
        if (s[i] == '.') {
            if (next == NULL) {
                next = cJSON_CreateObject();
                if (next == NULL) {
                    t->failed = 1;
                    return -1;
                }
                record(t, next, seg, 0, 1, seg);
                add(cur, name, next);
                if (*made == NULL) {
                    *made = next;
                    *made_in = cur;
                }
            } else if (!cJSON_IsObject(next)) {
                rbs__scene_error(t->scene, tloc(t, seg), "",
                                 cJSON_IsArray(next)
                                     ? "\"%s\" is an array (given by [index]) and cannot "
                                       "also have keys"
                                     : "\"%s\" was given a value and cannot also have keys",
                                 name);
                return -1;
            }
            cur = next;
            i++;
            continue;
        }
        /* name[index]... */
        if (next == NULL) {
            next = cJSON_CreateArray();
            if (next == NULL) {
                t->failed = 1;
                return -1;
            }
            record(t, next, seg, 0, 1, seg);
            add(cur, name, next);
            if (*made == NULL) {
                *made = next;
                *made_in = cur;
            }
        } else if (!cJSON_IsArray(next)) {
            rbs__scene_error(t->scene, tloc(t, seg), "",
                             cJSON_IsObject(next)
                                 ? "\"%s\" is an object (given by keys) and cannot also have "
                                   "[index]"
                                 : "\"%s\" was given a value and cannot also have [index]",
                             name);
            return -1;
        }
        for (;;) {
            size_t idx = 0, istart = ++i;
            int size = cJSON_GetArraySize(next);
            cJSON *elem;
            while (i < end && s[i] >= '0' && s[i] <= '9' && idx < 100000) {
                idx = idx * 10 + (size_t)(s[i] - '0');
                i++;
            }
            if (i == istart || i >= end || s[i] != ']') {
                rbs__scene_error(t->scene, tloc(t, istart), "",
                                 "bad index in key \"%.*s\": expected [number]",
                                 (int)key_len, s + key_off);
                return -1;
            }
            i++;
            if (idx > (size_t)size) {
                rbs__scene_error(t->scene, tloc(t, istart), "",
                                 "index [%lu] skips [%d]: give elements in order",
                                 (unsigned long)idx, size);
                return -1;
            }
            if (i == end) {
                if (idx < (size_t)size) {
                    rbs__scene_error(t->scene, tloc(t, istart), "",
                                     "element [%lu] is given twice", (unsigned long)idx);
                    return -1;
                }
                cJSON_AddItemToArray(next, value);
                return 0;
            }
            elem = cJSON_GetArrayItem(next, (int)idx);
            if (s[i] == '[') {
                if (elem == NULL) {
                    elem = cJSON_CreateArray();
                    if (elem == NULL) {
                        t->failed = 1;
                        return -1;
                    }
                    record(t, elem, seg, 0, 0, 0);
                    cJSON_AddItemToArray(next, elem);
                    if (*made == NULL) {
                        *made = elem;
                        *made_in = next;
                    }
                } else if (!cJSON_IsArray(elem)) {
                    rbs__scene_error(t->scene, tloc(t, istart), "",
                                     "element [%lu] is not an array", (unsigned long)idx);
                    return -1;
                }
                next = elem;
                continue;
            }
            if (s[i] != '.') {
                rbs__scene_error(t->scene, tloc(t, i), "",
                                 "bad key \"%.*s\": expected '.' or '[' after ']'",
                                 (int)key_len, s + key_off);
                return -1;
            }
            if (elem == NULL) {
                elem = cJSON_CreateObject();
                if (elem == NULL) {
                    t->failed = 1;
                    return -1;
                }
                record(t, elem, seg, 0, 0, 0);
                cJSON_AddItemToArray(next, elem);
                if (*made == NULL) {
                    *made = elem;
                    *made_in = next;
                }
            } else if (!cJSON_IsObject(elem)) {
                rbs__scene_error(t->scene, tloc(t, istart), "",
                                 "element [%lu] is not an object", (unsigned long)idx);
                return -1;
            }
            cur = elem;
            i++;
            break;
        }
    }
}

/* kv_walk; a bad key leaves nothing behind (a half-made "a" of "a..b=1" would
 * make the next key's error, or an unknown-key error, about it). */
static int kv_set(tctx *t, cJSON *obj, size_t key_off, size_t key_len, cJSON *value)
{
    cJSON *made = NULL, *made_in = NULL;
    if (kv_walk(t, obj, key_off, key_len, value, &made, &made_in) == 0) {
        return 0;
    }
    if (made != NULL) {
        cJSON_Delete(cJSON_DetachItemViaPointer(made_in, made));
    }
    return -1;
}

/* Skip a word from i: to the next blank outside quotes (or end). */
static size_t skip_word(const char *s, size_t i, size_t end)
{
    int inq = 0;
    while (i < end && (inq || !is_blank(s[i]))) {
        if (s[i] == '"') {
            inq = !inq;
        } else if (inq && s[i] == '\\' && i + 1 < end) {
            i++;
        }
        i++;
    }
    return i;
}

/* Parse "k=v k=v ..." in [i, end) into obj.  A value is one token or a
 * comma-separated list (an array); "..." quotes a string.  A bad word is
 * reported and skipped: each is reported, at its place. */
static void kv_list(tctx *t, size_t i, size_t end, cJSON *obj)
{
    const char *s = t->srcs[t->file].text;
    while (i < end) {
        size_t key_off, key_len;
        cJSON *value = NULL;
        ttok toks[TOKS_MAX];
        int n = 0;
        if (is_blank(s[i])) {
            i++;
            continue;
        }
        if (s[i] == '#' && !is_color_at(s, i, end)) {
            return;
        }
        key_off = i;
        while (i < end && s[i] != '=' && !is_blank(s[i])) {
            i++;
        }
        key_len = i - key_off;
        if (i >= end || s[i] != '=' || key_len == 0) {
            rbs__scene_error(t->scene, tloc(t, key_off), "",
                             "expected key=value, got \"%.*s\"", (int)(key_len ? key_len : 1),
                             s + key_off);
            i = skip_word(s, i, end);
            continue;
        }
        i++; /* '=' */
        /* the value runs to the next blank outside quotes */
        {
            size_t vstart = i, vend;
            int inq = 0, comma = 0;
            while (i < end && (inq || !is_blank(s[i]))) {
                if (s[i] == '"') {
                    inq = !inq;
                } else if (inq && s[i] == '\\' && i + 1 < end) {
                    i++;
                } else if (!inq && s[i] == ',') {
                    comma = 1;
                }
                i++;
            }
            vend = i;
            if (inq) {
                rbs__scene_error(t->scene, tloc(t, vstart), "",
                                 "unterminated string: missing closing '\"'");
                return;
            }
            if (vend == vstart) {
                rbs__scene_error(t->scene, tloc(t, key_off), "",
                                 "missing value after \"%.*s=\"", (int)key_len, s + key_off);
                continue;
            }
            n = tokenize(t, vstart, vend, 1, toks, TOKS_MAX);
            if (n < 0) {
                if (t->failed) {
                    return;
                }
                continue; /* (said by tokenize) */
            }
            if (n == 0) {
                rbs__scene_error(t->scene, tloc(t, vstart), "",
                                 "missing value after \"%.*s=\"", (int)key_len, s + key_off);
                continue;
            }
            if (comma) {
                /* a value with commas is an array of numbers (FORMAT.md):
                 * "a=1,b" was [1, "b"] */
                int k;
                for (k = 0; k < n; k++)
                    if (toks[k].quoted || !number_grammar(s + toks[k].off, toks[k].len))
                        break;
                if (k < n) {
                    rbs__scene_error(t->scene, tloc(t, toks[k].off), "",
                                     "\"%.*s\" in \"%.*s\" is not a number: a value with "
                                     "commas is an array of numbers (give other values by "
                                     "index, %.*s[%d]=...)",
                                     (int)toks[k].len, s + toks[k].off, (int)(vend - key_off),
                                     s + key_off, (int)key_len, s + key_off, k);
                    continue;
                }
            }
            if (n == 1 && !comma) {
                value = tok_value(t, s, toks[0].off, toks[0].len, toks[0].quoted, 1,
                                  key_off);
            } else {
                value = toks_value(t, toks, n, key_off);
                if (value != NULL && n == 1) {
                    /* "x=1," is a one-element array */
                    if (!cJSON_IsArray(value)) {
                        cJSON *arr = cJSON_CreateArray();
                        if (arr == NULL) {
                            cJSON_Delete(value);
                            t->failed = 1;
                            return;
                        }
                        record(t, arr, toks[0].off, 0, 1, key_off);
                        cJSON_AddItemToArray(arr, value);
                        record(t, value, toks[0].off, toks[0].len, 0, 0);
                        value = arr;
                    }
                }
            }
            if (value == NULL) {
                if (t->failed) {
                    return;
                }
                continue; /* (said where it was read) */
            }
        }
        if (kv_set(t, obj, key_off, key_len, value) != 0) {
            cJSON_Delete(value);
            if (t->failed) {
                return;
            }
        }
    }
}

/* ---- files -------------------------------------------------------------- */

/* Iterate over the lines of the current file: [*b, *e) without the newline. */
static int next_line(const tctx *t, size_t *pos, size_t *b, size_t *e)
{
    const rbs__src *src = &t->srcs[t->file];
    const char *nl;
    if (*pos >= src->len) {
        return 0;
    }
    if (*pos == 0 && src->len >= 3 && memcmp(src->text, "\xEF\xBB\xBF", 3) == 0) {
        *pos = 3; /* a UTF-8 byte order mark is skipped, as in JSON */
    }
    *b = *pos;
    nl = memchr(src->text + *pos, '\n', src->len - *pos);
    *e = nl != NULL ? (size_t)(nl - src->text) : src->len;
    *pos = nl != NULL ? *e + 1 : src->len;
    return 1;
}

/* A text file holds no NUL byte and is UTF-8 throughout (as a JSON scene
 * is), so that every name and string converts to JSON unchanged. */
static void check_binary(tctx *t)
{
    const rbs__src *src = &t->srcs[t->file];
    const char *z = memchr(src->text, '\0', src->len);
    const char *bom = rbs__utf16_bom(src->text, src->len);
    size_t i = 0;
    if (bom != NULL) {
        rbs__scene_error(t->scene, tloc(t, 0), "", RBS__UTF16_MESSAGE, bom);
        t->failed = 2;
        return;
    }
    if (z != NULL) {
        rbs__scene_error(t->scene, tloc(t, (size_t)(z - src->text)), "",
                         "NUL byte: this is not a text file");
        t->failed = 2;
        return;
    }
    while (i < src->len) {
        size_t n = rbs__utf8_seq(src->text, src->len, i);
        if (n == 0) {
            rbs__scene_error(t->scene, tloc(t, i), "",
                             "invalid UTF-8 (byte 0x%02x): scene files are UTF-8",
                             (unsigned)(unsigned char)src->text[i]);
            t->failed = 2;
            return;
        }
        i += n;
    }
    /* a line ends in "\n" or "\r\n": a carriage return alone (a file with
     * the old Mac line endings) would make the file one line */
    for (i = 0; i < src->len; i++) {
        /* (also the file's last byte: "steps = 1\r" at the end passed; a
         * probe of session 45) */
        if (src->text[i] == '\r' && (i + 1 >= src->len || src->text[i + 1] != '\n')) {
            rbs__scene_error(t->scene, tloc(t, i), "",
                             "a carriage return (\\r) not followed by a line feed: lines end "
                             "in \\n or \\r\\n (a file with carriage returns alone, old "
                             "Mac line endings, reads as one line; convert it, e.g. "
                             "tr '\\r' '\\n')");
            t->failed = 2;
            return;
        }
    }
}

static void load_materials(tctx *t, cJSON *mats)
{
    static const char *const cols[] = {"static", "kinetic", "restitution", "rolling",
                                       "spinning"};
    const char *s = t->srcs[t->file].text;
    size_t pos = 0, b, e;
    while (next_line(t, &pos, &b, &e) && !t->failed) {
        ttok toks[TOKS_MAX];
        int n = tokenize(t, b, e, 1, toks, TOKS_MAX), k;
        cJSON *row, *pair;
        if (n <= 0) {
            continue;
        }
        if (n < 4 || n > 7) {
            rbs__scene_error(t->scene, tloc(t, toks[0].off), "",
                             "expected 4 to 7 columns: material_a material_b static "
                             "kinetic [restitution [rolling [spinning]]], got %d",
                             n);
            continue;
        }
        row = cJSON_CreateObject();
        pair = cJSON_CreateArray();
        if (row == NULL || pair == NULL) {
            cJSON_Delete(row);
            cJSON_Delete(pair);
            t->failed = 1;
            return;
        }
        record(t, row, toks[0].off, 0, 0, 0);
        record(t, pair, toks[0].off, 0, 1, toks[0].off);
        add(row, "pair", pair);
        for (k = 0; k < 2; k++) {
            cJSON *nm = tok_value(t, s, toks[k].off, toks[k].len, toks[k].quoted, 0, 0);
            if (nm != NULL) {
                /* a name column is always a name, even if it looks like a number */
                if (!cJSON_IsString(nm)) {
                    char buf[RBS_NAME_MAX + 8];
                    size_t len = toks[k].len < sizeof buf - 1 ? toks[k].len
                                                              : sizeof buf - 1;
                    cJSON *str;
                    memcpy(buf, s + toks[k].off, len);
                    buf[len] = '\0';
                    str = cJSON_CreateString(buf);
                    cJSON_Delete(nm);
                    nm = str;
                    if (nm != NULL) {
                        record(t, nm, toks[k].off, toks[k].len, 0, 0);
                    }
                }
                if (nm != NULL) {
                    cJSON_AddItemToArray(pair, nm);
                }
            }
        }
        for (k = 2; k < n; k++) {
            /* "-" in the restitution column: the simulation's restitution */
            if (k == 4 && toks[k].len == 1 && s[toks[k].off] == '-' && !toks[k].quoted) {
                continue;
            }
            add(row, cols[k - 2],
                tok_value(t, s, toks[k].off, toks[k].len, toks[k].quoted, 1, toks[k].off));
        }
        cJSON_AddItemToArray(mats, row);
    }
}

static void load_objects(tctx *t, cJSON *bodies)
{
    const char *s = t->srcs[t->file].text;
    size_t pos = 0, b, e;
    cJSON *body = NULL;
    int complained = 0;
    while (next_line(t, &pos, &b, &e) && !t->failed) {
        ttok toks[TOKS_MAX];
        int n = tokenize(t, b, e, 1, toks, TOKS_MAX);
        char key[RBS_NAME_MAX];
        if (n <= 0) {
            continue;
        }
        if (!toks[0].quoted &&
            ((toks[0].len == 6 && memcmp(s + toks[0].off, "sphere", 6) == 0) ||
             (toks[0].len == 5 && memcmp(s + toks[0].off, "plane", 5) == 0))) {
            body = cJSON_CreateObject();
            if (body == NULL) {
                t->failed = 1;
                return;
            }
            record(t, body, toks[0].off, 0, 0, 0);
            cJSON_AddItemToArray(bodies, body);
            add(body, "type",
                tok_value(t, s, toks[0].off, toks[0].len, 0, 1, toks[0].off));
            if (n != 2) {
                rbs__scene_error(t->scene, tloc(t, toks[0].off), "",
                                 "expected \"%.*s NAME\" (one name, no blanks), got %d "
                                 "words",
                                 (int)toks[0].len, s + toks[0].off, n);
                continue;
            }
            {
                /* the name is always a string */
                size_t len = toks[1].len;
                char *nm = toks[1].quoted ? unquote(s + toks[1].off, len) : malloc(len + 1);
                cJSON *item;
                if (nm != NULL && !toks[1].quoted) {
                    memcpy(nm, s + toks[1].off, len);
                    nm[len] = '\0';
                }
                item = nm != NULL ? cJSON_CreateString(nm) : NULL;
                free(nm);
                if (item == NULL) {
                    t->failed = 1;
                    return;
                }
                record(t, item, toks[1].off, len, 1, toks[1].off);
                add(body, "name", item);
            }
            continue;
        }
        if (!toks[0].quoted && toks[0].len < sizeof key) {
            /* "cube c": a mistyped body line, not a key of the body before */
            static const char *const types[] = {"sphere", "plane"};
            const char *hint;
            memcpy(key, s + toks[0].off, toks[0].len);
            key[toks[0].len] = '\0';
            hint = rbs__suggest(key, types, 2);
            if (hint != NULL || (n == 2 && !rbs__body_key_near(key) &&
                                 !is_number(s + toks[1].off, toks[1].len))) {
                rbs__scene_error(t->scene, tloc(t, toks[0].off), "",
                                 "unknown body type \"%s\"%s%s%s; a body starts with "
                                 "\"sphere NAME\" or \"plane NAME\"",
                                 key, hint ? " (did you mean \"" : "", hint ? hint : "",
                                 hint ? "\"?)" : "");
                body = NULL;     /* its key lines are not checked */
                complained = 1;
                continue;
            }
        }
        if (body == NULL) {
            if (!complained) {
                rbs__scene_error(t->scene, tloc(t, toks[0].off), "",
                                 "expected \"sphere NAME\" or \"plane NAME\" to start a "
                                 "body, got \"%.*s\"",
                                 (int)(toks[0].len < 40 ? toks[0].len : 40),
                                 s + toks[0].off);
                complained = 1;
            }
            continue;
        }
        if (toks[0].quoted || toks[0].len >= sizeof key) {
            rbs__scene_error(t->scene, tloc(t, toks[0].off), "",
                             "expected a key such as \"radius\", got \"%.*s\"",
                             (int)(toks[0].len < 40 ? toks[0].len : 40), s + toks[0].off);
            continue;
        }
        memcpy(key, s + toks[0].off, toks[0].len);
        key[toks[0].len] = '\0';
        if (n == 1 && strcmp(key, "color") == 0 && bad_color_at(s, toks[0].off + toks[0].len, e)) {
            /* "color #d0303": a '#' word that is no colour began a comment */
            size_t at = toks[0].off + toks[0].len, w, k;
            char word[40], path[40];
            while (is_blank(s[at])) {
                at++;
            }
            /* the word as the validator echoes a string: quoted, '"' and '\\'
             * escaped, a control character or one beyond ASCII (a colour
             * has none) as '?' */
            for (w = at, k = 0; w < e && !is_blank(s[w]) && s[w] != ',' && k < 20; w++) {
                unsigned char c = (unsigned char)s[w];
                if (c >= 0x80 && c < 0xC0) {
                    continue; /* (the rest of a character beyond ASCII) */
                }
                if (c == '"' || c == '\\') {
                    word[k++] = '\\';
                }
                word[k++] = c < 0x20 || c >= 0x7f ? '?' : (char)c;
            }
            word[k] = '\0';
            snprintf(path, sizeof path, "bodies[%d].color", cJSON_GetArraySize(bodies) - 1);
            rbs__scene_error(t->scene, tloc(t, at), path,
                             "must be \"#rrggbb\" or three numbers in [0, 1], got \"%s\"%s: not "
                             "'#' and 6 hex digits, so it was read as a comment",
                             word, w < e && !is_blank(s[w]) && s[w] != ',' ? "..." : "");
            continue;
        }
        if (n == 1) {
            rbs__scene_error(t->scene, tloc(t, toks[0].off), "",
                             "missing value after \"%s\"", key);
            continue;
        }
        add(body, key, toks_value(t, toks + 1, n - 1, toks[0].off));
    }
}

/* Whether path names a descriptor rather than a file in a folder. */
static int is_descriptor(const char *path)
{
    return strcmp(path, "/dev/stdin") == 0 || strncmp(path, "/dev/fd/", 8) == 0 ||
           strncmp(path, "/proc/self/fd/", 14) == 0;
}

/* Resolve a file named in config.txt against config.txt's folder; for a
 * config.txt read from a descriptor (/dev/stdin, /dev/fd/N, /proc/self/fd/N:
 * "rbsim run -" reads /dev/stdin) against the current folder, where the
 * user's files are (it looked for "/dev/materials.txt": a probe of session
 * 46). */
static char *beside(const char *config, const char *name)
{
    const char *slash = strrchr(config, '/');
    size_t d = slash != NULL ? (size_t)(slash - config) + 1 : 0, n = strlen(name);
    char *out;
    if (name[0] == '/' || is_descriptor(config)) {
        d = 0;
    }
    out = malloc(d + n + 1);
    if (out != NULL) {
        memcpy(out, config, d);
        memcpy(out + d, name, n + 1);
    }
    return out;
}

static rbs_status load_sub(tctx *t, const char *config, const cJSON *name_item,
                           size_t line_off, char **texts, int which, cJSON *into)
{
    char *path;
    int32_t file;
    size_t len;
    rbs_status st;
    int relative;
    int32_t saved_file = t->file;
    if (!cJSON_IsString(name_item) || name_item->valuestring[0] == '\0') {
        rbs__scene_error(t->scene, tloc(t, line_off), "",
                         "expected a file name after \"%s =\"",
                         which == 1 ? "materials" : "objects");
        cJSON_Delete((cJSON *)name_item);
        return RBS_E_SCENE;
    }
    relative = name_item->valuestring[0] != '/';
    path = beside(config, name_item->valuestring);
    cJSON_Delete((cJSON *)name_item);
    if (path == NULL) {
        t->failed = 1;
        return RBS_E_MEMORY;
    }
    file = rbs__scene_add_file(t->scene, path);
    if (file < 0 || file != which) {
        free(path);
        if (file < 0) {
            t->failed = 1;
            return RBS_E_MEMORY;
        }
        return RBS_E_SCENE;
    }
    t->scene->file_read[file] = 1;
    st = rbs__read_file(t->scene, path, tloc(t, line_off), &texts[file], &len, NULL);
    if (st == RBS_E_IO && (t->stream || is_descriptor(config)) && relative &&
        access(path, F_OK) != 0) {
        /* A config given through a pipe works when its relative names lie
         * beside the pipe's own path (a FIFO in the scene's folder), or,
         * through /dev/stdin or /dev/fd/N, in the current folder: say why. */
        if (is_descriptor(config))
            rbs__scene_error(t->scene, tloc(t, line_off), "",
                             "'%s' is a descriptor: the file names in it are looked "
                             "for in the current folder; run from the scene's folder, "
                             "name the files by absolute paths, or load the config.txt "
                             "file itself",
                             config);
        else
            rbs__scene_error(t->scene, tloc(t, line_off), "",
                             "'%s' is a pipe or device: the file names in it are looked "
                             "for beside that path; name the files by absolute paths, or "
                             "load the config.txt file itself",
                             config);
    }
    free(path);
    if (st != RBS_OK) {
        return st;
    }
    if (rbs__src_init(&t->srcs[file], texts[file], len) != 0) {
        t->failed = 1;
        return RBS_E_MEMORY;
    }
    t->file = file;
    check_binary(t);
    if (t->failed != 2) {
        if (which == 1) {
            load_materials(t, into);
        } else {
            load_objects(t, into);
        }
    }
    if (t->failed == 2) {
        t->failed = 0;
    }
    t->file = saved_file;
    return RBS_OK;
}

rbs_status rbs__text_load(rbs_scene *scene, const char *path, char *text, size_t len,
                          int stream)
{
    rbs__src srcs[RBS__SCENE_FILES_MAX];
    char *texts[RBS__SCENE_FILES_MAX] = {NULL, NULL, NULL, NULL};
    rbs__posmap map;
    tctx t;
    cJSON *root = NULL, *sim, *mats, *bodies, *rends;
    cJSON *mat_name = NULL, *obj_name = NULL;
    size_t mat_off = 0, obj_off = 0, pos = 0, b, e;
    rbs__loc none = {0, 0, 0};
    rbs_status st = RBS_OK, st2;
    int32_t k;
    int config_unreadable, body_hinted = 0;
    memset(srcs, 0, sizeof srcs);
    memset(&map, 0, sizeof map);
    memset(&t, 0, sizeof t);
    t.scene = scene;
    t.map = &map;
    t.srcs = srcs;
    t.stream = stream;
    texts[0] = text;
    root = cJSON_CreateObject();
    sim = cJSON_CreateObject();
    mats = cJSON_CreateArray();
    bodies = cJSON_CreateArray();
    rends = cJSON_CreateArray();
    if (rbs__src_init(&srcs[0], texts[0], len) != 0 || rbs__posmap_init(&map, 1024) != 0 ||
        root == NULL || sim == NULL || mats == NULL || bodies == NULL || rends == NULL) {
        cJSON_Delete(root);
        cJSON_Delete(sim);
        cJSON_Delete(mats);
        cJSON_Delete(bodies);
        cJSON_Delete(rends);
        rbs__src_fini(&srcs[0]);
        rbs__posmap_fini(&map);
        free(texts[0]);
        rbs__scene_error(scene, none, "", "out of memory");
        return RBS_E_MEMORY;
    }
    record(&t, root, 0, 0, 0, 0);
    record(&t, sim, 0, 0, 1, 0);
    record(&t, mats, 0, 0, 1, 0);
    record(&t, bodies, 0, 0, 1, 0);
    record(&t, rends, 0, 0, 1, 0);
    add(root, "simulation", sim);
    check_binary(&t);
    config_unreadable = t.failed == 2; /* reported; the rest would only mislead */
    /* config.txt: "key = value" lines */
    while (t.failed == 0 && next_line(&t, &pos, &b, &e)) {
        const char *s = texts[0];
        size_t i = b, key_off, key_len, v;
        char key[RBS_NAME_MAX];
        ttok toks[TOKS_MAX];
        int n;
        while (i < e && is_blank(s[i])) {
            i++;
        }
        if (i == e || s[i] == '#') {
            continue;
        }
        key_off = i;
        while (i < e && !is_blank(s[i]) && s[i] != '=') {
            i++;
        }
        key_len = i - key_off;
        while (i < e && is_blank(s[i])) {
            i++;
        }
        if (i >= e || s[i] != '=') {
            /* A body line ("sphere NAME") says what the file seems to be: an
             * objects file given where its config.txt belongs (a probe of
             * session 46: "rbsim check pile/objects.txt" said only "expected
             * key = value" for every line). */
            int body = !body_hinted &&
                       ((key_len == 6 && strncmp(s + key_off, "sphere", 6) == 0) ||
                        (key_len == 5 && strncmp(s + key_off, "plane", 5) == 0));
            body_hinted |= body; /* (once) */
            rbs__scene_error(scene, tloc(&t, key_off), "",
                             "expected \"key = value\", got \"%.*s\"%s",
                             (int)((e - key_off) < 40 ? (e - key_off) : 40), s + key_off,
                             body ? " (a body line: this looks like an objects file; "
                                    "give the config.txt that names it)"
                                  : "");
            continue;
        }
        if (key_len == 0) {
            rbs__scene_error(scene, tloc(&t, key_off), "",
                             "missing key before '=': expected \"key = value\"");
            continue;
        }
        if (key_len >= sizeof key) {
            rbs__scene_error(scene, tloc(&t, key_off), "", "key too long");
            continue;
        }
        memcpy(key, s + key_off, key_len);
        key[key_len] = '\0';
        v = i + 1;
        while (v < e && is_blank(s[v])) {
            v++;
        }
        if (strcmp(key, "renderer") == 0) {
            ttok first;
            cJSON *r = cJSON_CreateObject();
            if (r == NULL) {
                t.failed = 1;
                break;
            }
            {
                /* the type is the first word */
                size_t w = v;
                int inq = 0;
                while (w < e && (inq || !is_blank(s[w]))) {
                    if (s[w] == '"') {
                        inq = !inq;
                    }
                    w++;
                }
                n = tokenize(&t, v, w, 0, &first, 1);
            }
            if (n <= 0) {
                if (n == 0) {
                    rbs__scene_error(scene, tloc(&t, key_off), "",
                                     "expected \"renderer = TYPE key=value ...\"");
                }
                cJSON_Delete(r);
                continue;
            }
            record(&t, r, first.off, 0, 0, 0);
            add(r, "type", tok_value(&t, s, first.off, first.len, first.quoted, 1,
                                     first.off));
            kv_list(&t, first.off + first.len, e, r);
            cJSON_AddItemToArray(rends, r);
            continue;
        }
        if (strcmp(key, "mutual_gravity") == 0 && v < e && memchr(s + v, '=', e - v)) {
            cJSON *g = cJSON_CreateObject();
            if (g == NULL) {
                t.failed = 1;
                break;
            }
            record(&t, g, v, 0, 1, key_off);
            kv_list(&t, v, e, g);
            add(sim, key, g);
            continue;
        }
        n = tokenize(&t, v, e, strcmp(key, "description") != 0, toks, TOKS_MAX);
        if (n < 0) {
            continue;
        }
        if (n == 0) {
            rbs__scene_error(scene, tloc(&t, key_off), "", "missing value after \"%s =\"",
                             key);
            continue;
        }
        if (strcmp(key, "description") == 0) {
            cJSON *d;
            if (n == 1 && toks[0].quoted) {
                d = tok_value(&t, s, toks[0].off, toks[0].len, 1, 1, key_off);
            } else {
                /* unquoted: the rest of the line, as written */
                size_t end = toks[n - 1].off + toks[n - 1].len;
                char *str = malloc(end - v + 1);
                d = NULL;
                if (str != NULL) {
                    memcpy(str, s + v, end - v);
                    str[end - v] = '\0';
                    d = cJSON_CreateString(str);
                    free(str);
                }
                if (d != NULL) {
                    record(&t, d, v, end - v, 1, key_off);
                } else {
                    t.failed = 1;
                }
            }
            add(root, "description", d);
        } else if (strcmp(key, "format") == 0) {
            add(root, "format", toks_value(&t, toks, n, key_off));
        } else if (strcmp(key, "materials") == 0 || strcmp(key, "objects") == 0) {
            cJSON **slot = key[0] == 'm' ? &mat_name : &obj_name;
            if (*slot != NULL) {
                rbs__scene_error(scene, tloc(&t, key_off), "",
                                 "\"%s\" is given twice", key);
                continue;
            }
            if (n > 1) {
                rbs__scene_error(scene, tloc(&t, toks[1].off), "",
                                 "extra word \"%.*s\" after the file name of \"%s\" (one "
                                 "name; quote a name with blanks or commas: %s = \"my "
                                 "file.txt\")",
                                 (int)(toks[1].len < 40 ? toks[1].len : 40), s + toks[1].off,
                                 key, key);
            }
            *slot = toks_value(&t, toks, 1, key_off);
            if (key[0] == 'm') {
                mat_off = toks[0].off;
            } else {
                obj_off = toks[0].off;
            }
        } else if (strncmp(key, "simulation", 10) == 0 && (key[10] == '\0' || key[10] == '.')) {
            /* (in the tree it would be simulation.simulation...: a repeated
             * prefix in the error, not the mistake) */
            if (key[10] == '.' && key[11] != '\0') {
                rbs__scene_error(scene, tloc(&t, key_off), key,
                                 "config.txt's keys have no \"simulation.\" prefix: write "
                                 "\"%s = ...\"",
                                 key + 11);
            } else {
                rbs__scene_error(scene, tloc(&t, key_off), key,
                                 "config.txt has no section \"simulation\": its keys are the "
                                 "simulation's, one a line (\"steps = 100\", \"dt = 0.001\")");
            }
        } else {
            add(sim, key, toks_value(&t, toks, n, key_off));
        }
    }
    add(root, "materials", mats);
    add(root, "bodies", bodies);
    add(root, "renderers", rends);
    /* the other two files, each as file 1 and 2 */
    if (t.failed == 0) {
        if (mat_name != NULL) {
            st2 = load_sub(&t, path, mat_name, mat_off, texts, 1, mats);
            mat_name = NULL;
            if (st2 != RBS_OK && st == RBS_OK) {
                st = st2;
            }
        } else if (rbs__scene_add_file(scene, "(no materials file)") != 1) {
            t.failed = 1;
        }
    }
    if (t.failed == 0) {
        if (obj_name != NULL) {
            st2 = load_sub(&t, path, obj_name, obj_off, texts, 2, bodies);
            obj_name = NULL;
            if (st2 != RBS_OK && st == RBS_OK) {
                st = st2;
            }
        } else {
            rbs__scene_error(scene, rbs__src_loc(&srcs[0], 0, 0), "",
                             "missing \"objects = FILE\" (the file of bodies)");
        }
    }
    cJSON_Delete(mat_name);
    cJSON_Delete(obj_name);
    if (t.failed == 1) {
        rbs__scene_error(scene, none, "", "out of memory");
        st = RBS_E_MEMORY;
    }
    if (st == RBS_OK && !config_unreadable) {
        rbs__scene_validate(scene, root, &map, srcs, scene->file_count);
    }
    cJSON_Delete(root);
    rbs__posmap_fini(&map);
    for (k = 0; k < RBS__SCENE_FILES_MAX; k++) {
        rbs__src_fini(&srcs[k]);
        free(texts[k]);
    }
    return st;
}
