/* The integrator's side of a system's lifetime hooks (layout_generation, acquire, release) and
 * its refusal of re-entrant calls, on every method and on the whole-array and chunked paths,
 * with a toy system whose hooks the test controls. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "near.h"
#include "tumble/ode.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* What the derivative or the hook does to its own integrator. */
typedef enum reentry { NONE, ADVANCE, STEP, RESET } reentry;

typedef struct toy {
    unsigned long long generation; /* the system's layout generation now */
    tb_status refuse;              /* acquire's answer when the generation matches */
    int acquired, granted, released;
    int fail_derivative; /* non-zero: the derivative returns it */
    reentry from_derivative, from_hook;
    tb_status reentry_status; /* what the last re-entrant call returned */
    int reentries;
    tb_integrator *integrator;
} toy;

static tb_status call_again(toy *t, reentry how)
{
    ++t->reentries;
    switch (how) {
    case ADVANCE:
        return tb_integrator_advance(t->integrator, 100.0);
    case STEP:
        return tb_integrator_step(t->integrator);
    default:
        return tb_integrator_reset(t->integrator, 0.0);
    }
}

/* y' = -y per component: separable, exact solution exp(-t). */
static int decay(double t, const double *y, double *dydt, void *ctx)
{
    (void)t;
    toy *system = ctx;
    if (system->from_derivative != NONE && system->integrator != NULL) {
        system->reentry_status = call_again(system, system->from_derivative);
    }
    for (size_t i = 0; i < 4; ++i) {
        dydt[i] = -y[i];
    }
    return system->fail_derivative;
}

static int decay_blocks(double t, const double *y, double *dydt, size_t first, size_t count,
                        void *ctx)
{
    (void)t, (void)first;
    toy *system = ctx;
    for (size_t i = 0; i < 2 * count; ++i) {
        dydt[i] = -y[i];
    }
    return system->fail_derivative;
}

static int hook(double t, double *y, void *ctx)
{
    (void)t, (void)y;
    toy *system = ctx;
    if (system->from_hook != NONE) {
        system->reentry_status = call_again(system, system->from_hook);
    }
    return 0;
}

static int block_hook(double t, double *y, size_t first, size_t count, void *ctx)
{
    (void)first, (void)count;
    return hook(t, y, ctx);
}

static unsigned long long generation(void *ctx)
{
    return ((toy *)ctx)->generation;
}

static tb_status acquire(void *ctx, unsigned long long made_at, char *detail)
{
    toy *t = ctx;
    ++t->acquired;
    if (made_at != t->generation) {
        snprintf(detail, TB_DETAIL_SIZE, "toy: layout %llu, integrator made on %llu", t->generation,
                 made_at);
        return TB_STATUS_LAYOUT_CHANGED;
    }
    if (t->refuse != TB_STATUS_OK) {
        snprintf(detail, TB_DETAIL_SIZE, "toy: stepped by another integrator");
        return t->refuse;
    }
    ++t->granted;
    return TB_STATUS_OK;
}

static void release(void *ctx)
{
    toy *t = ctx;
    ++t->released;
    assert_true(t->released <= t->granted); /* never a release without a granted acquire */
}

typedef struct setup {
    toy toy;
    double y[4];
    tb_ode_system system;
    tb_integrator *integrator;
} setup;

/* chunked: declare the system separable (blocks of 2), so fixed-step methods take the chunked
 * path. */
static void make(setup *s, tb_method method, int chunked)
{
    memset(s, 0, sizeof *s);
    s->toy.generation = 7;
    for (int i = 0; i < 4; ++i) {
        s->y[i] = 1.0;
    }
    s->system = (tb_ode_system){
        .n = 4,
        .derivative = decay,
        .post_step = hook,
        .ctx = &s->toy,
        .lifetime = {.layout_generation = generation, .acquire = acquire, .release = release}};
    if (chunked) {
        s->system.blocks.size = 2;
        s->system.blocks.derivative = decay_blocks;
        s->system.blocks.post_step = block_hook;
    }
    tb_integrator_def def = tb_integrator_def_default();
    def.method = method;
    if (!tb_method_is_adaptive(method)) {
        def.dt = 0.01;
    }
    assert_int_equal(tb_integrator_create(&s->system, &def, 0.0, s->y, &s->integrator, NULL),
                     TB_STATUS_OK);
    s->toy.integrator = s->integrator;
}

static void test_every_call_acquires_once_and_releases_what_it_acquired(void **state)
{
    (void)state;
    for (int m = 0; m < TB_METHOD_COUNT; ++m) {
        for (int chunked = 0; chunked <= 1; ++chunked) {
            setup s;
            make(&s, (tb_method)m, chunked);
            assert_int_equal(s.toy.acquired, 0); /* creation steps nothing */
            assert_int_equal(tb_integrator_advance(s.integrator, 0.5), TB_STATUS_OK);
            assert_int_equal(tb_integrator_step(s.integrator), TB_STATUS_OK);
            assert_int_equal(tb_integrator_reset(s.integrator, 1.0), TB_STATUS_OK);
            assert_int_equal(s.toy.acquired, 3);
            assert_int_equal(s.toy.released, 3);
            /* a failing call releases too */
            s.toy.fail_derivative = -3;
            assert_int_equal(tb_integrator_advance(s.integrator, 2.0), TB_STATUS_DERIVATIVE_FAILED);
            assert_int_equal(tb_integrator_advance(s.integrator, NAN), TB_STATUS_NOT_FINITE);
            assert_int_equal(s.toy.acquired, 5);
            assert_int_equal(s.toy.released, 5);
            tb_integrator_destroy(s.integrator);
        }
    }
}

