/* The small framework of the example-scene tests (test_example_scenes.c,
 * test_example_contact_scenes.c): each example is a function of checks run by name from the
 * command line, each check printed with its value and limit, and the program's exit status
 * says whether any failed. Not CMocka: a check that fails lets the others run and be printed. */
#ifndef TUMBLE_TEST_EXAMPLES_H
#define TUMBLE_TEST_EXAMPLES_H

#include "tumble/tumble.h"

#include <stddef.h>

typedef struct test_example {
    const char *name;    /* the scene's name: examples/scenes/NAME.json */
    void (*check)(void); /* loads it, runs it and checks it with test_check */
} test_example;

/* Prints what, value, limit and ok or FAILED; counts a failure when !ok. */
void test_check(int ok, const char *what, double value, double limit);

/* Loads DIR/NAME.json and its run settings into *run; on refusal prints the library's message and
 * exits with status 1 (the test fails). */
tb_scene *test_example_load(const char *dir, const char *name, tb_run_def *run);

/* Runs the example argv[1] names (argc - 2 further arguments, at most extra_args, are the
 * caller's to read): prints its name, its checks and "1 passed, 0 failed" or "0 passed, 1
 * failed", and returns 0 when every check held, 1 otherwise; 2 with the usage line when no
 * example has that name. */
int test_example_main(int argc, char **argv, const test_example *examples, size_t count,
                      int extra_args, const char *usage);

#endif
