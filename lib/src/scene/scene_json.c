/*
 * scene_json.c - JSON text to a cJSON tree plus the place of every value.
 *
 * cJSON keeps no positions, so a small scanner of our own first walks the raw
 * text in document order.  It checks the grammar strictly (RFC 8259: no
 * trailing text, no NaN, no raw control characters, paired surrogates),
 * limits nesting to RBS__SCENE_DEPTH_MAX before anything recurses deeply, and
 * records the byte offset of every value and key.  cJSON then builds the tree
 * from the same text; since it keeps members in document order, a pre-order
 * walk of the tree meets the items in the order the scanner saw them, which
 * maps every item to its offset.  No cJSON global state is read or set.
 */
#include "scene/scene_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct json_event {
    uint32_t off, len; /* token start and length (strings: with quotes) */
    int32_t is_key;
} json_event;

typedef struct json_scan {
    const char *s;
    size_t len, i;
    json_event *ev;
    size_t ev_count, ev_cap;
    int failed;  /* a syntax error was found */
    int nomem;
    size_t err_off;
    char err[160];
    char path[256];
    size_t path_len;
} json_scan;

static void scan_fail(json_scan *sc, size_t off, const char *msg)
{
    if (sc->failed) {
        return;
    }
    sc->failed = 1;
    sc->err_off = off;
    snprintf(sc->err, sizeof sc->err, "%s", msg);
}

static int scan_event(json_scan *sc, size_t off, size_t len, int is_key)
{
    if (sc->ev_count == sc->ev_cap) {
        size_t cap = sc->ev_cap ? sc->ev_cap * 2 : 256;
        json_event *ev = realloc(sc->ev, cap * sizeof *ev);
        if (ev == NULL) {
            sc->nomem = 1;
            scan_fail(sc, off, "out of memory");
            return -1;
        }
        sc->ev = ev;
        sc->ev_cap = cap;
    }
    sc->ev[sc->ev_count].off = (uint32_t)off;
    sc->ev[sc->ev_count].len = (uint32_t)len;
    sc->ev[sc->ev_count].is_key = is_key;
    sc->ev_count++;
    return 0;
}

static void skip_ws(json_scan *sc)
{
    while (sc->i < sc->len) {
        char c = sc->s[sc->i];
        if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
            sc->i++;
        } else {
            break;
        }
    }
}

/* Describe the character at i for a message: 'x', byte 0x.., or end. */
static void describe_char(const json_scan *sc, size_t i, char *out, size_t n)
{
    unsigned char c;
    if (i >= sc->len) {
        snprintf(out, n, "end of input");
        return;
    }
    c = (unsigned char)sc->s[i];
    if (c >= 0x21 && c < 0x7f) {
        snprintf(out, n, "'%c'", c);
    } else {
        snprintf(out, n, "byte 0x%02x", c);
    }
}

static void fail_expected(json_scan *sc, const char *what)
{
    char got[32], msg[160];
    describe_char(sc, sc->i, got, sizeof got);
    if (sc->i >= sc->len) {
        snprintf(msg, sizeof msg, "expected %s, got end of input (truncated JSON?)",
                 what);
    } else {
        snprintf(msg, sizeof msg, "expected %s, got %s", what, got);
    }
    scan_fail(sc, sc->i, msg);
}

static int hexval(char c)
{
    if (c >= '0' && c <= '9') {
        return c - '0';
    }
    if (c >= 'a' && c <= 'f') {
        return c - 'a' + 10;
    }
    if (c >= 'A' && c <= 'F') {
        return c - 'A' + 10;
    }
    return -1;
}

/* \uXXXX at sc->i (pointing at 'u'); returns the code unit or -1. */
static long scan_u4(json_scan *sc)
{
    long v = 0;
    int k;
    if (sc->i + 4 >= sc->len) {
        return -1;
    }
    for (k = 1; k <= 4; k++) {
        int h = hexval(sc->s[sc->i + (size_t)k]);
        if (h < 0) {
            return -1;
        }
        v = v * 16 + h;
    }
    return v;
}