static void expect_refusal(setup *s, tb_status expected, const char *why)
{
    double before[4];
    memcpy(before, s->y, sizeof before);
    const double t = tb_integrator_time(s->integrator);
    const int granted = s->toy.granted, released = s->toy.released;
    assert_int_equal(tb_integrator_advance(s->integrator, 1.0), expected);
    assert_non_null(strstr(tb_integrator_detail(s->integrator), why));
    assert_int_equal(tb_integrator_step(s->integrator), expected);
    assert_int_equal(tb_integrator_reset(s->integrator, 0.0), expected);
    assert_non_null(strstr(tb_integrator_detail(s->integrator), why));
    assert_memory_equal(s->y, before, sizeof before);
    assert_true(tb_integrator_time(s->integrator) == t);
    assert_int_equal(s->toy.granted, granted);
    assert_int_equal(s->toy.released, released);
}

static void test_a_changed_layout_or_a_busy_system_refuses_and_changes_nothing(void **state)
{
    (void)state;
    for (int m = 0; m < TB_METHOD_COUNT; ++m) {
        for (int chunked = 0; chunked <= 1; ++chunked) {
            setup s;
            make(&s, (tb_method)m, chunked);
            assert_int_equal(tb_integrator_advance(s.integrator, 0.25), TB_STATUS_OK);
            s.toy.refuse = TB_STATUS_BUSY;
            expect_refusal(&s, TB_STATUS_BUSY, "stepped by another integrator");
            s.toy.refuse = TB_STATUS_OK;
            s.toy.generation = 8;
            expect_refusal(&s, TB_STATUS_LAYOUT_CHANGED, "toy: layout 8, integrator made on 7");
            s.toy.generation = 7; /* back on its layout, it steps again */
            assert_int_equal(tb_integrator_advance(s.integrator, 0.5), TB_STATUS_OK);
            tb_integrator_destroy(s.integrator);
        }
    }
}

/* An integrator called from its own derivative or hook refuses with BUSY and changes nothing;
 * the call in progress goes on to the right answer (exp(-t) to the method's accuracy: 5e-3
 * covers Euler's global error at h = 0.01 over 0.5 s, 0.5 h t exp(-t) = 1.5e-3). */
static void test_a_call_from_inside_its_own_derivative_or_hook_is_refused(void **state)
{
    (void)state;
    static const reentry ways[] = {ADVANCE, STEP, RESET};
    for (int m = 0; m < TB_METHOD_COUNT; ++m) {
        for (size_t w = 0; w < 6; ++w) {
            setup s;
            make(&s, (tb_method)m, 0);
            if (w < 3) {
                s.toy.from_derivative = ways[w];
            } else {
                s.toy.from_hook = ways[w - 3];
            }
            s.toy.reentry_status = TB_STATUS_OK;
            assert_int_equal(tb_integrator_advance(s.integrator, 0.5), TB_STATUS_OK);
            assert_true(s.toy.reentries > 0);
            assert_int_equal(s.toy.reentry_status, TB_STATUS_BUSY);
            assert_true(tb_integrator_time(s.integrator) == 0.5);
            assert_near(s.y[0], exp(-0.5), 5e-3);
            assert_string_equal(tb_integrator_detail(s.integrator), "");
            assert_int_equal(s.toy.acquired, 1); /* the refused calls acquired nothing */
            assert_int_equal(s.toy.released, 1);
            tb_integrator_destroy(s.integrator);
        }
    }
}

/* Hooks come as a set: acquire without release would leave the system busy for ever. */
static void test_lifetime_hooks_come_together(void **state)
{
    (void)state;
    setup s;
    make(&s, TB_METHOD_RK4, 0);
    tb_integrator_destroy(s.integrator);
    s.system.lifetime.release = NULL;
    tb_integrator_def def = tb_integrator_def_default();
    tb_integrator *integrator = NULL;
    tb_error error;
    assert_int_equal(tb_integrator_create(&s.system, &def, 0.0, s.y, &integrator, &error),
                     TB_STATUS_NULL_POINTER);
    assert_non_null(strstr(error.message, "system.lifetime.release is NULL"));
    assert_null(integrator);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_call_acquires_once_and_releases_what_it_acquired),
        cmocka_unit_test(test_a_changed_layout_or_a_busy_system_refuses_and_changes_nothing),
        cmocka_unit_test(test_a_call_from_inside_its_own_derivative_or_hook_is_refused),
        cmocka_unit_test(test_lifetime_hooks_come_together),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
