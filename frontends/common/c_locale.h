/*
 * c_locale.h - the front ends' numbers in the "C" locale, per thread.
 *
 * printf's %g and strtod follow the thread's LC_NUMERIC.  A program that
 * embeds a renderer class and calls setlocale(LC_ALL, "") under German
 * settings would otherwise get CSV rows with a field too many per number
 * ("-0,5"), invalid JSON ("position":[-0,5,0,0,028575]) and camera
 * commands that refuse "zoom 1.5".  A renderer's draw runs on the
 * projector's thread, which has the process's locale whatever the caller's
 * thread set, so each renderer switches its own thread at its entry points.
 *
 * The switch is uselocale, never setlocale (process-wide, not thread-safe):
 * other threads keep their locale and no state is global.
 * newlocale(..., "C", 0) hands back the C library's built-in "C" locale on
 * glibc and musl (nothing allocated, it cannot fail), so a switch is cheap;
 * were it to fail elsewhere, the thread's own locale stays in force.
 *
 * Header-only: the dumpers and the SDL renderer are separate static
 * libraries (the SDL one links nothing of rbsim), and the library's own
 * helper (lib/src/core/c_locale.c) is internal to it.
 */
#ifndef RBSF_C_LOCALE_H
#define RBSF_C_LOCALE_H

#include <locale.h>

/** A switch to the "C" locale on this thread (pairs nest). */
typedef struct rbsf__locale {
    locale_t c, old;
} rbsf__locale;

/** Switch this thread to the "C" locale until rbsf__c_locale_pop(l). */
static inline void rbsf__c_locale_push(rbsf__locale *l)
{
    l->c = newlocale(LC_NUMERIC_MASK, "C", (locale_t)0);
    l->old = l->c != (locale_t)0 ? uselocale(l->c) : (locale_t)0;
}

/** Give this thread back the locale it had at the matching push. */
static inline void rbsf__c_locale_pop(rbsf__locale *l)
{
    if (l->c != (locale_t)0) {
        uselocale(l->old);
        freelocale(l->c);
    }
}

#endif /* RBSF_C_LOCALE_H */
