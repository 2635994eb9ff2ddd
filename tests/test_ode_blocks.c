/* Separable systems (tb_ode_system.blocks.size): fixed-step methods that finish each step a chunk
 * of blocks at a time, in the blocks' layout or in lane layout (tb_ode_system.blocks.lanes), on one
 * thread or several, give what stepping the whole array gives, and a failure in any chunk
 * leaves every block as it was before the step. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "near.h"
#include "tumble/ode.h"

#include <float.h>
#include <math.h>
#include <string.h>

/* Euler, midpoint and RK4: the fixed-step methods come first in tb_method. */
#define FIXED_STEP_METHODS (TB_METHOD_RK4 + 1)

/* 1000 blocks of 3 (3000 components): many chunks and a partial last one for any chunk size
 * the stepper may pick below 3000 doubles. */
#define BLOCKS 1000
#define SIZE 3

/* Block b: an oscillator x' = v, v' = -w^2 x and a decay z' = -w z, w = 1 + b / BLOCKS, so
 * every block differs and a block given the wrong index gives a different answer. */
typedef struct blocks {
    size_t fail_block; /* this block fails from fail_time on ... */
    double fail_time;
    enum {
        NO_FAILURE,
        DERIVATIVE_FAILS,
        HOOK_FAILS,
        BLOWS_UP,
        BLOWS_UP_AND_HOOK_FAILS /* the hook fails on the non-finite z, as a scene's on a NaN q */
    } failure;
} blocks;

static double rate(size_t b)
{
    return 1.0 + (double)b / BLOCKS;
}

static int block_derivative(double t, const double *y, double *dydt, size_t first, size_t count,
                            void *ctx)
{
    const blocks *setup = ctx;
    for (size_t i = 0; i < count; ++i) {
        const size_t b = first + i;
        const double w = rate(b), *s = y + SIZE * i;
        double *d = dydt + SIZE * i;
        d[0] = s[1];
        d[1] = -w * w * s[0];
        d[2] = -w * s[2];
        if (b == setup->fail_block && t >= setup->fail_time) {
            if (setup->failure == DERIVATIVE_FAILS) {
                return 5;
            }
            if (setup->failure == BLOWS_UP || setup->failure == BLOWS_UP_AND_HOOK_FAILS) {
                d[2] = INFINITY;
            }
        }
    }
    return 0;
}

static int whole_derivative(double t, const double *y, double *dydt, void *ctx)
{
    return block_derivative(t, y, dydt, 0, BLOCKS, ctx);
}

/* A projection after each step: (x, v) back onto its block's energy ellipse
 * w^2 x^2 + v^2 = w^2 (the start x = 1, v = 0), as the scene renormalises quaternions. */
static int block_hook(double t, double *y, size_t first, size_t count, void *ctx)
{
    const blocks *setup = ctx;
    for (size_t i = 0; i < count; ++i) {
        const size_t b = first + i;
        const double w = rate(b);
        double *s = y + SIZE * i;
        const double scale = w / sqrt(w * w * s[0] * s[0] + s[1] * s[1]);
        s[0] *= scale;
        s[1] *= scale;
        if (b == setup->fail_block && t >= setup->fail_time && setup->failure == HOOK_FAILS) {
            return 3;
        }
        if (setup->failure == BLOWS_UP_AND_HOOK_FAILS && !isfinite(s[2])) {
            return 3;
        }
    }
    return 0;
}

static int whole_hook(double t, double *y, void *ctx)
{
    return block_hook(t, y, 0, BLOCKS, ctx);
}

/* The lane forms: each lane gathered into a block and handed to the block functions, so the
 * arithmetic is theirs (what a system's lane forms must guarantee). */
#define LANES 16

