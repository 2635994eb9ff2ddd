/* The C-API fuzz target's read-outs (any id, any method, the derivative called directly) and
 * NULL arguments: a NULL required pointer gives TB_STATUS_NULL_POINTER, a detail that says so
 * (not the previous failure's), and changes nothing. */
#include "fuzz_api.h"

#include <stdlib.h>

static void check_read(const fuzz_harness *h, tb_status status, const char *call)
{
    fuzz_check(h, NULL, status, NULL, call, FUZZ_UNCHANGED);
}

static void read_body(fuzz_harness *h, const double *y)
{
    const size_t id = fuzz_body_id(h);
    double out[9], orientation[4];
    tb_body_state state;
    tb_mass_properties mass;
    fuzz_trace(h, "/* read-outs of body %s */", fuzz_c_id(id));
    check_read(h, tb_scene_body_rotation(h->scene, y, id, out), "tb_scene_body_rotation");
    check_read(h, tb_scene_body_velocity(h->scene, y, id, out), "tb_scene_body_velocity");
    check_read(h, tb_scene_body_angular_velocity(h->scene, y, id, out),
               "tb_scene_body_angular_velocity");
    check_read(h, tb_scene_body_shape_pose(h->scene, y, id, out, orientation),
               "tb_scene_body_shape_pose");
    check_read(h, tb_scene_get_state(h->scene, id, &state), "tb_scene_get_state");
    check_read(h, tb_scene_get_mass(h->scene, id, &mass), "tb_scene_get_mass");
    const char *name = tb_scene_body_name(h->scene, id);
    if ((name == NULL) != (id >= tb_scene_body_count(h->scene))) {
        fuzz_fail("tb_scene_body_name", "id %zu of %zu gave %s", id, tb_scene_body_count(h->scene),
                  name ? name : "NULL");
    }
    size_t found;
    if (name != NULL &&
        (tb_scene_find_body(h->scene, name, &found) != TB_STATUS_OK || found != id)) {
        fuzz_fail("tb_scene_find_body", "body %zu's own name \"%s\" not found as %zu", id, name,
                  id);
    }
}

static void read_scene(fuzz_harness *h, const double *y)
{
    double energy, vector[3], point[3] = {0, 0, 0};
    tb_conserved conserved;
    check_read(h, tb_scene_kinetic_energy(h->scene, y, &energy), "tb_scene_kinetic_energy");
    check_read(h, tb_scene_potential_energy(h->scene, y, &energy), "tb_scene_potential_energy");
    check_read(h, tb_scene_linear_momentum(h->scene, y, vector), "tb_scene_linear_momentum");
    check_read(h, tb_scene_angular_momentum(h->scene, y, point, vector),
               "tb_scene_angular_momentum");
    check_read(h, tb_scene_conserved(h->scene, &conserved), "tb_scene_conserved");
    const uint8_t method = fuzz_byte(h->in);
    double dt = -1;
    char which[TB_DETAIL_SIZE];
    const tb_status status = tb_scene_max_stable_step(
        h->scene, method == 255 ? (tb_method)17 : (tb_method)(method % TB_METHOD_COUNT), &dt,
        which);
    check_read(h, status, "tb_scene_max_stable_step");
    if (status == TB_STATUS_OK && !(dt > 0)) {
        fuzz_fail("tb_scene_max_stable_step", "OK with dt = %g", dt);
    }
}

void fuzz_op_read(fuzz_harness *h)
{
    const size_t n = tb_scene_state_size(h->scene);
    double *copy = malloc((n + 1) * sizeof(double)), *dydt = malloc((n + 1) * sizeof(double));
    if (copy == NULL || dydt == NULL) {
        abort();
    }
    memcpy(copy, tb_scene_states_const(h->scene), n * sizeof(double));
    fuzz_snapshot before;
    fuzz_snapshot_take(h, &before);
    read_body(h, copy);
    read_scene(h, copy);
    const double scale = fuzz_double(h->in);
    fuzz_trace(h, "tb_scene_absolute_tolerances(scene, %s, atol);", fuzz_c_double(scale));
    check_read(h, tb_scene_absolute_tolerances(h->scene, scale, dydt),
               "tb_scene_absolute_tolerances");
    fuzz_trace(h, "tb_scene_derivative(0, y, dydt, scene);");
    const int result = tb_scene_derivative(0.0, copy, dydt, h->scene);
    if (result == 0 && h->user_count == 0) {
        fuzz_check_state_finite(h, "tb_scene_derivative");
    }
    if (memcmp(copy, tb_scene_states_const(h->scene), n * sizeof(double)) != 0) {
        fuzz_fail("read-outs", "changed the scene's state");
    }
    fuzz_check_unchanged(h, &before, "read-outs", TB_STATUS_OK);
    fuzz_snapshot_free(&before);
    free(copy);
    free(dydt);
}

