/*
 * shown.h - a word from the command line or a typed command, made safe to
 * repeat in a message.
 *
 * The front ends repeat what they were given ("unknown option '--x'").
 * Written raw, a control character there (ESC starts a terminal command),
 * a C1 control (U+009B is a one-character ESC [), a bidirectional override
 * that reorders the rest of the line, or a stray byte of invalid UTF-8
 * would act on the terminal or garble it instead of being read.  Which
 * characters show as themselves is the library's rule, rbs_text_shown_len
 * (rbsim.h), which its scene errors and names follow too; each other
 * character, and each byte of invalid UTF-8, is shown as one '?'.
 */
#ifndef RBSF_SHOWN_H
#define RBSF_SHOWN_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "rbsim/rbsim.h" /* rbs_text_shown_len */

/** s as it may be shown, into buf (n > 4 bytes; buf may be s itself): each
 * character rbs_text_shown_len does not show and each byte of invalid UTF-8
 * as one '?'; cut with "..." if longer than buf holds.  Returns buf. */
static inline const char *rbsf__shown(const char *s, char *buf, size_t n)
{
    const unsigned char *in = (const unsigned char *)s;
    size_t k = 0, cut = 0; /* cut: the last character end with room for "..." */
    size_t left = strlen(s);
    while (left > 0) {
        size_t len, shown = rbs_text_shown_len((const char *)in, left, &len);
        size_t out = shown > 0 ? shown : 1;
        if (k + 4 <= n)
            cut = k;
        if (k + out + 1 > n) {
            memcpy(buf + cut, "...", 4);
            return buf;
        }
        if (shown == 0)
            buf[k] = '?';
        else
            memmove(buf + k, in, out); /* (buf may be s: never ahead of it) */
        k += out;
        in += len;
        left -= len;
    }
    buf[k] = '\0';
    return buf;
}

/** Write s[0 .. len) to f by the rules of rbsf__shown, whole (a sequence
 * cut off at len counts as invalid). */
static inline void rbsf__put_shown(FILE *f, const char *s, size_t len)
{
    size_t i = 0;
    while (i < len) {
        size_t skip, shown = rbs_text_shown_len(s + i, len - i, &skip);
        if (shown > 0)
            fwrite(s + i, 1, shown, f);
        else
            fputc('?', f);
        i += skip;
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
