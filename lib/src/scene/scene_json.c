/*
 * scene_json.c - JSON text to a cJSON tree plus the place of every value.
 *
 * cJSON keeps no positions, and its parser writes a global error variable on
 * every call (a data race when two threads load scenes).  So the text is read
 * by a small recursive-descent parser of our own, which checks the grammar
 * strictly (RFC 8259: no trailing text, no NaN, no raw control characters,
 * paired surrogates, well-formed UTF-8 in strings), limits nesting to
 * RBS__SCENE_DEPTH_MAX before it recurses deeply, builds the cJSON tree with cJSON's constructors (which
 * touch no global state), and records the byte offset of every value and key
 * in the position map as it goes.  Numbers are converted by strtod under the
 * "C" locale (set per thread by the callers, see rbs__c_locale_push).
 */
#include "scene/scene_internal.h"
#include "core/world_internal.h" /* rbs__utf8_seq */

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct json_scan {
    const char *s;
    size_t len, i;
    rbs__posmap *map; /* NULL: no positions */
    int32_t file;
    int failed; /* a syntax error was found (or memory ran out) */
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

/* Record where an item came from. */
static int scan_record(json_scan *sc, const cJSON *item, size_t off, size_t len,
                       int has_key, size_t key_off)
{
    rbs__pos pos;
    if (sc->map == NULL) {
        return 0;
    }
    memset(&pos, 0, sizeof pos);
    pos.item = item;
    pos.file = sc->file;
    pos.value_off = (uint32_t)off;
    pos.raw_off = (uint32_t)off;
    pos.raw_len = (uint32_t)len;
    pos.has_key = has_key;
    pos.key_off = (uint32_t)key_off;
    if (rbs__posmap_put(sc->map, &pos) != 0) {
        scan_fail(sc, off, "out of memory");
        return -1;
    }
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

/* Append code point u as UTF-8. */
static size_t put_utf8(char *out, unsigned long u)
{
    if (u < 0x80) {
        out[0] = (char)u;
        return 1;
    }
    if (u < 0x800) {
        out[0] = (char)(0xC0 | (u >> 6));
        out[1] = (char)(0x80 | (u & 0x3F));
        return 2;
    }
    if (u < 0x10000) {
        out[0] = (char)(0xE0 | (u >> 12));
        out[1] = (char)(0x80 | ((u >> 6) & 0x3F));
        out[2] = (char)(0x80 | (u & 0x3F));
        return 3;
    }
    out[0] = (char)(0xF0 | (u >> 18));
    out[1] = (char)(0x80 | ((u >> 12) & 0x3F));
    out[2] = (char)(0x80 | ((u >> 6) & 0x3F));
    out[3] = (char)(0x80 | (u & 0x3F));
    return 4;
}

/* A string token at sc->i (the opening quote), decoded into a new buffer
 * (*out, NUL-terminated; never longer than the token). */
static int scan_string(json_scan *sc, char **out)
{
    size_t start = sc->i, k = 0, j = start + 1;
    char *buf;
    *out = NULL;
    /* the decoded text is never longer than the raw token */
    while (j < sc->len && sc->s[j] != '"') {
        j += sc->s[j] == '\\' ? 2 : 1;
    }
    buf = malloc((j < sc->len ? j : sc->len) - start + 1);
    if (buf == NULL) {
        scan_fail(sc, start, "out of memory");
        return -1;
    }
    sc->i++; /* opening quote */
    while (sc->i < sc->len) {
        unsigned char c = (unsigned char)sc->s[sc->i];
        if (c == '"') {
            sc->i++;
            buf[k] = '\0';
            *out = buf;
            return 0;
        }
        if (c < 0x20) {
            scan_fail(sc, sc->i, c == '\n' ? "unterminated string (newline inside "
                                             "a string)"
                                           : "control character inside a string "
                                             "(write it as an escape)");
            free(buf);
            return -1;
        }
        if (c == '\\') {
            char e;
            if (sc->i + 1 >= sc->len) {
                break;
            }
            e = sc->s[sc->i + 1];
            if (e == 'u') {
                long u, lo;
                sc->i++;
                u = scan_u4(sc);
                if (u < 0) {
                    scan_fail(sc, sc->i - 1, "invalid \\u escape: expected 4 hex digits");
                    free(buf);
                    return -1;
                }
                if (u == 0) {
                    scan_fail(sc, sc->i - 1, "\\u0000 is not allowed in strings");
                    free(buf);
                    return -1;
                }
                if (u >= 0xDC00 && u <= 0xDFFF) {
                    scan_fail(sc, sc->i - 1, "invalid \\u escape: unpaired low surrogate");
                    free(buf);
                    return -1;
                }
                sc->i += 5;
                if (u >= 0xD800 && u <= 0xDBFF) {
                    if (sc->i + 1 >= sc->len || sc->s[sc->i] != '\\' ||
                        sc->s[sc->i + 1] != 'u') {
                        scan_fail(sc, sc->i - 6,
                                  "invalid \\u escape: unpaired high surrogate");
                        free(buf);
                        return -1;
                    }
                    sc->i++;
                    lo = scan_u4(sc);
                    if (lo < 0xDC00 || lo > 0xDFFF) {
                        scan_fail(sc, sc->i - 7,
                                  "invalid \\u escape: unpaired high surrogate");
                        free(buf);
                        return -1;
                    }
                    sc->i += 5;
                    u = 0x10000 + ((u - 0xD800) << 10) + (lo - 0xDC00);
                }
                k += put_utf8(buf + k, (unsigned long)u);
                continue;
            }
            switch (e) {
            case '"': buf[k++] = '"'; break;
            case '\\': buf[k++] = '\\'; break;
            case '/': buf[k++] = '/'; break;
            case 'b': buf[k++] = '\b'; break;
            case 'f': buf[k++] = '\f'; break;
            case 'n': buf[k++] = '\n'; break;
            case 'r': buf[k++] = '\r'; break;
            case 't': buf[k++] = '\t'; break;
            default: {
                char msg[80];
                char got[32];
                describe_char(sc, sc->i + 1, got, sizeof got);
                snprintf(msg, sizeof msg, "invalid escape in string: \\ followed by %s",
                         got);
                scan_fail(sc, sc->i, msg);
                free(buf);
                return -1;
            }
            }
            sc->i += 2;
            continue;
        }
        if (c >= 0x80) {
            /* RFC 8259: the text is UTF-8; copy a whole sequence */
            size_t n = rbs__utf8_seq(sc->s, sc->len, sc->i);
            if (n == 0) {
                char msg[80];
                snprintf(msg, sizeof msg, "invalid UTF-8 in a string (byte 0x%02x)", c);
                scan_fail(sc, sc->i, msg);
                free(buf);
                return -1;
            }
            memcpy(buf + k, sc->s + sc->i, n);
            k += n;
            sc->i += n;
            continue;
        }
        buf[k++] = (char)c;
        sc->i++;
    }
    scan_fail(sc, start, "unterminated string (truncated JSON?)");
    free(buf);
    return -1;
}

static int is_digit(char c) { return c >= '0' && c <= '9'; }

/* A number token; *value gets strtod's reading (inf on overflow: the
 * validator reports it with the raw text). */
static int scan_number(json_scan *sc, double *value)
{
    size_t start = sc->i;
    const char *s = sc->s;
    char buf[RBS__SCENE_NUMBER_MAX + 1];
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
    memcpy(buf, s + start, sc->i - start);
    buf[sc->i - start] = '\0';
    *value = strtod(buf, NULL);
    return 0;
}

static int scan_literal(json_scan *sc, const char *word)
{
    size_t n = strlen(word);
    if (sc->len - sc->i < n || memcmp(sc->s + sc->i, word, n) != 0) {
        fail_expected(sc, "a value (object, array, string, number, true, false "
                          "or null)");
        return -1;
    }
    sc->i += n;
    return 0;
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

static void path_key(json_scan *sc, size_t *saved, const char *key)
{
    *saved = sc->path_len;
    if (sc->path_len > 0 && sc->path_len + 1 < sizeof sc->path) {
        sc->path[sc->path_len++] = '.';
    }
    for (; *key != '\0' && sc->path_len + 1 < sizeof sc->path; key++) {
        sc->path[sc->path_len++] = *key;
    }
    sc->path[sc->path_len] = '\0';
}

static void path_restore(json_scan *sc, size_t saved)
{
    sc->path_len = saved;
    sc->path[saved] = '\0';
}

static cJSON *scan_value(json_scan *sc, int depth, int has_key, size_t key_off);

/* Attach item to parent (array if key is NULL); on failure frees item. */
static int attach(json_scan *sc, cJSON *parent, const char *key, cJSON *item)
{
    if (key != NULL ? !cJSON_AddItemToObject(parent, key, item)
                    : !cJSON_AddItemToArray(parent, item)) {
        cJSON_Delete(item);
        scan_fail(sc, sc->i, "out of memory");
        return -1;
    }
    return 0;
}

static int scan_object(json_scan *sc, int depth, cJSON *obj)
{
    sc->i++; /* { */
    skip_ws(sc);
    if (sc->i < sc->len && sc->s[sc->i] == '}') {
        sc->i++;
        return 0;
    }
    for (;;) {
        size_t key_off, saved;
        char *key;
        cJSON *item;
        skip_ws(sc);
        if (sc->i >= sc->len || sc->s[sc->i] != '"') {
            fail_expected(sc, "a string key in double quotes");
            return -1;
        }
        key_off = sc->i;
        if (scan_string(sc, &key) != 0) {
            return -1;
        }
        path_key(sc, &saved, key);
        skip_ws(sc);
        if (sc->i >= sc->len || sc->s[sc->i] != ':') {
            fail_expected(sc, "':' after the key");
            free(key);
            return -1;
        }
        sc->i++;
        item = scan_value(sc, depth, 1, key_off);
        if (item == NULL || attach(sc, obj, key, item) != 0) {
            free(key);
            return -1;
        }
        free(key);
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

static int scan_array(json_scan *sc, int depth, cJSON *arr)
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
        cJSON *item;
        path_index(sc, &saved, index++);
        item = scan_value(sc, depth, 0, 0);
        if (item == NULL || attach(sc, arr, NULL, item) != 0) {
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

/* One value at sc->i: a new item (recorded), or NULL after scan_fail. */
static cJSON *scan_value(json_scan *sc, int depth, int has_key, size_t key_off)
{
    char c;
    size_t start;
    cJSON *item = NULL;
    skip_ws(sc);
    if (sc->i >= sc->len) {
        fail_expected(sc, "a value");
        return NULL;
    }
    start = sc->i;
    c = sc->s[sc->i];
    if (c == '{' || c == '[') {
        int r;
        if (depth >= RBS__SCENE_DEPTH_MAX) {
            char msg[80];
            snprintf(msg, sizeof msg, "nesting deeper than %d levels",
                     RBS__SCENE_DEPTH_MAX);
            scan_fail(sc, sc->i, msg);
            return NULL;
        }
        item = c == '{' ? cJSON_CreateObject() : cJSON_CreateArray();
        if (item == NULL) {
            scan_fail(sc, start, "out of memory");
            return NULL;
        }
        if (scan_record(sc, item, start, 1, has_key, key_off) != 0) {
            cJSON_Delete(item);
            return NULL;
        }
        r = c == '{' ? scan_object(sc, depth + 1, item) : scan_array(sc, depth + 1, item);
        if (r != 0) {
            cJSON_Delete(item);
            return NULL;
        }
        return item;
    }
    if (c == '"') {
        char *str;
        if (scan_string(sc, &str) != 0) {
            return NULL;
        }
        item = cJSON_CreateString(str);
        free(str);
    } else if (c == '-' || is_digit(c)) {
        double x;
        if (scan_number(sc, &x) != 0) {
            return NULL;
        }
        item = cJSON_CreateNumber(x);
    } else if (c == 'N' || c == 'I') {
        scan_fail(sc, sc->i, "NaN and Infinity are not JSON numbers; numbers must "
                             "be finite");
        return NULL;
    } else if (c == 't' || c == 'f' || c == 'n') {
        const char *word = c == 't' ? "true" : c == 'f' ? "false" : "null";
        if (scan_literal(sc, word) != 0) {
            return NULL;
        }
        item = c == 't' ? cJSON_CreateTrue() : c == 'f' ? cJSON_CreateFalse()
                                                        : cJSON_CreateNull();
    } else if (c == '}' || c == ']') {
        fail_expected(sc, "a value (trailing comma?)");
        return NULL;
    } else {
        fail_expected(sc, "a value (object, array, string, number, true, false or "
                          "null)");
        return NULL;
    }
    if (item == NULL) {
        scan_fail(sc, start, "out of memory");
        return NULL;
    }
    if (scan_record(sc, item, start, sc->i - start, has_key, key_off) != 0) {
        cJSON_Delete(item);
        return NULL;
    }
    return item;
}

/* Parse a whole text; NULL after scan_fail. */
static cJSON *scan_document(json_scan *sc)
{
    cJSON *root;
    const char *bom = rbs__utf16_bom(sc->s, sc->len);
    if (bom != NULL) {
        char msg[160];
        snprintf(msg, sizeof msg, RBS__UTF16_MESSAGE, bom);
        scan_fail(sc, 0, msg);
        return NULL;
    }
    /* a UTF-8 byte order mark is skipped */
    if (sc->len >= 3 && memcmp(sc->s, "\xEF\xBB\xBF", 3) == 0) {
        sc->i = 3;
    }
    skip_ws(sc);
    if (sc->i >= sc->len) {
        scan_fail(sc, sc->i, "empty input: expected a JSON object");
        return NULL;
    }
    root = scan_value(sc, 0, 0, 0);
    if (root == NULL) {
        return NULL;
    }
    skip_ws(sc);
    if (sc->i < sc->len) {
        char got[32], msg[96];
        describe_char(sc, sc->i, got, sizeof got);
        snprintf(msg, sizeof msg, "unexpected %s after the end of the JSON value", got);
        scan_fail(sc, sc->i, msg);
        cJSON_Delete(root);
        return NULL;
    }
    return root;
}

int rbs__json_parse(rbs_scene *scene, const rbs__src *src, int32_t file,
                    rbs__posmap *map, cJSON **tree)
{
    json_scan sc;
    *tree = NULL;
    memset(&sc, 0, sizeof sc);
    sc.s = src->text;
    sc.len = src->len;
    sc.map = map;
    sc.file = file;
    if (src->len > RBS__SCENE_FILE_MAX) {
        rbs__scene_error(scene, rbs__src_loc(src, file, 0), "",
                         "scene is larger than %lu bytes",
                         (unsigned long)RBS__SCENE_FILE_MAX);
        return -1;
    }
    if (rbs__posmap_init(map, src->len / 8 + 16) != 0) {
        rbs__scene_error(scene, rbs__src_loc(src, file, 0), "", "out of memory");
        return -1;
    }
    *tree = scan_document(&sc);
    if (*tree == NULL) {
        rbs__scene_error(scene, rbs__src_loc(src, file, sc.err_off), sc.path, "%s",
                         sc.err);
        return -1;
    }
    return 0;
}

cJSON *rbs__json_tree(const char *text, size_t len)
{
    json_scan sc;
    memset(&sc, 0, sizeof sc);
    sc.s = text;
    sc.len = len;
    return scan_document(&sc);
}
