/* The C-API fuzz target's integration: integrators of every method and setting (through the
 * scene and through the generic layer), advances, single steps and resets to any time, and
 * tb_scene_run with frame callbacks that cancel or change the scene under the run. */
#include "fuzz_api.h"

#include <limits.h>
#include <stdlib.h>

static void maybe(fuzz_harness *h, double *field)
{
    if (fuzz_byte(h->in) < 64) {
        *field = fuzz_double(h->in);
    }
}

/* Settings of an integrator that will advance: every field may be anything except max_steps,
 * which stays small so that one input's work is bounded by the library's own step budget. */
static void integrator_settings(fuzz_harness *h, tb_integrator_def *def)
{
    *def = tb_integrator_def_default();
    const uint8_t method = fuzz_byte(h->in);
    def->method = method == 255 ? (tb_method)42 : (tb_method)(method % TB_METHOD_COUNT);
    maybe(h, &def->dt);
    maybe(h, &def->rtol);
    maybe(h, &def->atol);
    maybe(h, &def->initial_step);
    maybe(h, &def->max_step);
    def->max_steps = 1 + (long)(fuzz_u64(h->in) % FUZZ_MAX_STEPS);
    const uint8_t options = fuzz_byte(h->in);
    def->max_order = options & 1 ? (int)fuzz_choice(h->in, 15) - 1 : 0;
    def->linear_solver = (tb_linear_solver)(options >> 1 & 3);
    const bool allow_unstable = options >> 3 & 1;
    fuzz_trace(h, "tb_scene_set_allow_unstable(scene, %d);", allow_unstable);
    tb_scene_set_allow_unstable(h->scene, allow_unstable);
    def->preconditioner_half_bandwidth = options & 16 ? (int)fuzz_choice(h->in, 30) - 2 : -1;
    /* Seven times in eight only the fields the method reads (an unread field set away from its
     * default is refused at creation, which would stop most inputs there). */
    if ((options & 0xe0) != 0xe0 &&
        tb_integrator_def_set_method(def, def->method) != TB_STATUS_OK &&
        def->method < TB_METHOD_COUNT) {
        fuzz_fail("tb_integrator_def_set_method", "refused method %d", (int)def->method);
    }
}

static void trace_settings(const fuzz_harness *h, const tb_integrator_def *def)
{
    fuzz_trace(h,
               "idef = tb_integrator_def_default(); idef.method = %d; idef.dt = %s;\n"
               "idef.rtol = %s; idef.atol = %s; idef.initial_step = %s; idef.max_step = %s;\n"
               "idef.max_steps = %ld; idef.max_order = %d; idef.linear_solver = %d;\n"
               "idef.preconditioner_half_bandwidth = %d;",
               (int)def->method, fuzz_c_double(def->dt), fuzz_c_double(def->rtol),
               fuzz_c_double(def->atol), fuzz_c_double(def->initial_step),
               fuzz_c_double(def->max_step), def->max_steps, def->max_order,
               (int)def->linear_solver, def->preconditioner_half_bandwidth);
}

/* A creation that only probes validation (max_steps of any value): destroyed at once. */
static void probe_creation(fuzz_harness *h, tb_integrator_def *def)
{
    static const long steps[] = {0, -1, LONG_MIN, LONG_MAX, 1L << 40};
    def->max_steps = steps[fuzz_choice(h->in, 5)];
}

static tb_status create(fuzz_harness *h, const tb_integrator_def *def, double t0, int generic,
                        tb_integrator **out, const char **detail)
{
    if (!generic) {
        fuzz_trace(h, "tb_scene_integrator_create(scene, &idef, %s, &integrator);",
                   fuzz_c_double(t0));
        const tb_status status = tb_scene_integrator_create(h->scene, def, t0, out);
        *detail = tb_scene_detail(h->scene);
        return status;
    }
    static tb_error error;
    tb_ode_system system;
    fuzz_trace(h,
               "tb_scene_ode_system(scene, &system);\n"
               "tb_integrator_create(&system, &idef, %s, tb_scene_states(scene), "
               "&integrator, &error);",
               fuzz_c_double(t0));
    tb_status status = tb_scene_ode_system(h->scene, &system);
    if (status != TB_STATUS_OK) {
        *out = NULL; /* no creation was called: nothing to check of *out */
        *detail = tb_scene_detail(h->scene);
        return status;
    }
    status = tb_integrator_create(&system, def, t0, tb_scene_states(h->scene), out, &error);
    *detail = error.message;
    if (status == TB_STATUS_OK && error.message[0] != '\0') {
        fuzz_fail("tb_integrator_create", "TB_STATUS_OK with message \"%s\"", error.message);
    }
    return status;
}