static int scan_string(json_scan *sc, int is_key)
{
    size_t start = sc->i;
    sc->i++; /* opening quote */
    while (sc->i < sc->len) {
        unsigned char c = (unsigned char)sc->s[sc->i];
        if (c == '"') {
            sc->i++;
            return scan_event(sc, start, sc->i - start, is_key);
        }
        if (c < 0x20) {
            scan_fail(sc, sc->i, c == '\n' ? "unterminated string (newline inside "
                                             "a string)"
                                           : "control character inside a string "
                                             "(write it as an escape)");
            return -1;
        }
        if (c == '\\') {
            char e;
            if (sc->i + 1 >= sc->len) {
                break;
            }
            e = sc->s[sc->i + 1];
            if (e == 'u') {
                long u;
                sc->i++;
                u = scan_u4(sc);
                if (u < 0) {
                    scan_fail(sc, sc->i - 1, "invalid \\u escape: expected 4 hex digits");
                    return -1;
                }
                if (u == 0) {
                    scan_fail(sc, sc->i - 1, "\\u0000 is not allowed in strings");
                    return -1;
                }
                if (u >= 0xDC00 && u <= 0xDFFF) {
                    scan_fail(sc, sc->i - 1, "invalid \\u escape: unpaired low surrogate");
                    return -1;
                }
                sc->i += 5;
                if (u >= 0xD800 && u <= 0xDBFF) {
                    long lo;
                    if (sc->i + 1 >= sc->len || sc->s[sc->i] != '\\' ||
                        sc->s[sc->i + 1] != 'u') {
                        scan_fail(sc, sc->i - 6,
                                  "invalid \\u escape: unpaired high surrogate");
                        return -1;
                    }
                    sc->i++;
                    lo = scan_u4(sc);
                    if (lo < 0xDC00 || lo > 0xDFFF) {
                        scan_fail(sc, sc->i - 7,
                                  "invalid \\u escape: unpaired high surrogate");
                        return -1;
                    }
                    sc->i += 5;
                }
                continue;
            }
            if (strchr("\"\\/bfnrt", e) == NULL || e == '\0') {
                char msg[80];
                char got[32];
                describe_char(sc, sc->i + 1, got, sizeof got);
                snprintf(msg, sizeof msg, "invalid escape in string: \\ followed by %s",
                         got);
                scan_fail(sc, sc->i, msg);
                return -1;
            }
            sc->i += 2;
            continue;
        }
        sc->i++;
    }
    scan_fail(sc, start, "unterminated string (truncated JSON?)");
    return -1;
}

static int is_digit(char c) { return c >= '0' && c <= '9'; }

static int scan_number(json_scan *sc)
{
    size_t start = sc->i;
    const char *s = sc->s;
    if (sc->i < sc->len && s[sc->i] == '-') {
        sc->i++;
    }
    if (sc->i < sc->len && (s[sc->i] == 'I' || s[sc->i] == 'i' || s[sc->i] == 'N' ||
                            s[sc->i] == 'n')) {
        scan_fail(sc, start, "NaN and Infinity are not JSON numbers; numbers must "
                             "be finite");
        return -1;
    }
    if (sc->i >= sc->len || !is_digit(s[sc->i])) {
        fail_expected(sc, "a digit");
        return -1;
    }
    if (s[sc->i] == '0') {
        sc->i++;
        if (sc->i < sc->len && is_digit(s[sc->i])) {
            scan_fail(sc, start, "invalid number: leading zeros are not allowed");
            return -1;
        }
    } else {
        while (sc->i < sc->len && is_digit(s[sc->i])) {
            sc->i++;
        }
    }
    if (sc->i < sc->len && s[sc->i] == '.') {
        sc->i++;
        if (sc->i >= sc->len || !is_digit(s[sc->i])) {
            fail_expected(sc, "a digit after the decimal point");
            return -1;
        }
        while (sc->i < sc->len && is_digit(s[sc->i])) {
            sc->i++;
        }
    }
    if (sc->i < sc->len && (s[sc->i] == 'e' || s[sc->i] == 'E')) {
        sc->i++;
        if (sc->i < sc->len && (s[sc->i] == '+' || s[sc->i] == '-')) {
            sc->i++;
        }
        if (sc->i >= sc->len || !is_digit(s[sc->i])) {
            fail_expected(sc, "a digit in the exponent");
            return -1;
        }
        while (sc->i < sc->len && is_digit(s[sc->i])) {
            sc->i++;
        }
    }
    if (sc->i - start > RBS__SCENE_NUMBER_MAX) {
        scan_fail(sc, start, "number literal longer than 63 characters");
        return -1;
    }
    return scan_event(sc, start, sc->i - start, 0);
}

static int scan_literal(json_scan *sc, const char *word)
{
    size_t n = strlen(word);
    size_t start = sc->i;
    if (sc->len - sc->i < n || memcmp(sc->s + sc->i, word, n) != 0) {
        fail_expected(sc, "a value (object, array, string, number, true, false "
                          "or null)");
        return -1;
    }
    sc->i += n;
    return scan_event(sc, start, n, 0);
}

