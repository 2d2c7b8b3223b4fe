/*
 * name.h - the one rule for body and material names (internal).
 *
 * The world's API (world.c) and the scene validator (scene_validate.c)
 * both check names with rbs__name_check, so a world built through the API
 * holds only names a scene file can hold too, and the other way round.
 */
#ifndef RBS_CORE_NAME_H
#define RBS_CORE_NAME_H

#include <stddef.h>
#include <stdint.h>

/* What is wrong with a name (RBS__NAME_OK: nothing). */
typedef enum rbs__name_kind {
    RBS__NAME_OK = 0,
    RBS__NAME_LENGTH = 1,  /* not 1 .. RBS_NAME_MAX - 1 bytes */
    RBS__NAME_UTF8 = 2,    /* a byte that starts no well-formed UTF-8 sequence */
    RBS__NAME_ASCII = 3,   /* a blank, an ASCII control, '#', '"', '=' or ',' */
    RBS__NAME_UNSEEN = 4   /* a code point beyond ASCII that rbs_text_shown_len does not show */
} rbs__name_kind;

/* The first fault of a name: its kind, where (byte, 1-based; for LENGTH the
 * name's length in bytes), and the character (the byte for UTF8 and ASCII,
 * the code point for UNSEEN, then `what` says what it is). */
typedef struct rbs__name_fault {
    rbs__name_kind kind;
    size_t byte;
    size_t length;
    uint32_t code;
    const char *what; /* static text ("a space", "an invisible formatting
                         character", ...), or NULL */
} rbs__name_fault;

/* Check name (NUL-terminated, not NULL) against the rule: 1 to
 * RBS_NAME_MAX - 1 bytes of well-formed UTF-8 (RFC 3629) without blanks or
 * controls (bytes 0x01-0x20 and 0x7F), '#', '"', '=' or ',' (so that it
 * fits the text scene format too), nor a code point beyond ASCII that
 * rbs_text_shown_len (rbsim.h) does not show.
 * (A material's "*", the scene files' "any material", is its callers'.)
 * Returns fault->kind; *fault is filled either way.  Pure: thread-safe. */
rbs__name_kind rbs__name_check(const char *name, rbs__name_fault *fault);

/* "' ' (a space) at byte 3", "U+200B (an invisible formatting character)
 * at byte 3", "70 bytes": the fault for a message, in out (n bytes,
 * NUL-terminated; "" for RBS__NAME_OK). */
void rbs__name_fault_text(const rbs__name_fault *fault, char *out, size_t n);

#endif /* RBS_CORE_NAME_H */
