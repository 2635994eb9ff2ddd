/* libFuzzer target: random scenes built through the public C API. The input is read as a
 * program (fuzz_input.h): each operation adds a body (every mass constructor, extreme and
 * non-finite values), an effect (every kind, user effects that fail or re-enter), contact
 * points, sets states, makes integrators (every method, any dt/rtol/atol/max_steps), advances
 * them, runs the scene with frame callbacks that fail or change the scene, or reads it out.
 * After every call the contract is checked (fuzz_check): OK or an error with a detail; a
 * refused call changes nothing (state bit-identical, same counts); after OK the state is
 * finite. A violation aborts, so libFuzzer keeps the input. TUMBLE_FUZZ_TRACE=1 prints the
 * calls as C. */
#include "fuzz_api.h"

#include <stdarg.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

void fuzz_fail(const char *call, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    fprintf(stderr, "fuzz_api: invariant broken after %s: ", call);
    vfprintf(stderr, format, args);
    fputc('\n', stderr);
    va_end(args);
    abort();
}

void fuzz_trace(const fuzz_harness *h, const char *format, ...)
{
    if (!h->trace) {
        return;
    }
    va_list args;
    va_start(args, format);
    vfprintf(stderr, format, args);
    fputc('\n', stderr);
    va_end(args);
}

static char *rotating_buffer(void)
{
    static char buffers[64][512];
    static unsigned next;
    return buffers[next++ % 64];
}

const char *fuzz_c_double(double value)
{
    char *out = rotating_buffer();
    if (isnan(value)) {
        snprintf(out, 512, "NAN");
    } else if (isinf(value)) {
        snprintf(out, 512, value > 0 ? "INFINITY" : "-INFINITY");
    } else if (value == 0 ||
               (fabs(value) >= 1e-5 && fabs(value) < 1e17 && value == (double)(float)value)) {
        snprintf(out, 512, "%.9g", value); /* exact in fewer digits */
    } else {
        snprintf(out, 512, "%.17g", value);
    }
    return out;
}

const char *fuzz_c_vector(const double *values, size_t count)
{
    char *out = rotating_buffer();
    size_t used = (size_t)snprintf(out, 512, "(double[]){");
    for (size_t i = 0; i < count && used < 512; ++i) {
        used += (size_t)snprintf(out + used, 512 - used, "%s%s", i ? ", " : "",
                                 fuzz_c_double(values[i]));
    }
    if (used < 512) {
        snprintf(out + used, 512 - used, "}");
    }
    return out;
}

const char *fuzz_c_id(size_t id)
{
    char *out = rotating_buffer();
    if (id == (size_t)-1) {
        snprintf(out, 512, "(size_t)-1");
    } else {
        snprintf(out, 512, "%zu", id);
    }
    return out;
}

void fuzz_snapshot_take(const fuzz_harness *h, fuzz_snapshot *out)
{
    out->state_size = tb_scene_state_size(h->scene);
    out->bodies = tb_scene_body_count(h->scene);
    out->effects = tb_scene_effect_count(h->scene);
    out->state = malloc((out->state_size + 1) * sizeof(double));
    if (out->state == NULL) {
        abort();
    }
    memcpy(out->state, tb_scene_states_const(h->scene), out->state_size * sizeof(double));
}

void fuzz_snapshot_free(fuzz_snapshot *snapshot)
{
    free(snapshot->state);
    snapshot->state = NULL;
}

void fuzz_check_state_finite(const fuzz_harness *h, const char *call)
{
    const double *y = tb_scene_states_const(h->scene);
    const size_t n = tb_scene_state_size(h->scene);
    for (size_t i = 0; i < n; ++i) {
        if (!isfinite(y[i])) {
            fuzz_fail(call, "state[%zu] = %g is not finite after TB_STATUS_OK", i, y[i]);
        }
    }
}

void fuzz_check_unchanged(const fuzz_harness *h, const fuzz_snapshot *before, const char *call,
                          tb_status status)
{
    const char *name = tb_status_name(status);
    if (tb_scene_body_count(h->scene) != before->bodies ||
        tb_scene_effect_count(h->scene) != before->effects ||
        tb_scene_state_size(h->scene) != before->state_size) {
        fuzz_fail(call,
                  "refused (%s) but bodies %zu -> %zu, effects %zu -> %zu, state size %zu "
                  "-> %zu",
                  name, before->bodies, tb_scene_body_count(h->scene), before->effects,
                  tb_scene_effect_count(h->scene), before->state_size,
                  tb_scene_state_size(h->scene));
    }
    const double *y = tb_scene_states_const(h->scene);
    if (before->state_size > 0 &&
        memcmp(y, before->state, before->state_size * sizeof(double)) != 0) {
        for (size_t i = 0; i < before->state_size; ++i) {
            if (memcmp(&y[i], &before->state[i], sizeof(double)) != 0) {
                fuzz_fail(call, "refused (%s) but state[%zu] changed %.17g -> %.17g", name, i,
                          before->state[i], y[i]);
            }
        }
    }
}

/* Statuses that refuse a call before it acts: the state must be untouched even where a failed
 * step may leave the last good state. */
static int is_refusal(tb_status status)
{
    switch (status) {
    case TB_STATUS_INVALID_ARGUMENT:
    case TB_STATUS_NULL_POINTER:
    case TB_STATUS_OUT_OF_RANGE:
    case TB_STATUS_NOT_FINITE:
    case TB_STATUS_UNSUPPORTED:
    case TB_STATUS_UNSTABLE_STEP: /* checked before any step, also at run time */
    case TB_STATUS_LAYOUT_CHANGED:
    case TB_STATUS_BUSY:
        return 1;
    default:
        return 0;
    }
}