static int lanes_apply(double t, double *y, double *dydt, size_t first, size_t count, void *ctx,
                       int hook)
{
    int rc = 0;
    for (size_t j = 0; j < count && rc == 0; ++j) {
        double s[SIZE], d[SIZE];
        for (size_t c = 0; c < SIZE; ++c) {
            s[c] = y[c * LANES + j];
        }
        rc = hook ? block_hook(t, s, first + j, 1, ctx)
                  : block_derivative(t, s, d, first + j, 1, ctx);
        for (size_t c = 0; c < SIZE; ++c) {
            if (hook) {
                y[c * LANES + j] = s[c];
            } else {
                dydt[c * LANES + j] = d[c];
            }
        }
    }
    return rc;
}

static int lanes_derivative(double t, const double *y, double *dydt, size_t first, size_t count,
                            void *ctx)
{
    return lanes_apply(t, (double *)y, dydt, first, count, ctx, 0);
}

static int lanes_hook(double t, double *y, size_t first, size_t count, void *ctx)
{
    return lanes_apply(t, y, NULL, first, count, ctx, 1);
}

static void start(double *y)
{
    for (size_t b = 0; b < BLOCKS; ++b) {
        y[SIZE * b] = 1.0;
        y[SIZE * b + 1] = 0.0;
        y[SIZE * b + 2] = 1.0;
    }
}

/* How a variant steps: the whole array, chunks in the blocks' layout, chunks in lane layout. */
enum { WHOLE, CHUNKED, LANE_CHUNKS };

static tb_integrator *make_on(tb_method method, int layout, int threads, blocks *setup, double *y)
{
    tb_ode_system system = {
        .n = SIZE * BLOCKS, .derivative = whole_derivative, .post_step = whole_hook, .ctx = setup};
    if (layout != WHOLE) {
        system.blocks.size = SIZE;
        system.blocks.derivative = block_derivative;
        system.blocks.post_step = block_hook;
    }
    if (layout == LANE_CHUNKS) {
        system.blocks.lanes = LANES;
        system.blocks.lanes_derivative = lanes_derivative;
        system.blocks.lanes_post_step = lanes_hook;
    }
    tb_integrator_def def = tb_integrator_def_default();
    def.method = method;
    def.dt = 0.01;
    def.threads = threads;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_integrator_create(&system, &def, 0.0, y, &integrator, NULL), TB_STATUS_OK);
    return integrator;
}

static tb_integrator *make(tb_method method, int chunked, blocks *setup, double *y)
{
    return make_on(method, chunked ? CHUNKED : WHOLE, 1, setup, y);
}

/* The chunked variants: layout and threads (3 does not divide the chunks evenly; 2 threads are
 * tested on scenes in test_vector_paths). */
static const struct {
    int layout, threads;
} variants[] = {{CHUNKED, 1}, {LANE_CHUNKS, 1}, {LANE_CHUNKS, 3}};
#define VARIANTS (sizeof variants / sizeof variants[0])

/* Every path does the same arithmetic on every component in the same order (the library is
 * built without contraction into FMA), and the chunks are the same for any thread count, so they
 * agree to the last bit. RK4 also meets the exact decay z = exp(-w t) to 1e-8 (its error at
 * w h <= 0.02 over 2 s is ~1e-10), which a block stepped with another block's index, or a lane
 * with another lane's, would miss by up to 1e-1. */
