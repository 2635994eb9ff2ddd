/* The joint calls given wrong input: each refused with its status, a detail naming the field,
 * and nothing changed (the scene's counts, states, joints and the integrator, which still
 * steps: the layout did not move). One row per case: add one by adding a row to BAD_INPUTS. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct fixture {
    tb_scene *scene;
    tb_integrator *integrator;
    tb_joint_def def; /* a valid hinge between bodies 1 and 0, changed by each row */
    tb_joint_def out; /* read-outs' outputs */
    double force[3], torque[3], value;
    bool broken;
    tb_joint_type type;
} fixture;

#define STATIC_BODY 2

static void set_up(fixture *f)
{
    memset(f, 0, sizeof *f);
    f->scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(f->scene, (double[]){0.0, 0.0, -9.81}), TB_STATUS_OK);
    test_add_ball(f->scene, NULL, 1.0, 0.1, (double[]){0.0, 0.0, -1.0}, NULL);
    test_add_ball(f->scene, NULL, 1.0, 0.1, (double[]){0.0, 0.0, -2.0}, NULL);
    tb_body_def table = tb_body_def_default();
    table.motion = TB_MOTION_STATIC;
    table.position[2] = 3.0;
    assert_int_equal(tb_scene_add_body(f->scene, &table, NULL), TB_STATUS_OK);
    tb_joint_def first = tb_joint_def_default();
    first.body_a = 0;
    assert_int_equal(tb_scene_add_joint(f->scene, &first, NULL), TB_STATUS_OK);
    f->integrator = test_integrator_for(f->scene, TB_METHOD_RK4, 1.0 / 240.0, 0.0);
    f->def = tb_joint_def_default();
    f->def.type = TB_JOINT_HINGE;
    f->def.body_a = 1;
    f->def.body_b = 0;
    f->def.anchor[2] = -1.5;
    f->def.axis[0] = 1.0;
}

