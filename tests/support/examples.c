#include "examples.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int failures;

void test_check(int ok, const char *what, double value, double limit)
{
    printf("  %-62s %12.4g  (limit %.3g)  %s\n", what, value, limit, ok ? "ok" : "FAILED");
    failures += !ok;
}

tb_scene *test_example_load(const char *dir, const char *name, tb_run_def *run)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s.json", dir, name);
    tb_scene *scene = NULL;
    tb_error error;
    if (tb_scene_load_file(path, &scene, run, &error) != TB_STATUS_OK) {
        printf("%s\n", error.message);
        exit(1);
    }
    return scene;
}

int test_example_main(int argc, char **argv, const test_example *examples, size_t count,
                      int extra_args, const char *usage)
{
    for (size_t k = 0; k < count; ++k) {
        if (argc >= 2 && argc <= 2 + extra_args && strcmp(argv[1], examples[k].name) == 0) {
            printf("%s:\n", examples[k].name);
            examples[k].check();
            printf("%d passed, %d failed\n", failures == 0, failures != 0);
            return failures == 0 ? 0 : 1;
        }
    }
    fprintf(stderr, "%s\n", usage);
    return 2;
}