static void test_chunked_steps_equal_whole_array_steps(void **state)
{
    (void)state;
    static double whole[SIZE * BLOCKS], chunked[SIZE * BLOCKS];
    for (size_t v = 0; v < VARIANTS * FIXED_STEP_METHODS; ++v) {
        const int m = (int)(v / VARIANTS);
        blocks setup = {.failure = NO_FAILURE};
        start(whole);
        start(chunked);
        tb_integrator *a = make((tb_method)m, 0, &setup, whole);
        tb_integrator *b = make_on((tb_method)m, variants[v % VARIANTS].layout,
                                   variants[v % VARIANTS].threads, &setup, chunked);
        assert_int_equal(tb_integrator_advance(a, 2.0), TB_STATUS_OK);
        assert_int_equal(tb_integrator_advance(b, 2.0), TB_STATUS_OK);
        double largest = 0.0;
        for (size_t i = 0; i < SIZE * BLOCKS; ++i) {
            largest = fmax(largest, fabs(chunked[i] - whole[i]));
        }
        assert_memory_equal(chunked, whole, sizeof whole);
        tb_integrator_stats sa, sb;
        tb_integrator_get_stats(a, &sa);
        tb_integrator_get_stats(b, &sb);
        print_message("%-8s layout %d, %d threads: largest difference %.3g, %ld steps, %ld "
                      "evaluations\n",
                      tb_method_name((tb_method)m), variants[v % VARIANTS].layout,
                      variants[v % VARIANTS].threads, largest, sb.steps, sb.derivative_evals);
        assert_int_equal(sa.steps, sb.steps);
        assert_int_equal(sa.derivative_evals, sb.derivative_evals);
        if (m == TB_METHOD_RK4) {
            for (size_t k = 0; k < BLOCKS; ++k) {
                assert_near(chunked[SIZE * k + 2], exp(-2.0 * rate(k)), 1e-8);
            }
        }
        tb_integrator_destroy(a);
        tb_integrator_destroy(b);
    }
}

/* Block 900 lies in a late chunk: earlier chunks were already written when it fails, and must
 * be put back. The state after the failure is bit for bit the state at the last good step. */
static void test_a_failure_in_a_late_chunk_leaves_every_block_as_it_was(void **state)
{
    (void)state;
    static const struct {
        int failure;
        tb_status status;
        const char *detail;
    } cases[] = {
        {DERIVATIVE_FAILS, TB_STATUS_DERIVATIVE_FAILED, "returned 5"},
        {HOOK_FAILS, TB_STATUS_HOOK_FAILED, "hook returned 3"},
        {BLOWS_UP, TB_STATUS_STATE_NOT_FINITE, "y[2702]"}, /* z of block 900 */
        /* the cause, not the hook that failed on it (was HOOK_FAILED) */
        {BLOWS_UP_AND_HOOK_FAILS, TB_STATUS_STATE_NOT_FINITE, "y[2702] became inf"},
    };
    static double y[SIZE * BLOCKS], last_good[SIZE * BLOCKS];
    for (size_t v = 0; v < VARIANTS * FIXED_STEP_METHODS; ++v) {
        const int m = (int)(v / VARIANTS);
        for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
            blocks setup = {.fail_block = 900, .fail_time = 0.0505, .failure = cases[k].failure};
            start(y);
            tb_integrator *integrator = make_on((tb_method)m, variants[v % VARIANTS].layout,
                                                variants[v % VARIANTS].threads, &setup, y);
            /* steps of 0.01 from 0: the derivative first sees t >= 0.0505 in the step from
             * 0.05 (midpoint's and RK4's stage at t + h/2) or from 0.06 (Euler's only stage at
             * t); the hook, at the end of the step from 0.05 */
            const double good =
                m == TB_METHOD_EULER && cases[k].failure != HOOK_FAILS ? 0.06 : 0.05;
            assert_int_equal(tb_integrator_advance(integrator, good), TB_STATUS_OK);
            memcpy(last_good, y, sizeof y);
            assert_int_equal(tb_integrator_advance(integrator, 1.0), cases[k].status);
            print_message("%-8s layout %d, %d threads: %-40s at t = %g\n",
                          tb_method_name((tb_method)m), variants[v % VARIANTS].layout,
                          variants[v % VARIANTS].threads, tb_integrator_detail(integrator),
                          tb_integrator_time(integrator));
            assert_near(tb_integrator_time(integrator), good, 1e-15);
            assert_memory_equal(y, last_good, sizeof y);
            assert_non_null(strstr(tb_integrator_detail(integrator), cases[k].detail));
            tb_integrator_destroy(integrator);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_chunked_steps_equal_whole_array_steps),
        cmocka_unit_test(test_a_failure_in_a_late_chunk_leaves_every_block_as_it_was),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
