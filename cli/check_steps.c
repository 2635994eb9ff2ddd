/* tumble check's report of the fixed steps, all asked of the library (tb_scene_default_step,
 * tb_scene_max_stable_step), so that what check prints is what run would take. */
#include "check_steps.h"

#include <math.h>
#include <stdio.h>

static void print_method(const tb_scene *scene, tb_method method)
{
    double dt = 0.0, stable = 0.0;
    char which[TB_DETAIL_SIZE];
    if (tb_scene_default_step(scene, method, &dt) != TB_STATUS_OK) {
        fprintf(stderr, "  %-9s no default step: %s\n", tb_method_name(method),
                tb_scene_detail(scene));
        return;
    }
    fprintf(stderr, "  %-9s dt %.3g s, %.6g steps per simulated second", tb_method_name(method), dt,
            1.0 / dt);
    if (tb_scene_max_stable_step(scene, method, &stable, which) == TB_STATUS_OK &&
        isfinite(stable)) {
        fprintf(stderr, " (stable up to %.3g s, set by %s)", stable, which);
    }
    fprintf(stderr, "\n");
}

void cli_check_steps(const tb_scene *scene)
{
    fprintf(stderr, "default steps (dt 0) of the fixed-step methods:\n");
    for (int m = 0; m < TB_METHOD_COUNT; ++m) {
        if (!tb_method_is_adaptive((tb_method)m)) {
            print_method(scene, (tb_method)m);
        }
    }
}
