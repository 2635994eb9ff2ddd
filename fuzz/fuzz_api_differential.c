/* The C-API fuzz target's differential checks: claims of the design that a random scene can test.
 *
 * - "Bodies that do not interact are stepped a cache-sized chunk at a time ... None of this
 *   changes the result: the same bits for any chunk" (DESIGN.md): a fixed-step integrator on the
 *   scene's separable system and one on the same system with block_size 0 (the whole-array path)
 *   give the same status and bit-identical states.
 * - "A torque-free body keeps L exactly under every Runge-Kutta method" and a force-free one its P
 *   (DESIGN.md): in a scene without effects, P and L come out of a fixed-step advance unchanged
 *   (exactly equal; a -0 may come out +0).
 * Both integrators run on copies of the state through the generic layer, without the scene's
 * lifetime hooks, so the scene and the harness's integrators are left alone. */
#include "fuzz_api.h"

#include <stdlib.h>

static tb_status advance_copy(fuzz_harness *h, const tb_ode_system *system,
                              const tb_integrator_def *def, double *y, double target, char *detail)
{
    tb_integrator *integrator = NULL;
    tb_error error;
    tb_status status = tb_integrator_create(system, def, 0.0, y, &integrator, &error);
    if (status == TB_STATUS_OK) {
        status = tb_integrator_advance(integrator, target);
        snprintf(detail, TB_DETAIL_SIZE, "%s", tb_integrator_detail(integrator));
        tb_integrator_stats stats;
        tb_integrator_get_stats(integrator, &stats);
        h->evaluations += stats.derivative_evals;
    } else {
        snprintf(detail, TB_DETAIL_SIZE, "%s", error.message);
    }
    tb_integrator_destroy(integrator);
    return status;
}

static void check_momenta_kept(const fuzz_harness *h, const double *before, const double *after)
{
    for (size_t body = 0; body < tb_scene_body_count(h->scene); ++body) {
        const size_t at = TB_STATE_SIZE * body + TB_STATE_P;
        for (size_t i = 0; i < 6; ++i) {
            if (before[at + i] != after[at + i]) { /* -0 + 0 is +0: equal values, not bits */
                fuzz_fail("tb_integrator_advance (no effects)",
                          "body %zu's %s[%zu] changed: %a -> %a", body, i < 3 ? "P" : "L", i % 3,
                          before[at + i], after[at + i]);
            }
        }
    }
}

void fuzz_op_differential(fuzz_harness *h)
{
    const tb_method method = (tb_method)fuzz_choice(h->in, 3); /* euler, midpoint, rk4 */
    const double dt = fuzz_byte(h->in) < 128 ? 1.0 / 240 : fuzz_double(h->in);
    const double target = (double)(1 + fuzz_choice(h->in, 8)) / 8.0;
    /* Sleeping off for the comparison: the islands' flags live in the scene, outside y, so
     * the first of two runs over copies of the state (without the scene's acquire, which
     * this harness takes out) would hand its sleeping bodies to the second. Chunking is what
     * is compared; sleep has its own tests (test_sleep, test_sleep_wake). */
    const bool sleeping = tb_scene_sleeping(h->scene);
    tb_scene_set_sleeping(h->scene, false);
    tb_ode_system chunked;
    if (tb_scene_ode_system(h->scene, &chunked) != TB_STATUS_OK) {
        tb_scene_set_sleeping(h->scene, sleeping);
        return;
    }
    chunked.lifetime.layout_generation = NULL, chunked.lifetime.acquire = NULL,
    chunked.lifetime.release = NULL;
    tb_ode_system whole = chunked;
    whole.blocks.size = 0, whole.blocks.derivative = NULL, whole.blocks.post_step = NULL;
    tb_integrator_def def = tb_integrator_def_default();
    def.method = method, def.dt = dt, def.max_steps = FUZZ_MAX_STEPS;
    const size_t n = chunked.n;
    double *start = malloc(3 * n * sizeof(double));
    if (start == NULL) {
        abort();
    }
    double *a = start + n, *b = start + 2 * n;
    memcpy(start, tb_scene_states_const(h->scene), n * sizeof(double));
    memcpy(a, start, n * sizeof(double)), memcpy(b, start, n * sizeof(double));
    fuzz_trace(h, "/* differential: %s dt %s to t = %s, separable (block_size %zu) and whole */",
               tb_method_name(method), fuzz_c_double(dt), fuzz_c_double(target),
               chunked.blocks.size);
    char detail_a[TB_DETAIL_SIZE], detail_b[TB_DETAIL_SIZE];
    const tb_status status_a = advance_copy(h, &chunked, &def, a, target, detail_a);
    const tb_status status_b = advance_copy(h, &whole, &def, b, target, detail_b);
    if (status_a != status_b || memcmp(a, b, n * sizeof(double)) != 0) {
        fuzz_fail("tb_integrator_advance (chunked vs whole array)", "%s (%s) vs %s (%s), states %s",
                  tb_status_name(status_a), detail_a, tb_status_name(status_b), detail_b,
                  memcmp(a, b, n * sizeof(double)) ? "differ" : "equal");
    }
    if (status_a == TB_STATUS_OK && tb_scene_effect_count(h->scene) == 0) {
        check_momenta_kept(h, start, a);
    }
    free(start);
    tb_scene_set_sleeping(h->scene, sleeping);
}
