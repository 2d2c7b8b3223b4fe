/*
 * stream.c - the machine's limits for one core, measured the way STREAM does
 * (J. D. McCalpin, "Memory Bandwidth and Machine Balance in Current High
 * Performance Computers", IEEE TCCA Newsletter, 1995):
 *
 *   peers_stream [MEGABYTES_PER_ARRAY]     prints one JSON line
 *
 *  copy:  c[i] = a[i]              16 bytes per element (read + write)
 *  triad: a[i] = b[i] + s * c[i]   24 bytes per element
 * counted as STREAM counts them (write-allocate traffic not added), best of
 * 10 passes over arrays far larger than the caches (default 128 MB each).
 * Also a floating-point rate: 8 independent multiply-add chains in doubles,
 * plain C as the build compiles it (a rough ceiling for rbsim's arithmetic,
 * which is mostly scalar).
 * Single-threaded, like rbsim's stepping.
 */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int main(int argc, char **argv)
{
    double mb = argc > 1 ? atof(argv[1]) : 128.0;
    size_t n, i;
    double *a, *b, *c, best_copy = 1e30, best_triad = 1e30, s = 3.0, t, check = 0.0;
    double acc[8], x = 1.0000001, y = 1e-9, flops_time = 1e30;
    long reps = 50000000, r;
    int pass, k;
    if (!(mb >= 1.0 && mb <= 8192.0)) {
        fprintf(stderr, "usage: peers_stream [MEGABYTES_PER_ARRAY in 1..8192]\n");
        return 2;
    }
    n = (size_t)(mb * 1e6 / sizeof(double));
    a = malloc(n * sizeof *a);
    b = malloc(n * sizeof *b);
    c = malloc(n * sizeof *c);
    if (!a || !b || !c) {
        fprintf(stderr, "peers_stream: out of memory for 3 x %.0f MB\n", mb);
        return 2;
    }
    for (i = 0; i < n; ++i) {
        a[i] = 1.0;
        b[i] = 2.0;
        c[i] = 0.0;
    }
    for (pass = 0; pass < 10; ++pass) {
        t = now();
        for (i = 0; i < n; ++i)
            c[i] = a[i];
        t = now() - t;
        if (t < best_copy)
            best_copy = t;
        t = now();
        for (i = 0; i < n; ++i)
            a[i] = b[i] + s * c[i];
        t = now() - t;
        if (t < best_triad)
            best_triad = t;
    }
    for (i = 0; i < n; i += 4096)
        check += a[i] + c[i];

    /* multiply-add chains: 2 flops each */
    for (pass = 0; pass < 3; ++pass) {
        for (k = 0; k < 8; ++k)
            acc[k] = (double)k;
        t = now();
        for (r = 0; r < reps; ++r)
            for (k = 0; k < 8; ++k)
                acc[k] = acc[k] * x + y;
        t = now() - t;
        if (t < flops_time)
            flops_time = t;
        for (k = 0; k < 8; ++k)
            check += acc[k];
    }

    printf("{\"array_mb\": %.0f, \"copy_gbs\": %.3f, \"triad_gbs\": %.3f, \"gflops_scalar\": %.3f, "
           "\"check\": %.6g}\n",
           mb, 16.0 * (double)n / best_copy / 1e9, 24.0 * (double)n / best_triad / 1e9,
           2.0 * 8.0 * (double)reps / flops_time / 1e9, check);
    free(a);
    free(b);
    free(c);
    return 0;
}
