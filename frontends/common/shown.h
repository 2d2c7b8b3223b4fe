/*
 * shown.h - a word from the command line or a typed command, made safe to
 * repeat in a message.
 *
 * The front ends repeat what they were given ("unknown option '--x'").
 * Written raw, a control character there (ESC starts a terminal command),
 * a C1 control (U+009B is a one-character ESC [), a bidirectional override
 * that reorders the rest of the line, or a stray byte of invalid UTF-8
 * would act on the terminal or garble it instead of being read.  The
 * library's scene errors and names follow the same rule (lib/src/core/text.c,
 * rbs__unseen_kind); that helper is internal to the library, so the front
 * ends keep this header-only copy of the characters that act on a terminal
 * (it leaves Unicode's spaces alone, which only look blank).
 */
#ifndef RBSF_SHOWN_H
#define RBSF_SHOWN_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

/** The length of the well-formed UTF-8 sequence at s (RFC 3629: no
 * overlong forms, surrogates or code points beyond U+10FFFF) and its code
 * point in *u, or 0 for a byte that does not start one. */
static inline size_t rbsf__utf8_at(const unsigned char *s, uint32_t *u)
{
    unsigned char c = s[0], lo = 0x80, hi = 0xBF;
    size_t n, k;
    if (c < 0x80) {
        *u = c;
        return 1;
    }
    if (c >= 0xC2 && c <= 0xDF) {
        n = 2;
    } else if (c >= 0xE0 && c <= 0xEF) {
        n = 3;
        lo = c == 0xE0 ? 0xA0 : 0x80;
        hi = c == 0xED ? 0x9F : 0xBF;
    } else if (c >= 0xF0 && c <= 0xF4) {
        n = 4;
        lo = c == 0xF0 ? 0x90 : 0x80;
        hi = c == 0xF4 ? 0x8F : 0xBF;
    } else {
        return 0;
    }
    *u = (uint32_t)(c & (0x7F >> n));
    for (k = 1; k < n; k++) {
        if (s[k] < (k == 1 ? lo : 0x80) || s[k] > (k == 1 ? hi : 0xBF))
            return 0; /* (a NUL ends the string here too) */
        *u = *u << 6 | (uint32_t)(s[k] & 0x3F);
    }
    return n;
}

/** Whether code point u acts on a terminal or hides in the text: ASCII's
 * controls and DEL, C1 controls, line and paragraph separators, and the
 * invisible formatting characters (zero-width ones, bidirectional marks,
 * embeddings, overrides and isolates, the byte order mark). */
static inline int rbsf__acts_on_terminal(uint32_t u)
{
    return u < 0x20 || (u >= 0x7F && u <= 0x9F) || u == 0x2028 || u == 0x2029 || u == 0xAD ||
           u == 0x34F || u == 0x61C || u == 0x180E || (u >= 0x200B && u <= 0x200F) ||
           (u >= 0x202A && u <= 0x202E) || (u >= 0x2060 && u <= 0x206F) || u == 0xFEFF ||
           (u >= 0xFFF9 && u <= 0xFFFB);
}

/** s as it may be shown, into buf (n > 4 bytes; buf may be s itself): each
 * character that acts on a terminal and each byte of invalid UTF-8 as one
 * '?'; cut with "..." if longer than buf holds.  Returns buf. */
static inline const char *rbsf__shown(const char *s, char *buf, size_t n)
{
    const unsigned char *in = (const unsigned char *)s;
    size_t k = 0, cut = 0; /* cut: the last character end with room for "..." */
    while (*in != '\0') {
        uint32_t u = 0;
        size_t len = rbsf__utf8_at(in, &u);
        size_t out = len == 0 || rbsf__acts_on_terminal(u) ? 1 : len;
        if (k + 4 <= n)
            cut = k;
        if (k + out + 1 > n) {
            memcpy(buf + cut, "...", 4);
            return buf;
        }
        if (out == 1 && (len != 1 || rbsf__acts_on_terminal(u)))
            buf[k] = '?';
        else
            memmove(buf + k, in, out); /* (buf may be s: never ahead of it) */
        k += out;
        in += len == 0 ? 1 : len;
    }
    buf[k] = '\0';
    return buf;
}

/** Write s[0 .. len) to f by the rules of rbsf__shown, whole (a sequence
 * cut off at len counts as invalid). */
static inline void rbsf__put_shown(FILE *f, const char *s, size_t len)
{
    const unsigned char *in = (const unsigned char *)s;
    size_t i = 0;
    while (i < len) {
        uint32_t u = 0;
        size_t n = rbsf__utf8_at(in + i, &u);
        if (n == 0 || i + n > len || rbsf__acts_on_terminal(u)) {
            fputc('?', f);
            i += n == 0 || i + n > len ? 1 : n;
        } else {
            fwrite(in + i, 1, n, f);
            i += n;
        }
    }
}

/** rbsf__put_shown of a whole string. */
static inline void rbsf__puts_shown(FILE *f, const char *s)
{
    rbsf__put_shown(f, s, strlen(s));
}

/** A message to f, printf-style, shown safely: its line breaks and tabs
 * kept, every other character that acts on a terminal (as in the paths it
 * names) and each byte of invalid UTF-8 as '?'; cut with "..." past 16 KiB
 * (four paths of PATH_MAX). */
#ifdef __GNUC__
__attribute__((format(printf, 2, 3)))
#endif
static inline void rbsf__tell(FILE *f, const char *fmt, ...)
{
    char text[16384];
    const char *s = text, *line;
    va_list ap;
    int n;
    va_start(ap, fmt);
    n = vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    if (n < 0)
        return;
    if ((size_t)n >= sizeof text)
        memcpy(text + sizeof text - 5, "...\n", 5);
    while (*s != '\0') {
        size_t len = strcspn(s, "\n\t");
        line = s;
        rbsf__put_shown(f, line, len);
        s += len;
        if (*s != '\0')
            fputc(*s++, f);
    }
}

#endif
