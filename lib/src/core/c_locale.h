/*
 * c_locale.h - numbers as text in the "C" locale (internal).
 *
 * printf's %g and %f and strtod follow the thread's LC_NUMERIC.  A program
 * that embeds the library and calls setlocale(LC_ALL, "") under German
 * settings would otherwise get messages reading "got (0,5, 1,5, 0) m/s",
 * rbs_world_explain's "dt = 0,001 s", and the projector's "speed 0.5"
 * refused while "speed 0,5" was taken.  So every number the library writes
 * or reads as text goes through these functions, or runs between
 * rbs__c_locale_push and rbs__c_locale_pop (the scene module does so for a
 * whole load or save).
 *
 * The switch is per thread (uselocale), never setlocale: the caller's other
 * threads and its own formatting keep their locale, and nothing is global.
 * newlocale(..., "C", 0) hands back the C library's built-in "C" locale on
 * glibc and musl (nothing allocated, it cannot fail), so a switch is two
 * uselocale calls and is cheap; were it to fail elsewhere, the thread's own
 * locale stays in force.
 */
#ifndef RBS_CORE_C_LOCALE_H
#define RBS_CORE_C_LOCALE_H

#include <locale.h>
#include <stdarg.h>
#include <stddef.h>

/** A switch to the "C" locale on this thread, undone by rbs__c_locale_pop
 * (pairs nest). */
typedef struct rbs__locale {
    locale_t c, old;
} rbs__locale;
void rbs__c_locale_push(rbs__locale *l);
void rbs__c_locale_pop(rbs__locale *l);

/** snprintf and vsnprintf in the "C" locale. */
int rbs__snprintf_c(char *buf, size_t n, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
int rbs__vsnprintf_c(char *buf, size_t n, const char *fmt, va_list ap)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 0)))
#endif
    ;

/** strtod in the "C" locale. */
double rbs__strtod_c(const char *s, char **end);

/** x for a message, in its shortest form that reads back as the same double
 * (0.1, not 0.10000000000000001; 1.0000001, not %g's 1), in the "C" locale,
 * in buf (32 bytes or more); returns buf. */
const char *rbs__shortest(char *buf, double x);

#endif