void fuzz_op_create_integrator(fuzz_harness *h)
{
    const unsigned slot = fuzz_choice(h->in, FUZZ_MAX_INTEGRATORS);
    tb_integrator_def def;
    integrator_settings(h, &def);
    const uint8_t selector = fuzz_byte(h->in);
    const int probe = selector < 32;
    if (probe) {
        probe_creation(h, &def);
    }
    double t0 = 0.0;
    if (selector & 64) {
        t0 = fuzz_double(h->in);
    }
    trace_settings(h, &def);
    fuzz_snapshot before;
    fuzz_snapshot_take(h, &before);
    tb_integrator *integrator = (tb_integrator *)&before; /* must be set to NULL on failure */
    const char *detail = NULL;
    const tb_status status = create(h, &def, t0, selector & 128, &integrator, &detail);
    fuzz_check(h, &before, status, detail, "tb_scene_integrator_create", FUZZ_UNCHANGED);
    if (status != TB_STATUS_OK && integrator != NULL) {
        fuzz_fail("tb_scene_integrator_create", "failed but *out_integrator is not NULL");
    }
    fuzz_snapshot_free(&before);
    if (status != TB_STATUS_OK) {
        return;
    }
    if (probe) {
        fuzz_trace(h, "tb_integrator_destroy(integrator);");
        tb_integrator_destroy(integrator);
        return;
    }
    fuzz_trace(h, "tb_integrator_destroy(integrators[%u]); integrators[%u] = integrator;", slot,
               slot);
    tb_integrator_destroy(h->integrators[slot]);
    h->integrators[slot] = integrator;
    h->definitions[slot] = def;
}

static void count_work(fuzz_harness *h, const tb_integrator_stats *before,
                       const tb_integrator_stats *after)
{
    h->evaluations += after->derivative_evals - before->derivative_evals;
}

/* After an advance: on OK the integrator is at the target; on failure at a finite time no later
 * than the target. */
static void check_time(tb_integrator *integrator, tb_status status, double start, double target)
{
    const double t = tb_integrator_time(integrator);
    if (status == TB_STATUS_OK && t != target) {
        fuzz_fail("tb_integrator_advance", "OK to %.17g but the integrator is at %.17g", target, t);
    }
    if (status != TB_STATUS_OK && isfinite(target) && target >= start &&
        !(t >= start && t <= target)) {
        fuzz_fail("tb_integrator_advance", "failed from %.17g to %.17g leaving time %.17g", start,
                  target, t);
    }
}

void fuzz_op_advance(fuzz_harness *h)
{
    const unsigned slot = fuzz_choice(h->in, FUZZ_MAX_INTEGRATORS);
    tb_integrator *integrator = h->integrators[slot];
    const unsigned kind = fuzz_choice(h->in, 4);
    const double start = integrator ? tb_integrator_time(integrator) : 0.0;
    const double amount =
        fuzz_byte(h->in) < 128 ? (double)fuzz_choice(h->in, 9) / 8.0 : fuzz_double(h->in);
    if (integrator == NULL) {
        return;
    }
    tb_integrator_stats stats_before, stats_after;
    tb_integrator_get_stats(integrator, &stats_before);
    fuzz_snapshot before;
    fuzz_snapshot_take(h, &before);
    tb_status status;
    const char *call;
    h->in_derivative = 1;
    if (kind <= 1) {
        call = "tb_integrator_advance";
        fuzz_trace(h, "tb_integrator_advance(integrators[%u], %s);", slot,
                   fuzz_c_double(start + amount));
        status = tb_integrator_advance(integrator, start + amount);
    } else if (kind == 2) {
        call = "tb_integrator_step";
        fuzz_trace(h, "tb_integrator_step(integrators[%u]);", slot);
        status = tb_integrator_step(integrator);
    } else {
        call = "tb_integrator_reset";
        fuzz_trace(h, "tb_integrator_reset(integrators[%u], %s);", slot, fuzz_c_double(amount));
        status = tb_integrator_reset(integrator, amount);
    }
    h->in_derivative = 0;
    fuzz_check(h, &before, status, tb_integrator_detail(integrator), call,
               kind == 3 ? FUZZ_UNCHANGED : FUZZ_LAST_GOOD);
    if (kind <= 1) {
        check_time(integrator, status, start, start + amount);
    }
    tb_integrator_get_stats(integrator, &stats_after);
    count_work(h, &stats_before, &stats_after);
    fuzz_snapshot_free(&before);
}

