/* The command line of the benchmarks over the example scenes (bench_bdf_contact, bench_ark_imex):
 *   [--quick] [--solver NAME] [--scene NAME] [EXAMPLES_DIR]
 * in that order, each optional; --solver only where the benchmark has solvers to choose. */
#ifndef TUMBLE_BENCH_ARGS_H
#define TUMBLE_BENCH_ARGS_H

#include <stdbool.h>
#include <string.h>

typedef struct bench_args {
    bool quick;           /* --quick: the ctest's short run */
    const char *solver;   /* --solver NAME: that solver's rows alone; NULL: every solver */
    const char *scene;    /* --scene NAME: that scene's rows alone; NULL: every scene */
    const char *examples; /* the example scenes' folder */
} bench_args;

/* The arguments; examples: the folder when none is given; with_solver: whether --solver is
 * read (otherwise it is taken for the folder, as any other word). */
static inline bench_args bench_parse_args(int argc, char **argv, const char *examples,
                                          bool with_solver)
{
    bench_args args = {false, NULL, NULL, examples};
    int next = 1;
    if (argc > next && strcmp(argv[next], "--quick") == 0) {
        args.quick = true;
        next += 1;
    }
    if (with_solver && argc > next + 1 && strcmp(argv[next], "--solver") == 0) {
        args.solver = argv[next + 1];
        next += 2;
    }
    if (argc > next + 1 && strcmp(argv[next], "--scene") == 0) {
        args.scene = argv[next + 1];
        next += 2;
    }
    if (argc > next) {
        args.examples = argv[next];
    }
    return args;
}

/* Whether a row named name is wanted by a filter (NULL: every row). */
static inline bool bench_wanted(const char *filter, const char *name)
{
    return filter == NULL || strcmp(filter, name) == 0;
}

#endif