/* A failure with a detail of its own first, so a NULL-pointer refusal that keeps the old detail
 * shows. */
static void fail_first(fuzz_harness *h)
{
    const double g[3] = {NAN, 0, 0};
    fuzz_trace(h, "tb_scene_add_gravity(scene, (double[]){NAN, 0, 0}); /* a detail to replace */");
    tb_scene_add_gravity(h->scene, g);
}

static void expect_null(fuzz_harness *h, const fuzz_snapshot *before, tb_status status,
                        const char *detail, const char *call)
{
    fuzz_trace(h, "%s /* with a NULL argument */", call);
    if ((status == TB_STATUS_OUT_OF_RANGE || status == TB_STATUS_INVALID_ARGUMENT) &&
        tb_scene_body_count(h->scene) == 0) {
        return; /* no body 0, nothing to integrate: either refusal is right */
    }
    if (status != TB_STATUS_NULL_POINTER) {
        fuzz_fail(call, "a NULL argument gave %s, not NULL_POINTER", tb_status_name(status));
    }
    fuzz_check(h, before, status, detail, call, FUZZ_UNCHANGED);
    if (detail != NULL && strstr(detail, "NULL") == NULL) {
        fuzz_fail(call, "a NULL argument left the detail \"%s\"", detail);
    }
}

static tb_status scene_null_call(fuzz_harness *h, unsigned which, const char **call)
{
    const double v[3] = {0, 0, 1};
    tb_integrator_def idef = tb_integrator_def_default();
    idef.method = TB_METHOD_CVODE_ADAMS; /* no stability limit to refuse first */
    tb_integrator *integrator = NULL;
    switch (which) {
    case 0:
        *call = "tb_scene_add_body(scene, NULL, &id)";
        return tb_scene_add_body(h->scene, NULL, NULL);
    case 1:
        *call = "tb_scene_set_state(scene, 0, NULL)";
        return tb_scene_set_state(h->scene, 0, NULL);
    case 2:
        *call = "tb_scene_set_velocity(scene, 0, NULL, w)";
        return tb_scene_set_velocity(h->scene, 0, NULL, v);
    case 3:
        *call = "tb_scene_add_gravity(scene, NULL)";
        return tb_scene_add_gravity(h->scene, NULL);
    case 4:
        *call = "tb_scene_add_force(scene, 0, NULL, p, TB_FRAME_WORLD)";
        return tb_scene_add_force(h->scene, 0, NULL, v, TB_FRAME_WORLD);
    case 5:
        *call = "tb_scene_add_torque(scene, 0, NULL, TB_FRAME_WORLD)";
        return tb_scene_add_torque(h->scene, 0, NULL, TB_FRAME_WORLD);
    case 6:
        *call = "tb_scene_add_drag(scene, NULL)";
        return tb_scene_add_drag(h->scene, NULL);
    case 7:
        *call = "tb_scene_add_spring(scene, NULL)";
        return tb_scene_add_spring(h->scene, NULL);
    case 8:
        *call = "tb_scene_add_ground(scene, NULL)";
        return tb_scene_add_ground(h->scene, NULL);
    case 9:
        *call = "tb_scene_add_user_effect(scene, NULL, NULL)";
        return tb_scene_add_user_effect(h->scene, NULL, NULL);
    case 10:
        *call = "tb_scene_set_contact_points(scene, 0, NULL, 2, 1)";
        return tb_scene_set_contact_points(h->scene, 0, NULL, 2, 1);
    case 11:
        *call = "tb_scene_integrator_create(scene, NULL, 0, &integrator)";
        return tb_scene_integrator_create(h->scene, NULL, 0, &integrator);
    default:
        *call = "tb_scene_integrator_create(scene, &idef, 0, NULL)";
        return tb_scene_integrator_create(h->scene, &idef, 0, NULL);
    }
}

