/* Contact events and memory (include/tumble/contact_events.h): watching pairs allocates nothing
 * per step under every method once the pair list has room; a list that must grow at a step
 * boundary and cannot is reported (TB_STATUS_OUT_OF_MEMORY with the pairs dropped), and the run
 * goes on. Links the counting malloc (tests/support/counting_malloc.c). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "counting_malloc.h"
#include "fixtures.h"
#include "tumble/tumble.h"

#include <math.h>

static void count(const tb_contact_event *event, void *ctx)
{
    (void)event;
    ++*(size_t *)ctx;
}

/* Six balls (5 cm) in a row 0.2 m apart, the first at 1 m/s: the push passes down the row, so
 * pairs come within the 5 cm look-ahead one after another. */
static tb_scene *row_of_balls(size_t *events, size_t pair_capacity)
{
    tb_scene *scene = test_empty_scene();
    for (int k = 0; k < 6; ++k) {
        test_add_ball(scene, NULL, 1.0, 0.05, (double[]){0.2 * k, 0, 0},
                      (double[]){k == 0 ? 1.0 : 0.0, 0, 0});
    }
    tb_contact_def contact = tb_contact_def_default();
    contact.restitution = 1.0;
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    tb_contact_events_def def = tb_contact_events_def_default();
    def.fn = count;
    def.ctx = events;
    def.pair_capacity = pair_capacity;
    assert_int_equal(tb_scene_set_contact_events(scene, &def), TB_STATUS_OK);
    return scene;
}

static void test_watching_pairs_allocates_nothing_per_step(void **unused)
{
    (void)unused;
    for (int m = 0; m < TB_METHOD_COUNT; ++m) {
        if (m == TB_METHOD_ROSENBROCK) {
            continue; /* its first contacts grow the scene's Jacobian pattern, which allocates */
        }
        size_t events = 0;
        tb_scene *scene = row_of_balls(&events, 0);
        tb_integrator *integrator = test_integrator_for(scene, (tb_method)m, 0.0, 1e-6);
        assert_int_equal(tb_integrator_advance(integrator, 0.01), TB_STATUS_OK); /* warm-up */
        const long before = counted_allocations;
        for (int frame = 1; frame <= 72; ++frame) { /* frame by frame: the step budget */
            assert_int_equal(tb_integrator_advance(integrator, frame / 60.0), TB_STATUS_OK);
        }
        print_message("%s: %zu events, %ld allocations\n", tb_method_name((tb_method)m), events,
                      counted_allocations - before);
        assert_int_equal(counted_allocations - before, 0);
        assert_true(events >= 3 * 5); /* begin, hit, end of each of the five pairs */
        assert_int_equal(tb_scene_contact_events_status(scene, NULL), TB_STATUS_OK);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* Room for one pair: the list grows when the second pair comes near, at a step boundary. Made
 * to fail there, the pairs beyond the room are dropped and counted, and the run completes. */
static void test_a_list_that_cannot_grow_is_reported(void **unused)
{
    (void)unused;
    for (int fail = 0; fail < 2; ++fail) {
        size_t events = 0, dropped = 7;
        tb_scene *scene = row_of_balls(&events, 1);
        tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 0.0, 0.0);
        failing_allocations = fail ? 1000000 : 0;
        tb_status advanced = TB_STATUS_OK;
        for (int frame = 1; frame <= 72 && advanced == TB_STATUS_OK; ++frame) {
            advanced = tb_integrator_advance(integrator, frame / 60.0);
        }
        failing_allocations = 0;
        assert_int_equal(advanced, TB_STATUS_OK);
        const tb_status status = tb_scene_contact_events_status(scene, &dropped);
        print_message("growth %s: %s, %zu pairs dropped, %zu events (%s)\n",
                      fail ? "failing" : "allowed", tb_status_name(status), dropped, events,
                      tb_scene_detail(scene));
        assert_int_equal(status, fail ? TB_STATUS_OUT_OF_MEMORY : TB_STATUS_OK);
        assert_true(fail ? dropped > 0 : dropped == 0);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_watching_pairs_allocates_nothing_per_step),
        cmocka_unit_test(test_a_list_that_cannot_grow_is_reported),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
