/*
 * test_extremes.c - the extreme cases (cases.c) for every method.
 *
 * Usage: test_extremes [light|heavy]  (default light: everything but the
 * 1e7-step runs).  For each case and method: a method that does not cover
 * the scene (RBS_E_UNSUPPORTED) is skipped with a printed note; otherwise
 * the measured value must be within the case's bound, unless the case lists
 * the method as not promised (then the number is only printed).  Any other
 * error from a call fails the test.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "cases.h"

static void run_case(void **state)
{
    const xcase *c = (const xcase *)*state;
    int m, failures = 0;
    for (m = 0; m < XMETHODS; ++m) {
        xres r;
        const char *name = rbs_method_name((rbs_method)m);
        memset(&r, 0, sizeof r);
        r.extra = NAN;
        c->run((rbs_method)m, &r);
        if (r.skipped) {
            print_message("[ SKIP     ] %s/%s: %s\n", c->id, name, r.note);
            continue;
        }
        if (r.failed) {
            print_error("%s/%s: %s\n", c->id, name, r.note);
            failures++;
            continue;
        }
        print_message("[ MEASURED ] %s/%s: %.6g (bound %.6g)%s%s\n", c->id, name, r.value, r.bound,
                      xres_pass(&r) ? "" : " OVER THE BOUND",
                      (c->not_promised >> m) & 1u ? " (not promised)" : "");
        if (!xres_pass(&r) && !((c->not_promised >> m) & 1u)) {
            print_error("%s/%s: %.17g exceeds the bound %.17g (%s)\n", c->id, name, r.value, r.bound,
                        c->bound);
            failures++;
        }
    }
    if (failures)
        fail_msg("%s: %d method(s) failed", c->id, failures);
}

int main(int argc, char **argv)
{
    uint32_t n, i, k = 0;
    int heavy = argc > 1 && strcmp(argv[1], "heavy") == 0;
    const xcase *cs = xcases(&n);
    struct CMUnitTest *tests = calloc(n, sizeof *tests);
    int rc;
    if (tests == NULL)
        return 1;
    for (i = 0; i < n; ++i) {
        if (cs[i].heavy != heavy)
            continue;
        tests[k].name = cs[i].id;
        tests[k].test_func = run_case;
        tests[k].initial_state = (void *)&cs[i];
        k++;
    }
    rc = _cmocka_run_group_tests(heavy ? "extremes_heavy" : "extremes", tests, k, NULL, NULL);
    free(tests);
    return rc;
}