/* Changes the scene from inside a frame callback, as a user's code might. */
static void change_scene(fuzz_harness *h)
{
    tb_status status = TB_STATUS_OK;
    const char *call = "frame callback";
    if (h->frame_kind == FUZZ_FRAME_ADD_BODY) {
        tb_body_def def = tb_body_def_default();
        tb_error error;
        tb_mass_from_sphere(TB_MASS_GIVEN, 1.0, 0.5, &def.mass, &error);
        fuzz_trace(h, "    /* frame callback */ tb_scene_add_body(scene, &sphere, &id);");
        status = tb_scene_add_body(h->scene, &def, NULL);
        call = "tb_scene_add_body (frame callback)";
    } else if (h->frame_kind == FUZZ_FRAME_ADD_GROUND) {
        const tb_ground_def def = tb_ground_def_default();
        fuzz_trace(h, "    /* frame callback */ tb_scene_add_ground(scene, &default_ground);");
        status = tb_scene_add_ground(h->scene, &def);
        call = "tb_scene_add_ground (frame callback)";
    } else if (h->frame_kind == FUZZ_FRAME_ADD_EFFECT) {
        tb_drag_def def = tb_drag_def_default();
        def.linear = 0.5;
        fuzz_trace(h, "    /* frame callback */ tb_scene_add_drag(scene, &(linear 0.5));");
        status = tb_scene_add_drag(h->scene, &def);
        call = "tb_scene_add_drag (frame callback)";
    } else if (h->frame_kind == FUZZ_FRAME_SET_STATE) {
        tb_body_state state;
        if (tb_scene_get_state(h->scene, 0, &state) == TB_STATUS_OK) {
            state.x[2] += 1.0;
            fuzz_trace(h, "    /* frame callback */ tb_scene_set_state(scene, 0, &(x + 1 m));");
            status = tb_scene_set_state(h->scene, 0, &state);
            call = "tb_scene_set_state (frame callback)";
        }
    } else if (h->frame_kind == FUZZ_FRAME_CONTACT) {
        const tb_contact_point point = {{0, 0, 0}, 0.5};
        fuzz_trace(h, "    /* frame callback */ tb_scene_set_contact_points(scene, 0, "
                      "&(centre, 0.5 m), 1, 1);");
        status = tb_scene_set_contact_points(h->scene, 0, &point, 1, 1);
        call = "tb_scene_set_contact_points (frame callback)";
    }
    fuzz_check(h, NULL, status, tb_scene_detail(h->scene), call, FUZZ_UNCHANGED);
    h->callback_changed = 1;
}

static size_t frames_seen;
static double last_frame_time;

static int on_frame(size_t frame, double t, const tb_scene *scene, void *ctx)
{
    fuzz_harness *h = ctx;
    if (scene != h->scene || frame != frames_seen || !isfinite(t) ||
        (frame > 0 && !(t > last_frame_time))) {
        fuzz_fail("tb_scene_run",
                  "frame callback got frame %zu at t = %g after %zu frames "
                  "(last at %g)",
                  frame, t, frames_seen, last_frame_time);
    }
    ++frames_seen;
    last_frame_time = t;
    fuzz_check_state_finite(h, "tb_scene_run (state handed to a frame)");
    if (frame >= FUZZ_MAX_FRAMES || (h->frame_kind == FUZZ_FRAME_CANCEL && frame == h->at_frame)) {
        return 1;
    }
    if (frame == h->at_frame && h->frame_kind != FUZZ_FRAME_CONTINUE) {
        change_scene(h);
    }
    return 0;
}

void fuzz_op_run(fuzz_harness *h)
{
    tb_run_def def = tb_run_def_default();
    integrator_settings(h, &def.integrator);
    def.fps = 10.0 + fuzz_choice(h->in, 60);
    def.duration = (double)fuzz_choice(h->in, 9) / 4.0;
    maybe(h, &def.fps);
    maybe(h, &def.duration);
    h->frame_kind = (fuzz_frame_kind)fuzz_choice(h->in, FUZZ_FRAME_KIND_COUNT);
    h->at_frame = fuzz_choice(h->in, 8);
    /* Without a callback nothing stops a long run but the library's own budgets. */
    const int callback = fuzz_byte(h->in) >= 64 || !(def.duration * def.fps < FUZZ_MAX_FRAMES);
    trace_settings(h, &def.integrator);
    fuzz_trace(h,
               "run = tb_run_def_default(); run.integrator = idef; run.fps = %s; "
               "run.duration = %s;\n"
               "tb_scene_run(scene, &run, %s, ctx, &stats, &error); "
               "/* frame callback: kind %d at frame %zu */",
               fuzz_c_double(def.fps), fuzz_c_double(def.duration), callback ? "on_frame" : "NULL",
               (int)h->frame_kind, h->at_frame);
    fuzz_snapshot before;
    fuzz_snapshot_take(h, &before);
    frames_seen = 0;
    h->callback_changed = 0;
    h->in_derivative = 1;
    tb_integrator_stats stats;
    tb_error error;
    const tb_status status =
        tb_scene_run(h->scene, &def, callback ? on_frame : NULL, h, &stats, &error);
    h->in_derivative = 0;
    /* A run may stop on any status after some frames (UNSTABLE_STEP as the spin grows,
     * LAYOUT_CHANGED after a callback changed the scene): the last good state. */
    fuzz_check(h, &before, status, error.message, "tb_scene_run", FUZZ_HAS_RUN);
    if (status == TB_STATUS_OK && error.message[0] != '\0') {
        fuzz_fail("tb_scene_run", "TB_STATUS_OK with message \"%s\"", error.message);
    }
    h->callback_changed = 0;
    h->evaluations += stats.derivative_evals;
    fuzz_snapshot_free(&before);
}
