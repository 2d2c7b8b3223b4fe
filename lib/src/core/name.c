/*
 * name.c - the one rule for body and material names (name.h), used by the
 * world's API and by the scene validator alike, and the display rule it
 * rests on (rbs_text_shown_len, rbsim.h), used by the scene errors and the
 * front ends.
 */
#include "core/name.h"

#include <stdio.h>
#include <string.h>

#include "core/world_internal.h" /* rbs__utf8_seq */
#include "rbsim/rbsim.h"         /* RBS_NAME_MAX */

/* The code point of the well-formed UTF-8 sequence at s and its length in
 * bytes (*len). */
static uint32_t code_point(const unsigned char *s, size_t *len)
{
    if (s[0] < 0x80) {
        *len = 1;
        return s[0];
    }
    if (s[0] < 0xE0) {
        *len = 2;
        return (uint32_t)(s[0] & 0x1F) << 6 | (uint32_t)(s[1] & 0x3F);
    }
    if (s[0] < 0xF0) {
        *len = 3;
        return (uint32_t)(s[0] & 0x0F) << 12 | (uint32_t)(s[1] & 0x3F) << 6 | (uint32_t)(s[2] & 0x3F);
    }
    *len = 4;
    return (uint32_t)(s[0] & 0x07) << 18 | (uint32_t)(s[1] & 0x3F) << 12 | (uint32_t)(s[2] & 0x3F) << 6 |
           (uint32_t)(s[3] & 0x3F);
}

/* What a code point beyond ASCII that a name may not hold, and a terminal
 * is not shown, is (static text; NULL: a name may hold it): C1 controls,
 * Unicode's spaces, line and paragraph separators, and the invisible
 * formatting characters (soft hyphen, zero-width ones, the bidirectional
 * marks, embeddings, overrides and isolates, which reorder the text around
 * them on a terminal: Boucher and Anderson, "Trojan Source", 2021), and the
 * byte order mark. */
static const char *unseen_kind(uint32_t u)
{
    if (u >= 0x80 && u <= 0x9F)
        return "a control character";
    if (u == 0x2028 || u == 0x2029)
        return "a line or paragraph separator";
    if (u == 0xA0 || u == 0x1680 || (u >= 0x2000 && u <= 0x200A) || u == 0x202F || u == 0x205F || u == 0x3000)
        return "a space";
    if (u == 0xAD || u == 0x34F || u == 0x61C || u == 0x180E || (u >= 0x200B && u <= 0x200F) ||
        (u >= 0x202A && u <= 0x202E) || (u >= 0x2060 && u <= 0x206F) || u == 0xFEFF ||
        (u >= 0xFFF9 && u <= 0xFFFB))
        return "an invisible formatting character";
    return NULL;
}

size_t rbs_text_shown_len(const char *text, size_t len, size_t *skip)
{
    const unsigned char c = len > 0 ? (unsigned char)text[0] : 0;
    size_t n, k;
    if (len == 0) {
        if (skip != NULL)
            *skip = 0;
        return 0;
    }
    n = c < 0x80 ? 1 : rbs__utf8_seq(text, len, 0);
    if (skip != NULL)
        *skip = n > 0 ? n : 1;
    if (n == 0 || c < 0x20 || c == 0x7f)
        return 0;
    return c < 0x80 || unseen_kind(code_point((const unsigned char *)text, &k)) == NULL ? n : 0;
}

rbs__name_kind rbs__name_check(const char *name, rbs__name_fault *fault)
{
    size_t n = strlen(name), i, len;
    memset(fault, 0, sizeof *fault);
    fault->length = n;
    if (n == 0 || n >= RBS_NAME_MAX)
        return fault->kind = RBS__NAME_LENGTH;
    for (i = 0; i < n; i += len) {
        unsigned char c = (unsigned char)name[i];
        fault->byte = i + 1;
        fault->code = c;
        if ((len = rbs__utf8_seq(name, n, i)) == 0)
            return fault->kind = RBS__NAME_UTF8;
        if (c <= 0x20 || c == 0x7f || c == '#' || c == '"' || c == '=' || c == ',') {
            fault->what = c == ' ' ? "a space" : c <= 0x20 || c == 0x7f ? "a control character" : NULL;
            return fault->kind = RBS__NAME_ASCII;
        }
        if (c >= 0x80) {
            size_t k;
            fault->code = code_point((const unsigned char *)name + i, &k);
            if ((fault->what = unseen_kind(fault->code)) != NULL)
                return fault->kind = RBS__NAME_UNSEEN;
        }
    }
    fault->byte = 0;
    fault->code = 0;
    return fault->kind = RBS__NAME_OK;
}

void rbs__name_fault_text(const rbs__name_fault *f, char *out, size_t n)
{
    unsigned long at = (unsigned long)f->byte;
    switch (f->kind) {
    case RBS__NAME_LENGTH:
        snprintf(out, n, "%lu bytes", (unsigned long)f->length);
        break;
    case RBS__NAME_UTF8:
        snprintf(out, n, "byte 0x%02x at byte %lu, which starts no UTF-8 sequence",
                 (unsigned)f->code, at);
        break;
    case RBS__NAME_ASCII:
        if (f->code == ' ')
            snprintf(out, n, "' ' (a space) at byte %lu", at);
        else if (f->what != NULL)
            snprintf(out, n, "0x%02X (%s) at byte %lu", (unsigned)f->code, f->what, at);
        else
            snprintf(out, n, "'%c' at byte %lu", (char)f->code, at);
        break;
    case RBS__NAME_UNSEEN:
        snprintf(out, n, "U+%04lX (%s) at byte %lu", (unsigned long)f->code, f->what, at);
        break;
    default:
        if (n > 0)
            out[0] = '\0';
        break;
    }
}
