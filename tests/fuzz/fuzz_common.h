/*
 * fuzz_common.h - shared by the fuzz harnesses: the libFuzzer entry point's
 * prototype and an invariant check that stops the process loudly (abort()
 * is what libFuzzer and the regression runner both report as a crash; this
 * is test code, never library code).
 */
#ifndef RBS_FUZZ_COMMON_H
#define RBS_FUZZ_COMMON_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "rbsim/rbsim.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define FUZZ_CHECK(cond, ...)                                                   \
    do {                                                                        \
        if (!(cond)) {                                                          \
            fprintf(stderr, "fuzz invariant failed at %s:%d: %s: ", __FILE__,   \
                    __LINE__, #cond);                                           \
            fprintf(stderr, __VA_ARGS__);                                       \
            fputc('\n', stderr);                                                \
            abort();                                                            \
        }                                                                       \
    } while (0)

/* A status is RBS_OK or one of the listed errors. */
static inline int fuzz_status_valid(rbs_status st)
{
    return st <= RBS_OK && st >= RBS_E_OWN_INPUT;
}

/* Steps a fuzzed world may take per input: a few, so a slow scene cannot
 * stall the fuzzer (the work of one step is itself bounded by the core). */
#define FUZZ_STEPS 3

#endif