void fuzz_check(const fuzz_harness *h, const fuzz_snapshot *before, tb_status status,
                const char *detail, const char *call, fuzz_failure_rule rule)
{
    if (status > 0 || strcmp(tb_status_name(status), "UNKNOWN") == 0) {
        fuzz_fail(call, "returned %d, not a tb_status", (int)status);
    }
    fuzz_trace(h, "    /* -> %s%s%s */", tb_status_name(status), detail ? ": " : "",
               detail ? detail : "");
    if (status == TB_STATUS_OK) {
        fuzz_check_state_finite(h, call);
        return;
    }
    if (detail != NULL && detail[0] == '\0') {
        fuzz_fail(call, "returned %s with an empty detail", tb_status_name(status));
    }
    if (before == NULL) {
        return;
    }
    if (rule == FUZZ_UNCHANGED || (rule == FUZZ_LAST_GOOD && is_refusal(status))) {
        fuzz_check_unchanged(h, before, call, status);
    } else if (!h->callback_changed && tb_scene_body_count(h->scene) != before->bodies) {
        fuzz_fail(call, "failed (%s) and the body count changed", tb_status_name(status));
    } else {
        const double *y = tb_scene_states_const(h->scene);
        for (size_t i = 0; i < tb_scene_state_size(h->scene); ++i) {
            if (!isfinite(y[i])) {
                fuzz_fail(call, "failed (%s) leaving state[%zu] = %g, not the last good state",
                          tb_status_name(status), i, y[i]);
            }
        }
    }
}

size_t fuzz_body_id(fuzz_harness *h)
{
    const size_t count = tb_scene_body_count(h->scene);
    const uint8_t selector = fuzz_byte(h->in);
    if (selector < 224) {
        return count == 0 ? 0 : selector % count;
    }
    static const size_t odd[] = {0, 1, 8, 100, (size_t)-2, (size_t)-1, (size_t)1 << 62};
    return selector % 8 == 0 ? count : odd[selector % 7];
}

static void create_scene(fuzz_harness *h)
{
    tb_scene_def def = tb_scene_def_default();
    const uint8_t selector = fuzz_byte(h->in);
    if (selector & 1) {
        def.body_capacity = fuzz_choice(h->in, 4);
    }
    if (selector & 2) {
        def.effect_capacity = fuzz_choice(h->in, 4);
    }
    def.renormalize_quaternions = (selector & 4) == 0;
    if ((selector & 0xf8) == 0xf8) { /* capacities whose size computations overflow */
        static const size_t huge[] = {(size_t)1 << 61, (size_t)1 << 62, (size_t)-1,
                                      (size_t)1 << 59};
        def.body_capacity = huge[fuzz_choice(h->in, 4)];
        def.effect_capacity = huge[fuzz_choice(h->in, 4)];
    }
    tb_error error;
    fuzz_trace(h,
               "tb_scene_def def = tb_scene_def_default();\n"
               "def.body_capacity = %zu; def.effect_capacity = %zu;\n"
               "def.renormalize_quaternions = %d;\n"
               "tb_scene *scene; tb_error error;\n"
               "tb_scene_create(&def, &scene, &error);",
               def.body_capacity, def.effect_capacity, def.renormalize_quaternions);
    const tb_status status = tb_scene_create(&def, &h->scene, &error);
    if (status != TB_STATUS_OK) {
        if (h->scene != NULL || error.message[0] == '\0') {
            fuzz_fail("tb_scene_create", "failed (%s) with a scene or without a message",
                      tb_status_name(status));
        }
        /* Huge capacities may be refused; the rest of the input runs on a default scene. */
        def = tb_scene_def_default();
        if (tb_scene_create(&def, &h->scene, &error) != TB_STATUS_OK) {
            abort();
        }
    } else if (error.message[0] != '\0') {
        fuzz_fail("tb_scene_create", "TB_STATUS_OK with message \"%s\"", error.message);
    }
}

static void operate(fuzz_harness *h)
{
    switch (fuzz_choice(h->in, 12)) {
    case 0:
    case 1:
        fuzz_op_add_body(h);
        break;
    case 2:
    case 3:
        fuzz_op_add_effect(h);
        break;
    case 4:
        fuzz_op_contact_points(h);
        break;
    case 5:
        fuzz_op_set_state(h);
        break;
    case 6:
        fuzz_op_mass(h);
        break;
    case 7:
        fuzz_op_create_integrator(h);
        break;
    case 8:
    case 9:
        fuzz_op_advance(h);
        break;
    case 10:
        fuzz_op_run(h);
        break;
    default: {
        const uint8_t which = fuzz_byte(h->in);
        if (which & 1) {
            fuzz_op_read(h);
        } else if (which & 64) {
            fuzz_op_differential(h);
        } else {
            fuzz_op_null_arguments(h);
        }
        break;
    }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input in = {data, size, 0};
    fuzz_harness h;
    memset(&h, 0, sizeof h);
    h.in = &in;
    const char *trace = getenv("TUMBLE_FUZZ_TRACE");
    h.trace = trace != NULL && trace[0] == '1';
    create_scene(&h);
    for (int op = 0;
         op < FUZZ_MAX_OPERATIONS && !fuzz_exhausted(&in) && h.evaluations < FUZZ_MAX_EVALUATIONS;
         ++op) {
        operate(&h);
    }
    for (int i = 0; i < FUZZ_MAX_INTEGRATORS; ++i) {
        tb_integrator_destroy(h.integrators[i]);
    }
    tb_scene_destroy(h.scene);
    return 0;
}
