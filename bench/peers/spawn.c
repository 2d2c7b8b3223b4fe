/*
 * spawn.c - runs one benchmark process and reports its own peak memory.
 *
 *   peers_spawn LIMIT_SECONDS OUTFILE COMMAND [ARGS...]
 *
 * Prints one JSON line: exit code, signal, whether it was killed for running
 * past LIMIT_SECONDS, peak resident memory (ru_maxrss of the one waited-for
 * child, getrusage(RUSAGE_CHILDREN), kB) and wall time.  COMMAND's stdout and stderr go to OUTFILE.
 *
 * Why a separate program: Linux carries a process's peak RSS across execve
 * (the old image's high-water mark is kept), so a driver forked straight from
 * the Python runner would report at least the runner's ~60 MB.  Forked from
 * this small program, the driver's peak is its own.
 *
 * The child runs with address-space randomisation off (personality(2),
 * ADDR_NO_RANDOMIZE; "aslr": 0 in the line, 1 if the system refused), every
 * engine alike: where the libraries land decides which pages of them the
 * kernel maps around each fault, and with it on, the peak of the same run
 * of the one-ball scene varied by 0.28 MB (rbsim: 2.81-3.09 MB in 10 runs;
 * off: 3.02 MB in all 8) -- as much as a third of what a 1,000-sphere pile
 * adds to it.
 */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/personality.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int main(int argc, char **argv)
{
    double limit, t0;
    char *end = NULL;
    pid_t pid;
    int status = 0, killed = 0, fd, aslr;
    struct rusage ru;
    struct timespec nap = {0, 20000000};

    if (argc < 4) {
        fprintf(stderr, "usage: peers_spawn LIMIT_SECONDS OUTFILE COMMAND [ARGS...]\n");
        return 2;
    }
    limit = strtod(argv[1], &end);
    if (*argv[1] == '\0' || *end != '\0' || !(limit > 0.0)) {
        fprintf(stderr, "peers_spawn: LIMIT_SECONDS must be > 0, got \"%s\"\n", argv[1]);
        return 2;
    }
    fd = open(argv[2], O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) {
        fprintf(stderr, "peers_spawn: cannot create %s\n", argv[2]);
        return 2;
    }
    {
        /* (in the parent: the child inherits it, and the report says it) */
        const int was = personality(0xffffffff);
        aslr = was == -1 || personality((unsigned long)was | ADDR_NO_RANDOMIZE) == -1 ||
               !(personality(0xffffffff) & ADDR_NO_RANDOMIZE);
    }
    t0 = now();
    pid = fork();
    if (pid < 0) {
        fprintf(stderr, "peers_spawn: fork failed\n");
        return 2;
    }
    if (pid == 0) {
        dup2(fd, 1);
        dup2(fd, 2);
        close(fd);
        execvp(argv[3], &argv[3]);
        fprintf(stderr, "peers_spawn: cannot run %s\n", argv[3]);
        _exit(127);
    }
    close(fd);
    for (;;) {
        pid_t r = waitpid(pid, &status, WNOHANG);
        if (r == pid)
            break;
        if (r < 0 && errno != EINTR) {
            fprintf(stderr, "peers_spawn: waitpid failed\n");
            return 2;
        }
        if (!killed && now() - t0 > limit) {
            kill(pid, SIGKILL);
            killed = 1;
        }
        nanosleep(&nap, NULL);
    }
    getrusage(RUSAGE_CHILDREN, &ru); /* the one child: its own peak */
    printf("{\"exit\": %d, \"signal\": %d, \"killed\": %d, \"maxrss_kb\": %ld, \"wall\": %.6f, \"aslr\": %d}\n",
           WIFEXITED(status) ? WEXITSTATUS(status) : -1, WIFSIGNALED(status) ? WTERMSIG(status) : 0,
           killed, ru.ru_maxrss, now() - t0, aslr);
    return 0;
}
