/* libFuzzer target: any bytes given to the scene loader must give a scene or a status with a
 * message, never a crash, a leak or undefined behaviour. A failed load leaves no scene and the
 * run definition untouched; a loaded scene has a finite state and survives a derivative and a
 * short run with the integrator the file asks for (its step budget kept small, so that the
 * library's budget, not the harness, bounds the work). Built by scripts/fuzz.sh. */
#include "tumble/tumble.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void fail(const char *what, const char *detail)
{
    fprintf(stderr, "fuzz_scene_loader: %s (%s)\n", what, detail);
    abort();
}

static void check_finite(const tb_scene *scene, const char *when)
{
    const double *y = tb_scene_states_const(scene);
    for (size_t i = 0; i < tb_scene_state_size(scene); ++i) {
        if (!isfinite(y[i])) {
            fail("a non-finite state", when);
        }
    }
}

static void exercise(tb_scene *scene, tb_run_def *run)
{
    check_finite(scene, "after loading");
    double *dydt = malloc((tb_scene_state_size(scene) + 1) * sizeof(double));
    if (dydt == NULL) {
        abort();
    }
    tb_scene_derivative(0.0, tb_scene_states(scene), dydt, scene);
    free(dydt);
    run->duration = 0.05;
    run->fps = 20;
    run->integrator.max_steps = 1000;
    tb_error error;
    const tb_status status = tb_scene_run(scene, run, NULL, NULL, NULL, &error);
    if (status != TB_STATUS_OK && error.message[0] == '\0') {
        fail("a failed run without a message", tb_status_name(status));
    }
    check_finite(scene, status == TB_STATUS_OK ? "after a run" : "after a failed run");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (text == NULL) {
        return 0;
    }
    memcpy(text, data, size);
    text[size] = '\0';
    tb_scene *scene = NULL;
    tb_run_def run, untouched;
    memset(&run, 0xa5, sizeof run);
    memcpy(&untouched, &run, sizeof run);
    tb_error error;
    const tb_status status = tb_scene_load_string(text, "fuzz.json", NULL, &scene, &run, &error);
    if (status == TB_STATUS_OK) {
        exercise(scene, &run);
        tb_scene_destroy(scene);
    } else if (error.message[0] == '\0' || scene != NULL) {
        fail("a failed load without a message or with a scene", tb_status_name(status));
    } else if (memcmp(&run, &untouched, sizeof run) != 0) {
        fail("a failed load changed the run definition", error.message);
    }
    free(text);
    return 0;
}
