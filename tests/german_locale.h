/*
 * german_locale.h - a locale with a decimal comma for the tests that check
 * that numbers stay in the "C" locale whatever the caller's (a program that
 * calls setlocale(LC_ALL, "") under German settings prints 0.5 as "0,5").
 *
 * Debian 12 ships no compiled German locale, so the test makes one at run
 * time with localedef (libc-bin) from the de_DE source and the UTF-8
 * charmap of Debian's "locales" package, into a folder of the build, and
 * finds it through LOCPATH.  A missing tool or source is a failure that says
 * to run .ci/setup, never a skip: the check would otherwise pass unseen.
 *
 * Header-only, for the test programs of several suites.  Include after
 * <stdio.h>.
 */
#ifndef RBS_TESTS_GERMAN_LOCALE_H
#define RBS_TESTS_GERMAN_LOCALE_H

#include <errno.h>
#include <locale.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

#define GERMAN_LOCALE "de_DE.UTF-8"

/* Make de_DE.UTF-8 in dir (created if missing; the test's build folder),
 * point LOCPATH there and check that the locale loads and writes 0.5 as
 * "0,5".  The process stays in the "C" locale.  Returns 0, or -1 after
 * printing why (with what to install) on stderr. */
static int german_locale_make(const char *dir)
{
    char cmd[8300], half[16];
    int rc;
    if (dir == NULL || strlen(dir) > 4000 || strchr(dir, '\'') != NULL) {
        fprintf(stderr, "german_locale: give the locale folder as the first argument "
                        "(meson passes the test's build folder)\n");
        return -1;
    }
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "german_locale: cannot create '%s': %s\n", dir, strerror(errno));
        return -1;
    }
    /* made again on every run (about 2 s): a locale left by an earlier run
     * would hide a machine that can no longer make one, and a half-written
     * one would fail for no reason.  localedef exits 1 on mere warnings, so
     * its status alone does not decide: setlocale does. */
    snprintf(cmd, sizeof cmd,
             "rm -rf '%s/" GERMAN_LOCALE "' && "
             "localedef -i de_DE -f UTF-8 '%s/" GERMAN_LOCALE "' >/dev/null 2>&1",
             dir, dir);
    rc = system(cmd);
    if (setenv("LOCPATH", dir, 1) != 0) {
        fprintf(stderr, "german_locale: setenv LOCPATH failed\n");
        return -1;
    }
    if (setlocale(LC_ALL, GERMAN_LOCALE) == NULL) {
        fprintf(stderr,
                "german_locale: could not make the " GERMAN_LOCALE " locale in '%s' "
                "(localedef -i de_DE -f UTF-8: %s %d): it needs localedef (libc-bin) and "
                "Debian's 'locales' package (the de_DE source and the UTF-8 charmap); "
                "run .ci/setup\n",
                dir, rc == -1 ? "could not run, status" :
                     WIFEXITED(rc) ? "exit status" : "wait status",
                rc == -1 ? -1 : WIFEXITED(rc) ? WEXITSTATUS(rc) : rc);
        return -1;
    }
    /* the premise of every test that uses it: this locale writes a comma */
    snprintf(half, sizeof half, "%g", 0.5);
    setlocale(LC_ALL, "C");
    if (strcmp(half, "0,5") != 0) {
        fprintf(stderr, "german_locale: " GERMAN_LOCALE " wrote 0.5 as '%s', expected '0,5'\n",
                half);
        return -1;
    }
    return 0;
}

#endif