/* label, expected status, a word the detail names ("" for none: no scene to hold it), call */
#define BAD_INPUTS(X)                                                                              \
    X("add_joint: NULL scene", NULL_POINTER, "", tb_scene_add_joint(NULL, &f->def, NULL))          \
    X("add_joint: NULL def", NULL_POINTER, "def", tb_scene_add_joint(f->scene, NULL, NULL))        \
    X("add_joint: def not from default", INVALID_ARGUMENT, "def",                                  \
      (f->def.internal_cookie = 0, tb_scene_add_joint(f->scene, &f->def, NULL)))                   \
    X("add_joint: unknown type", INVALID_ARGUMENT, "type",                                         \
      (f->def.type = TB_JOINT_TYPE_COUNT, tb_scene_add_joint(f->scene, &f->def, NULL)))            \
    X("add_joint: body_a out of range", OUT_OF_RANGE, "body_a",                                    \
      (f->def.body_a = 7, tb_scene_add_joint(f->scene, &f->def, NULL)))                            \
    X("add_joint: body_a the world", OUT_OF_RANGE, "body_a",                                       \
      (f->def.body_a = TB_WORLD, tb_scene_add_joint(f->scene, &f->def, NULL)))                     \
    X("add_joint: body_b out of range", OUT_OF_RANGE, "body_b",                                    \
      (f->def.body_b = 3, tb_scene_add_joint(f->scene, &f->def, NULL)))                            \
    X("add_joint: body_b == body_a", INVALID_ARGUMENT, "body_b",                                   \
      (f->def.body_b = 1, tb_scene_add_joint(f->scene, &f->def, NULL)))                            \
    X("add_joint: static body to the world", INVALID_ARGUMENT, "dynamic",                          \
      (f->def.body_a = STATIC_BODY, f->def.body_b = TB_WORLD,                                      \
       tb_scene_add_joint(f->scene, &f->def, NULL)))                                               \
    X("add_joint: hinge with a zero axis", INVALID_ARGUMENT, "axis",                               \
      (memset(f->def.axis, 0, sizeof f->def.axis), tb_scene_add_joint(f->scene, &f->def, NULL)))   \
    X("add_joint: NaN anchor", NOT_FINITE, "anchor",                                               \
      (f->def.anchor[1] = NAN, tb_scene_add_joint(f->scene, &f->def, NULL)))                       \
    X("add_joint: infinite axis", NOT_FINITE, "axis",                                              \
      (f->def.axis[2] = INFINITY, tb_scene_add_joint(f->scene, &f->def, NULL)))                    \
    X("add_joint: limits reversed", INVALID_ARGUMENT, "limits",                                    \
      (f->def.has_limits = 1, f->def.limits[0] = 1.0,                                              \
       tb_scene_add_joint(f->scene, &f->def, NULL)))                                               \
    X("add_joint: NaN limit", NOT_FINITE, "limits",                                                \
      (f->def.limits[1] = NAN, tb_scene_add_joint(f->scene, &f->def, NULL)))                       \
    X("add_joint: restitution above 1", INVALID_ARGUMENT, "restitution",                           \
      (f->def.has_limits = 1, f->def.restitution = 1.5,                                            \
       tb_scene_add_joint(f->scene, &f->def, NULL)))                                               \
    X("add_joint: restitution without limits", INVALID_ARGUMENT, "restitution",                    \
      (f->def.restitution = 0.5, tb_scene_add_joint(f->scene, &f->def, NULL)))                     \
    X("add_joint: motor without max force", INVALID_ARGUMENT, "motor",                             \
      (f->def.motor = TB_MOTOR_VELOCITY, tb_scene_add_joint(f->scene, &f->def, NULL)))             \
    X("add_joint: motor on a ball joint", INVALID_ARGUMENT, "motor",                               \
      (f->def.type = TB_JOINT_BALL, f->def.motor = TB_MOTOR_VELOCITY,                              \
       f->def.motor_max_force = 1.0, tb_scene_add_joint(f->scene, &f->def, NULL)))                 \
    X("add_joint: NaN break_force", NOT_FINITE, "break_force",                                     \
      (f->def.break_force = NAN, tb_scene_add_joint(f->scene, &f->def, NULL)))                     \
    X("add_joint: zero break_torque", INVALID_ARGUMENT, "break_torque",                            \
      (f->def.break_torque = 0.0, tb_scene_add_joint(f->scene, &f->def, NULL)))                    \
    X("add_joint: negative soft_frequency", INVALID_ARGUMENT, "soft_frequency",                    \
      (f->def.soft_frequency = -1.0, tb_scene_add_joint(f->scene, &f->def, NULL)))                 \
    X("set_joint_motor: on a ball joint", INVALID_ARGUMENT, "motor",                               \
      tb_scene_set_joint_motor(f->scene, 0, TB_MOTOR_VELOCITY, 1.0, 1.0))                          \
    X("set_joint_motor: unknown mode", INVALID_ARGUMENT, "motor",                                  \
      tb_scene_set_joint_motor(f->scene, 0, (tb_joint_motor_mode)7, 1.0, 1.0))                     \
    X("set_joint_motor: NaN speed", NOT_FINITE, "motor_speed",                                     \
      tb_scene_set_joint_motor(f->scene, 0, TB_MOTOR_VELOCITY, NAN, 1.0))                          \
    X("set_joint_motor: index out of range", OUT_OF_RANGE, "joint",                                \
      tb_scene_set_joint_motor(f->scene, 4, TB_MOTOR_VELOCITY, 1.0, 1.0))                          \
    X("joint_axial: a ball joint", INVALID_ARGUMENT, "hinge or slider",                            \
      tb_scene_joint_axial(f->scene, tb_scene_states_const(f->scene), 0, &f->value, NULL, NULL))   \
    X("joint_axial: NULL y", NULL_POINTER, "y",                                                    \
      tb_scene_joint_axial(f->scene, NULL, 0, &f->value, NULL, NULL))                              \
    X("add_joint: a hinge's limit past pi", INVALID_ARGUMENT, "limits",                            \
      (f->def.has_limits = 1, f->def.limits[1] = 4.0,                                              \
       tb_scene_add_joint(f->scene, &f->def, NULL)))                                               \
    X("add_joint: damping on a rigid joint", INVALID_ARGUMENT, "soft_damping_ratio",               \
      (f->def.soft_damping_ratio = 0.5, tb_scene_add_joint(f->scene, &f->def, NULL)))              \
    X("add_joint: infinite soft_frequency", NOT_FINITE, "soft_frequency",                          \
      (f->def.soft_frequency = INFINITY, tb_scene_add_joint(f->scene, &f->def, NULL)))             \
    X("joint_def: index out of range", OUT_OF_RANGE, "joint",                                      \
      tb_scene_joint_def(f->scene, 1, &f->out))                                                    \
    X("joint_def: NULL out_def", NULL_POINTER, "out_def", tb_scene_joint_def(f->scene, 0, NULL))   \
    X("joint_error: NULL y", NULL_POINTER, "y",                                                    \
      tb_scene_joint_error(f->scene, NULL, 0, &f->value, NULL))                                    \
    X("joint_error: index out of range", OUT_OF_RANGE, "joint",                                    \
      tb_scene_joint_error(f->scene, tb_scene_states_const(f->scene), 5, &f->value, NULL))         \
    X("joint_reaction: NULL out_torque", NULL_POINTER, "out_torque",                               \
      tb_scene_joint_reaction(f->scene, tb_scene_states_const(f->scene), 0, f->force, NULL))       \
    X("joint_reaction: index out of range", OUT_OF_RANGE, "joint",                                 \
      tb_scene_joint_reaction(f->scene, tb_scene_states_const(f->scene), 1, f->force, f->torque))  \
    X("joint_broken: NULL out_broken", NULL_POINTER, "out_broken",                                 \
      tb_scene_joint_broken(f->scene, 0, NULL))                                                    \
    X("joint_type_from_name: capitalised", INVALID_ARGUMENT, "",                                   \
      tb_joint_type_from_name("Ball", &f->type))                                                   \
    X("joint_type_from_name: NULL", NULL_POINTER, "", tb_joint_type_from_name(NULL, &f->type))     \
    X("project_joints: NULL scene", NULL_POINTER, "", tb_scene_project_joints(NULL, 0.0, NULL))    \
    X("project_joints: negative tolerance", INVALID_ARGUMENT, "tolerance",                         \
      tb_scene_project_joints(f->scene, -1e-9, &f->value))                                         \
    X("project_joints: NaN tolerance", NOT_FINITE, "tolerance",                                    \
      tb_scene_project_joints(f->scene, NAN, &f->value))

