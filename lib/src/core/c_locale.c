/*
 * c_locale.c - numbers as text in the "C" locale, per thread (see
 * c_locale.h for why).
 */
#include "core/c_locale.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>

void rbs__c_locale_push(rbs__locale *l)
{
    l->c = newlocale(LC_NUMERIC_MASK, "C", (locale_t)0);
    l->old = l->c != (locale_t)0 ? uselocale(l->c) : (locale_t)0;
}

void rbs__c_locale_pop(rbs__locale *l)
{
    if (l->c != (locale_t)0) {
        uselocale(l->old);
        freelocale(l->c);
    }
}

int rbs__vsnprintf_c(char *buf, size_t n, const char *fmt, va_list ap)
{
    rbs__locale l;
    int k;
    rbs__c_locale_push(&l);
    k = vsnprintf(buf, n, fmt, ap);
    rbs__c_locale_pop(&l);
    return k;
}

int rbs__snprintf_c(char *buf, size_t n, const char *fmt, ...)
{
    va_list ap;
    int k;
    va_start(ap, fmt);
    k = rbs__vsnprintf_c(buf, n, fmt, ap);
    va_end(ap);
    return k;
}

double rbs__strtod_c(const char *s, char **end)
{
    rbs__locale l;
    double x;
    int e;
    rbs__c_locale_push(&l);
    x = strtod(s, end);
    e = errno; /* strtod's ERANGE, for the caller */
    rbs__c_locale_pop(&l);
    errno = e;
    return x;
}

const char *rbs__shortest(char *buf, double x)
{
    rbs__locale l;
    int prec;
    rbs__c_locale_push(&l);
    for (prec = 1; prec < 17; ++prec) {
        snprintf(buf, 32, "%.*g", prec, x);
        if (strtod(buf, NULL) == x || x != x)
            break;
    }
    if (prec == 17)
        snprintf(buf, 32, "%.17g", x);
    rbs__c_locale_pop(&l);
    return buf;
}
