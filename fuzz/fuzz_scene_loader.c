/* libFuzzer target: any bytes given to the scene loader must give a scene or a status with a
 * message, never a crash, a leak or undefined behaviour. Built by scripts/fuzz.sh. */
#include "tumble/tumble.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (text == NULL) {
        return 0;
    }
    memcpy(text, data, size);
    text[size] = '\0';
    tb_scene *scene = NULL;
    tb_run_def run;
    tb_error error;
    const tb_status status = tb_scene_load_string(text, "fuzz.json", NULL, &scene, &run, &error);
    if (status == TB_STATUS_OK) {
        /* A loaded scene must also survive a derivative and a short, cheap run. */
        double *dydt = malloc(tb_scene_state_size(scene) * sizeof(double));
        if (dydt != NULL) {
            tb_scene_derivative(0.0, tb_scene_states(scene), dydt, scene);
            free(dydt);
        }
        run.duration = 0.05;
        run.fps = 20;
        run.integrator.max_steps = 1000;
        /* A scene may ask for a minute dt; the harness only runs what is quick. */
        if (tb_method_is_adaptive(run.integrator.method) ||
            run.duration / run.integrator.dt < 2000) {
            tb_scene_run(scene, &run, NULL, NULL, NULL, &error);
        }
        tb_scene_destroy(scene);
    } else if (error.message[0] == '\0' || scene != NULL) {
        abort(); /* a failure must say why and leave nothing behind */
    }
    free(text);
    return 0;
}