static void path_index(json_scan *sc, size_t *saved, unsigned long index)
{
    *saved = sc->path_len;
    if (sc->path_len < sizeof sc->path) {
        int k = snprintf(sc->path + sc->path_len, sizeof sc->path - sc->path_len,
                         "[%lu]", index);
        if (k > 0) {
            sc->path_len += (size_t)k;
            if (sc->path_len >= sizeof sc->path) {
                sc->path_len = sizeof sc->path - 1;
            }
        }
    }
}

static void path_key(json_scan *sc, size_t *saved, size_t key_off, size_t key_len)
{
    size_t k;
    *saved = sc->path_len;
    if (sc->path_len > 0 && sc->path_len + 1 < sizeof sc->path) {
        sc->path[sc->path_len++] = '.';
    }
    /* the raw key without quotes (escapes kept as written) */
    for (k = key_off + 1; k + 1 < key_off + key_len; k++) {
        if (sc->path_len + 1 >= sizeof sc->path) {
            break;
        }
        sc->path[sc->path_len++] = sc->s[k];
    }
    sc->path[sc->path_len] = '\0';
}

static void path_restore(json_scan *sc, size_t saved)
{
    sc->path_len = saved;
    sc->path[saved] = '\0';
}

static int scan_value(json_scan *sc, int depth);

static int scan_object(json_scan *sc, int depth)
{
    sc->i++; /* { */
    skip_ws(sc);
    if (sc->i < sc->len && sc->s[sc->i] == '}') {
        sc->i++;
        return 0;
    }
    for (;;) {
        size_t key_off, saved;
        skip_ws(sc);
        if (sc->i >= sc->len || sc->s[sc->i] != '"') {
            fail_expected(sc, "a string key in double quotes");
            return -1;
        }
        key_off = sc->i;
        if (scan_string(sc, 1) != 0) {
            return -1;
        }
        path_key(sc, &saved, key_off, sc->i - key_off);
        skip_ws(sc);
        if (sc->i >= sc->len || sc->s[sc->i] != ':') {
            fail_expected(sc, "':' after the key");
            return -1;
        }
        sc->i++;
        if (scan_value(sc, depth) != 0) {
            return -1;
        }
        path_restore(sc, saved);
        skip_ws(sc);
        if (sc->i < sc->len && sc->s[sc->i] == ',') {
            sc->i++;
            continue;
        }
        if (sc->i < sc->len && sc->s[sc->i] == '}') {
            sc->i++;
            return 0;
        }
        fail_expected(sc, "',' or '}' after an object member");
        return -1;
    }
}

static int scan_array(json_scan *sc, int depth)
{
    unsigned long index = 0;
    sc->i++; /* [ */
    skip_ws(sc);
    if (sc->i < sc->len && sc->s[sc->i] == ']') {
        sc->i++;
        return 0;
    }
    for (;;) {
        size_t saved;
        path_index(sc, &saved, index++);
        if (scan_value(sc, depth) != 0) {
            return -1;
        }
        path_restore(sc, saved);
        skip_ws(sc);
        if (sc->i < sc->len && sc->s[sc->i] == ',') {
            sc->i++;
            continue;
        }
        if (sc->i < sc->len && sc->s[sc->i] == ']') {
            sc->i++;
            return 0;
        }
        fail_expected(sc, "',' or ']' after an array element");
        return -1;
    }
}

static int scan_value(json_scan *sc, int depth)
{
    char c;
    skip_ws(sc);
    if (sc->i >= sc->len) {
        fail_expected(sc, "a value");
        return -1;
    }
    c = sc->s[sc->i];
    if (c == '{' || c == '[') {
        if (depth >= RBS__SCENE_DEPTH_MAX) {
            char msg[80];
            snprintf(msg, sizeof msg, "nesting deeper than %d levels",
                     RBS__SCENE_DEPTH_MAX);
            scan_fail(sc, sc->i, msg);
            return -1;
        }
        if (scan_event(sc, sc->i, 1, 0) != 0) {
            return -1;
        }
        return c == '{' ? scan_object(sc, depth + 1) : scan_array(sc, depth + 1);
    }
    if (c == '"') {
        return scan_string(sc, 0);
    }
    if (c == '-' || is_digit(c)) {
        return scan_number(sc);
    }
    if (c == 'N' || c == 'I') {
        scan_fail(sc, sc->i, "NaN and Infinity are not JSON numbers; numbers must "
                             "be finite");
        return -1;
    }
    if (c == 't') {
        return scan_literal(sc, "true");
    }
    if (c == 'f') {
        return scan_literal(sc, "false");
    }
    if (c == 'n') {
        return scan_literal(sc, "null");
    }
    if (c == '}' || c == ']') {
        fail_expected(sc, "a value (trailing comma?)");
        return -1;
    }
    fail_expected(sc, "a value (object, array, string, number, true, false or "
                      "null)");
    return -1;
}