static tb_status attempt(size_t i, fixture *f)
{
    size_t row = 0;
#define AS_CASE(label, status, word, call)                                                         \
    if (row++ == i) {                                                                              \
        return call;                                                                               \
    }
    BAD_INPUTS(AS_CASE)
#undef AS_CASE
    fail();
    return TB_STATUS_OK;
}

static const struct {
    const char *label;
    tb_status expected;
    const char *word;
} cases[] = {
#define AS_ROW(label, status, word, call) {label, TB_STATUS_##status, word},
    BAD_INPUTS(AS_ROW)
#undef AS_ROW
};

typedef struct snapshot {
    size_t bodies, effects, joints, size;
    double states[3 * TB_STATE_SIZE];
    tb_joint_def first;
    double time;
    tb_joint_def out;
    tb_joint_type type;
} snapshot;

static void take(const fixture *f, snapshot *s)
{
    memset(s, 0, sizeof *s);
    s->bodies = tb_scene_body_count(f->scene);
    s->effects = tb_scene_effect_count(f->scene);
    s->joints = tb_scene_joint_count(f->scene);
    s->size = tb_scene_state_size(f->scene);
    memcpy(s->states, tb_scene_states_const(f->scene), s->size * sizeof(double));
    assert_int_equal(tb_scene_joint_def(f->scene, 0, &s->first), TB_STATUS_OK);
    s->time = tb_integrator_time(f->integrator);
    s->out = f->out;
    s->type = f->type;
}

static void test_every_joint_call_refuses_bad_input_and_changes_nothing(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        fixture f;
        set_up(&f);
        snapshot before, after;
        take(&f, &before);
        const tb_status status = attempt(i, &f);
        const char *detail = tb_scene_detail(f.scene);
        print_message("%-40s -> %s: %s\n", cases[i].label, tb_status_name(status), detail);
        assert_int_equal(status, cases[i].expected);
        assert_non_null(strstr(detail, cases[i].word));
        take(&f, &after);
        assert_memory_equal(&before, &after, sizeof before);
        /* the layout did not move: the integrator made before still steps */
        assert_int_equal(tb_integrator_advance(f.integrator, 0.1), TB_STATUS_OK);
        tb_integrator_destroy(f.integrator);
        tb_scene_destroy(f.scene);
    }
}

/* An integrator made before a joint was added refuses to step (the layout's generation). */
static void test_integrator_made_before_a_joint_refuses_to_step(void **state)
{
    (void)state;
    fixture f;
    set_up(&f);
    size_t id = 0;
    assert_int_equal(tb_scene_add_joint(f.scene, &f.def, &id), TB_STATUS_OK);
    assert_int_equal(id, 1);
    assert_int_equal(tb_integrator_advance(f.integrator, 0.1), TB_STATUS_LAYOUT_CHANGED);
    assert_string_equal(tb_joint_type_name(TB_JOINT_TYPE_COUNT), "unknown");
    tb_joint_type type = TB_JOINT_BALL;
    assert_int_equal(tb_joint_type_from_name("slider", &type), TB_STATUS_OK);
    assert_int_equal(type, TB_JOINT_SLIDER);
    tb_integrator_destroy(f.integrator);
    tb_scene_destroy(f.scene);
}

/* A user effect that adds a joint from inside the derivative: refused as busy, nothing added. */
static int add_joint_inside(double t, const tb_scene *scene, const double *y, double *dydt,
                            void *ctx)
{
    (void)t, (void)y, (void)dydt;
    tb_status *status = ctx;
    tb_joint_def def = tb_joint_def_default();
    def.body_a = 1;
    *status = tb_scene_add_joint((tb_scene *)scene, &def, NULL);
    return 0;
}

static void test_adding_a_joint_while_stepping_is_busy(void **state)
{
    (void)state;
    fixture f;
    set_up(&f);
    tb_status inside = TB_STATUS_OK;
    assert_int_equal(tb_scene_add_user_effect(f.scene, add_joint_inside, &inside), TB_STATUS_OK);
    tb_integrator *integrator = test_integrator_for(f.scene, TB_METHOD_RK4, 1.0 / 240.0, 0.0);
    assert_int_equal(tb_integrator_advance(integrator, 0.01), TB_STATUS_OK);
    assert_int_equal(inside, TB_STATUS_BUSY);
    assert_int_equal(tb_scene_joint_count(f.scene), 1);
    tb_integrator_destroy(integrator);
    tb_integrator_destroy(f.integrator);
    tb_scene_destroy(f.scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_joint_call_refuses_bad_input_and_changes_nothing),
        cmocka_unit_test(test_integrator_made_before_a_joint_refuses_to_step),
        cmocka_unit_test(test_adding_a_joint_while_stepping_is_busy),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