/* Calls whose objects hold no detail: only the status is checked. */
static tb_status free_null_call(fuzz_harness *h, unsigned which, const char **call)
{
    tb_mass_properties props;
    tb_error error;
    double out[9];
    size_t id;
    switch (which) {
    case 0:
        *call = "tb_scene_get_state(scene, 0, NULL)";
        return tb_scene_get_state(h->scene, 0, NULL);
    case 1:
        *call = "tb_scene_kinetic_energy(scene, NULL, &energy)";
        return tb_scene_kinetic_energy(h->scene, NULL, out);
    case 2:
        *call = "tb_scene_body_velocity(scene, NULL, 0, v)";
        return tb_scene_body_velocity(h->scene, NULL, 0, out);
    case 3:
        *call = "tb_scene_find_body(scene, NULL, &id)";
        return tb_scene_find_body(h->scene, NULL, &id);
    case 4:
        *call = "tb_scene_max_stable_step(scene, TB_METHOD_RK4, NULL, NULL)";
        return tb_scene_max_stable_step(h->scene, TB_METHOD_RK4, NULL, NULL);
    case 5:
        *call = "tb_scene_ode_system(scene, NULL)";
        return tb_scene_ode_system(h->scene, NULL);
    case 6:
        *call = "tb_integrator_advance(NULL, 1)";
        return tb_integrator_advance(NULL, 1);
    case 7:
        *call = "tb_mass_from_box(TB_MASS_GIVEN, 1, NULL, &props, &error)";
        return tb_mass_from_box(TB_MASS_GIVEN, 1, NULL, &props, &error);
    case 8:
        *call = "tb_mass_from_sphere(TB_MASS_GIVEN, 1, 1, NULL, &error)";
        return tb_mass_from_sphere(TB_MASS_GIVEN, 1, 1, NULL, &error);
    case 9:
        *call = "tb_mass_validate(NULL, &error)";
        return tb_mass_validate(NULL, &error);
    default:
        *call = "tb_scene_absolute_tolerances(scene, 1e-6, NULL)";
        return tb_scene_absolute_tolerances(h->scene, 1e-6, NULL);
    }
}

void fuzz_op_null_arguments(fuzz_harness *h)
{
    const unsigned which = fuzz_choice(h->in, 24);
    fuzz_snapshot before;
    const char *call = "";
    if (which < 13) {
        fail_first(h);
        fuzz_snapshot_take(h, &before);
        const tb_status status = scene_null_call(h, which, &call);
        expect_null(h, &before, status, tb_scene_detail(h->scene), call);
    } else {
        fuzz_snapshot_take(h, &before);
        const tb_status status = free_null_call(h, which - 13, &call);
        expect_null(h, &before, status, NULL, call);
    }
    fuzz_snapshot_free(&before);
    /* Functions that return no status must survive NULL too. */
    const double f[3] = {1, 0, 0};
    double *dydt = calloc(tb_scene_state_size(h->scene) + 1, sizeof(double));
    if (dydt == NULL) {
        abort();
    }
    fuzz_trace(h, "tb_effect_add_force(scene, y, dydt, 0, NULL, f); "
                  "tb_effect_add_torque(scene, NULL, 0, f);\n"
                  "tb_scene_derivative(0, NULL, dydt, scene); "
                  "tb_scene_normalize_quaternions(0, NULL, scene); /* must refuse */");
    if (tb_scene_body_count(h->scene) > 0) {
        tb_effect_add_force(h->scene, tb_scene_states_const(h->scene), dydt, 0, NULL, f);
        tb_effect_add_torque(h->scene, NULL, 0, f);
    }
    if (tb_scene_derivative(0, NULL, dydt, h->scene) == 0 ||
        tb_scene_normalize_quaternions(0, NULL, h->scene) == 0) {
        fuzz_fail("tb_scene_derivative/tb_scene_normalize_quaternions", "accepted a NULL state");
    }
    free(dydt);
}