/* Pre-order walk of the tree, taking one scanner event per value and key. */
typedef struct json_walk {
    const json_scan *sc;
    size_t next;
    rbs__posmap *map;
    int32_t file;
    int failed;
} json_walk;

static void walk_item(json_walk *w, const cJSON *item, const json_event *key)
{
    rbs__pos pos;
    const json_event *ev;
    const cJSON *child;
    if (w->failed) {
        return;
    }
    if (w->next >= w->sc->ev_count || w->sc->ev[w->next].is_key) {
        w->failed = 1;
        return;
    }
    ev = &w->sc->ev[w->next++];
    memset(&pos, 0, sizeof pos);
    pos.item = item;
    pos.file = w->file;
    pos.value_off = ev->off;
    pos.raw_off = ev->off;
    pos.raw_len = ev->len;
    if (key != NULL) {
        pos.key_off = key->off;
        pos.has_key = 1;
    }
    if (rbs__posmap_put(w->map, &pos) != 0) {
        w->failed = 1;
        return;
    }
    for (child = item->child; child != NULL; child = child->next) {
        const json_event *k = NULL;
        if (cJSON_IsObject(item)) {
            if (w->next >= w->sc->ev_count || !w->sc->ev[w->next].is_key) {
                w->failed = 1;
                return;
            }
            k = &w->sc->ev[w->next++];
        }
        walk_item(w, child, k);
    }
}

int rbs__json_parse(rbs_scene *scene, const rbs__src *src, int32_t file,
                    rbs__posmap *map, cJSON **tree)
{
    json_scan sc;
    const char *end = NULL;
    cJSON *root;
    json_walk w;
    *tree = NULL;
    memset(&sc, 0, sizeof sc);
    sc.s = src->text;
    sc.len = src->len;
    if (src->len > RBS__SCENE_FILE_MAX) {
        rbs__scene_error(scene, rbs__src_loc(src, file, 0), "",
                         "scene is larger than %lu bytes",
                         (unsigned long)RBS__SCENE_FILE_MAX);
        return -1;
    }
    /* a UTF-8 byte order mark is skipped, as cJSON does */
    if (sc.len >= 3 && memcmp(sc.s, "\xEF\xBB\xBF", 3) == 0) {
        sc.i = 3;
    }
    skip_ws(&sc);
    if (sc.i >= sc.len) {
        scan_fail(&sc, sc.i, "empty input: expected a JSON object");
    } else if (scan_value(&sc, 0) == 0) {
        skip_ws(&sc);
        if (sc.i < sc.len) {
            char got[32], msg[96];
            describe_char(&sc, sc.i, got, sizeof got);
            snprintf(msg, sizeof msg, "unexpected %s after the end of the JSON value",
                     got);
            scan_fail(&sc, sc.i, msg);
        }
    }
    if (sc.failed) {
        rbs__scene_error(scene, rbs__src_loc(src, file, sc.err_off), sc.path, "%s",
                         sc.err);
        free(sc.ev);
        return -1;
    }
    root = cJSON_ParseWithLengthOpts(src->text, src->len, &end, 0);
    if (root == NULL) {
        size_t off = end != NULL && end >= src->text && end <= src->text + src->len
                         ? (size_t)(end - src->text)
                         : 0;
        rbs__scene_error(scene, rbs__src_loc(src, file, off), "",
                         "malformed JSON (or out of memory)");
        free(sc.ev);
        return -1;
    }
    if (rbs__posmap_init(map, sc.ev_count) != 0) {
        rbs__scene_error(scene, rbs__src_loc(src, file, 0), "", "out of memory");
        cJSON_Delete(root);
        free(sc.ev);
        return -1;
    }
    w.sc = &sc;
    w.next = 0;
    w.map = map;
    w.file = file;
    w.failed = 0;
    walk_item(&w, root, NULL);
    if (w.failed || w.next != sc.ev_count) {
        rbs__scene_error(scene, rbs__src_loc(src, file, 0), "",
                         "internal error: positions do not match the parsed tree "
                         "(or out of memory)");
        cJSON_Delete(root);
        free(sc.ev);
        return -1;
    }
    free(sc.ev);
    *tree = root;
    return 0;
}
