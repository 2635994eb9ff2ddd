/* The contact pass a step boundary keeps for the derivative at the same (t, y)
 * (src/effects/contact_pass_memo.h): the derivative stays a pure function of (t, y). Where the
 * kept pass is taken, its derivative is the same bits as the full pass gives (the same state at
 * another t, which the contact does not read: no keyframed body); where the state differs from
 * the kept one by a millimetre, the kept pass is not taken and the forces are those of the new
 * state. Bits, not a tolerance: the same (t, y) must give the same bits whatever was evaluated
 * before (docs/contact.md). Reads the contact effect's memo (private) to see it taken. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "effects/contact_pass_memo.h"
#include "effects/effect_contact.h"
#include "fixtures.h"
#include "tumble/tumble.h"

#include <math.h>
#include <string.h>

#define MAX_STATES 4096

static const double cube[3] = {0.1, 0.1, 0.1}; /* m, 1 kg */

/* Two cubes stacked on a ground plane and a third beside the bottom one, 0.5 mm away (within
 * the contact's 1 mm margin: a pair listed, not touching). */
static tb_scene *stack_scene(void)
{
    tb_scene *scene = test_empty_scene();
    test_add_box(scene, 1.0, cube, (double[]){0.0, 0.0, 0.05});
    test_add_box(scene, 1.0, cube, (double[]){0.0, 0.0, 0.15});
    test_add_box(scene, 1.0, cube, (double[]){0.1005, 0.0, 0.05});
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -9.81}), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    tb_contact_def contact = tb_contact_def_default();
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    return scene;
}

static const tb__pass_memo *contact_memo(const tb_scene *scene)
{
    for (size_t k = 0; k < scene->effect_count; ++k) {
        if (strcmp(scene->effects[k].ops->name, "contact") == 0) {
            return tb__contact_of(&scene->effects[k])->memo;
        }
    }
    fail_msg("no contact effect");
    return NULL;
}

static void test_the_kept_pass_gives_the_full_pass_bits(void **state)
{
    (void)state;
    tb_scene *scene = stack_scene();
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 0.0, 1e-6);
    assert_int_equal(tb_integrator_advance(integrator, 0.05), TB_STATUS_OK);
    const size_t n = tb_scene_state_size(scene);
    assert_true(n <= MAX_STATES);
    static double y[MAX_STATES], moved[MAX_STATES], kept[MAX_STATES], full[MAX_STATES],
        moved_kept_t[MAX_STATES], moved_other_t[MAX_STATES], again[MAX_STATES];
    memcpy(y, tb_scene_states_const(scene), n * sizeof(double));
    const double t = tb_scene_time(scene), other = t + 1e-3;
    const tb__pair_contact *pairs = NULL;
    size_t count = 0;
    /* the last step's boundary kept its pass at the state the run stopped at */
    assert_true(tb__pass_memo_at(contact_memo(scene), scene, t, y, &pairs, &count));
    assert_true(count >= 2); /* the stacked pair touching, the side pair within the margin */
    assert_int_equal(tb_scene_derivative(t, y, kept, scene), 0);
    assert_int_equal(tb_scene_derivative(other, y, full, scene), 0);
    assert_memory_equal(kept, full, n * sizeof(double));
    /* the top cube 1 mm lower, into the bottom one: not the kept state */
    memcpy(moved, y, n * sizeof(double));
    moved[TB_STATE_SIZE * 1 + TB_STATE_X + 2] -= 1e-3;
    assert_false(tb__pass_memo_at(contact_memo(scene), scene, t, moved, &pairs, &count));
    assert_int_equal(tb_scene_derivative(t, moved, moved_kept_t, scene), 0);
    assert_int_equal(tb_scene_derivative(other, moved, moved_other_t, scene), 0);
    assert_memory_equal(moved_kept_t, moved_other_t, n * sizeof(double));
    /* pushed up by far more than its weight (9.81 N): 1 mm is 1250 penetrations */
    const size_t top_pz = TB_STATE_SIZE * 1 + TB_STATE_P + 2;
    assert_true(moved_kept_t[top_pz] > kept[top_pz] + 100.0);
    /* and the kept pass is still taken at its own (t, y) */
    assert_int_equal(tb_scene_derivative(t, y, again, scene), 0);
    assert_memory_equal(kept, again, n * sizeof(double));
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_the_kept_pass_gives_the_full_pass_bits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
