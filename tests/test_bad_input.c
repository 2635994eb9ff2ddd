/* Every public function that takes input, given wrong input: a status naming the problem,
 * never a crash, and nothing changed (the scene's states and counts, the integrator's time,
 * the output structs). One line per case: add one by adding a row to BAD_INPUTS. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "tumble/tumble.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct fixture {
    tb_scene *scene, *other_scene, *grown_scene;
    tb_integrator *integrator, *other, *stale;
    tb_ode_system system;
    tb_integrator_def idef, rk4_with_rtol;
    tb_scene_def huge_effect_capacity;
    tb_body_def body, long_name, duplicate, subnormal_mass, overflowing_momentum;
    tb_body_state state, bad_state;
    tb_mass_properties mass, bad_mass;
    tb_mass_part part;
    tb_drag_def drag;
    tb_spring_def spring, far_spring;
    tb_ground_def ground;
    tb_run_def run, zero_fps, infinite_run, tiny_dt_run;
    tb_contact_point points[8];
    tb_method method;
    tb_conserved conserved;
    double y[2], v[3], matrix[9], value, positions[6], masses[2], nan_positions[6];
    double vertices[12], subnormal_tensor[9], subnormal_masses[2], huge_omega[3];
    unsigned triangles[12], past_the_vertices[12];
    tb_contact_point far_point;
    tb_shape nan_sphere, far_hull, flat_hull, mesh_past_the_vertices;
    tb_shape_piece nan_piece, piece_out;
    tb_visual_mesh visual_out;
    tb_contact_def bad_contact, null_bodies;
    tb_contact_def huge_body_count, huge_friction_points, shapeless, huge_gravity;
    tb_contact_def nan_restitution, forgotten_count;
    tb_ground_def nan_ground_restitution;
    tb_scene_def huge_body_capacity;
    size_t first_body[2];
    double far_vertices[12], flat_vertices[12], nan_vertices[12];
    size_t id, count;
    char name[100];
} fixture;

static int harmonic(double t, const double *y, double *dydt, void *ctx)
{
    (void)t, (void)ctx;
    dydt[0] = y[1];
    dydt[1] = -y[0];
    return 0;
}

/* Inputs at the ends of the double range (issue 11): each made a hang, a crash or a
 * non-finite value before it was refused. */
static void set_up_extremes(fixture *f)
{
    f->huge_effect_capacity = tb_scene_def_default();
    f->huge_effect_capacity.effect_capacity = (size_t)1 << 61; /* its byte size overflowed */
    f->subnormal_mass = f->body;
    f->subnormal_mass.name = "light";
    f->subnormal_mass.mass.mass = 5e-324; /* 1 / m = inf */
    f->overflowing_momentum = f->body;
    f->overflowing_momentum.name = "heavy";
    tb_mass_from_sphere(TB_MASS_GIVEN, 1e100, 0.1, &f->overflowing_momentum.mass, NULL);
    f->overflowing_momentum.velocity[0] = 1e300; /* P = 1e400 */
    f->huge_omega[2] = 1.7976931348623157e308;   /* I omega finite, I^-1 L with it not */
    for (int k = 0; k < 9; ++k) {
        f->subnormal_tensor[k] = k % 4 == 0 ? 1e-322 : 0.0; /* GSL's eigen-solver hung */
    }
    f->subnormal_masses[0] = f->subnormal_masses[1] = 5e-324;
    memcpy(f->past_the_vertices, f->triangles, sizeof f->triangles);
    f->past_the_vertices[11] = 7;
    f->far_spring = tb_spring_def_default();
    f->far_spring.point_a[1] = 6.3498042097568784e246; /* its rate overflowed: stable dt 0 s */
    f->far_spring.stiffness = 2.8;
    f->far_point = (tb_contact_point){{0, 1e200, 0}, 0.0};
    f->rk4_with_rtol = f->idef;
    f->rk4_with_rtol.rtol = 1e-8; /* ignored silently before */
    f->tiny_dt_run = tb_run_def_default();
    f->tiny_dt_run.integrator.dt = 1e-300; /* 1.7e298 steps a frame: ran "forever" */
    /* an integrator whose scene grew a body after it was made */
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene_create(&scene_def, &f->grown_scene, NULL);
    tb_scene_add_body(f->grown_scene, &f->body, NULL);
    tb_scene_integrator_create(f->grown_scene, &f->idef, 0.0, &f->stale);
    f->long_name.name = "second";
    tb_scene_add_body(f->grown_scene, &f->long_name, NULL);
    f->long_name.name = f->name;
}

/* Counts near the wrap of size_t, and contact inputs the library took and the run did not
 * (issue 19): each size computed from a caller's count goes through one checked multiply. */
static void set_up_counts(fixture *f)
{
    f->first_body[0] = f->first_body[1] = 0; /* the second: a repeat, so the check stops */
    f->huge_body_count = tb_contact_def_default();
    f->huge_body_count.bodies = f->first_body;
    f->huge_body_count.body_count = ((size_t)1 << 61) + 1; /* 8 bytes each wrapped to 8 */
    f->huge_friction_points = tb_contact_def_default();
    f->huge_friction_points.friction_points = (size_t)1 << 61;
    f->shapeless = tb_contact_def_default();
    f->shapeless.bodies = f->first_body; /* the ball has no shape */
    f->shapeless.body_count = 1;
    f->huge_gravity = tb_contact_def_default();
    f->huge_gravity.gravity = 1e300; /* omega 1e153 rad/s: the run failed */
    /* a contact surface's red team: NaN is NOT_FINITE in every field; a list of bodies with
     * its count left 0 made an effect that touched nothing, silently */
    f->nan_restitution = tb_contact_def_default();
    f->nan_restitution.restitution = NAN;
    f->nan_ground_restitution = tb_ground_def_default();
    f->nan_ground_restitution.restitution = NAN;
    f->forgotten_count = tb_contact_def_default();
    f->forgotten_count.bodies = f->first_body;
    f->huge_body_capacity = tb_scene_def_default();
    f->huge_body_capacity.body_capacity = (size_t)1 << 61;
}

/* Shapes and contact effects (issue 12). */
static void set_up_contact(fixture *f)
{
    f->nan_sphere = tb_shape_default();
    f->nan_sphere.type = TB_SHAPE_SPHERE;
    f->nan_sphere.radius = NAN;
    f->nan_piece = tb_shape_piece_default();
    f->nan_piece.shape = f->nan_sphere;
    for (int k = 0; k < 12; ++k) {
        f->far_vertices[k] = k % 3 == k / 3 ? 1e101 : 0.0; /* a tetrahedron past 1e100 m */
        f->flat_vertices[k] = k % 3 == 2 ? 0.0 : (double)(k % 4);
    }
    f->far_hull = tb_shape_default();
    f->far_hull.type = TB_SHAPE_CONVEX;
    f->far_hull.vertices = f->far_vertices;
    f->far_hull.vertex_count = 4;
    f->flat_hull = f->far_hull;
    f->flat_hull.vertices = f->flat_vertices;
    f->bad_contact = tb_contact_def_default();
    f->bad_contact.restitution = 2.0;
    f->null_bodies = tb_contact_def_default();
    f->null_bodies.body_count = 2;
    set_up_counts(f);
}

/* Body 0 is drawn as the tetrahedron (vertices, triangles): a refused call must leave it
 * (past_the_vertices is filled by set_up_extremes). */
static void set_up_visual_mesh(fixture *f)
{
    for (int k = 0; k < 12; ++k) {
        f->nan_vertices[k] = k == 7 ? NAN : f->vertices[k];
    }
    assert_int_equal(tb_scene_set_body_visual_mesh(f->scene, 0, 0, f->vertices, 4, f->triangles, 4),
                     TB_STATUS_OK);
    f->mesh_past_the_vertices = tb_shape_default();
    f->mesh_past_the_vertices.type = TB_SHAPE_CONVEX;
    f->mesh_past_the_vertices.vertices = f->vertices;
    f->mesh_past_the_vertices.vertex_count = 4;
    f->mesh_past_the_vertices.triangles = f->past_the_vertices;
    f->mesh_past_the_vertices.triangle_count = 4;
}

static void set_up(fixture *f)
{
    memset(f, 0, sizeof *f);
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene_create(&scene_def, &f->scene, NULL);
    f->body = tb_body_def_default();
    f->body.name = "ball";
    tb_mass_from_sphere(TB_MASS_GIVEN, 1.0, 0.1, &f->body.mass, NULL);
    f->body.position[2] = 1.0;
    tb_scene_add_body(f->scene, &f->body, NULL);
    tb_scene_add_gravity(f->scene, (double[]){0, 0, -9.81});
    f->idef = tb_integrator_def_default();
    tb_scene_integrator_create(f->scene, &f->idef, 0.0, &f->integrator);
    tb_integrator_advance(f->integrator, 0.1);
    f->system = (tb_ode_system){.n = 2, .derivative = harmonic};
    f->y[0] = 1.0;
    memset(f->name, 'n', sizeof f->name - 1);
    f->long_name = f->body;
    f->long_name.name = f->name;
    f->duplicate = f->body;
    tb_scene_get_state(f->scene, 0, &f->state);
    f->bad_state = f->state;
    f->bad_state.P[1] = INFINITY;
    f->bad_mass = f->body.mass;
    f->bad_mass.moments[1] = -1.0;
    f->part.props = f->body.mass;
    f->part.orientation[0] = 1.0;
    f->drag = tb_drag_def_default();
    f->drag.internal_cookie = 0;
    f->spring = tb_spring_def_default();
    f->spring.body_b = 9;
    f->spring.stiffness = 1.0;
    f->ground = tb_ground_def_default();
    f->ground.offset = NAN;
    f->run = tb_run_def_default();
    f->zero_fps = f->run;
    f->zero_fps.fps = 0.0;
    f->infinite_run = f->run;
    f->infinite_run.duration = INFINITY;
    const double positions[6] = {0, 0, 0, 1, 0, 0};
    memcpy(f->positions, positions, sizeof positions);
    memcpy(f->nan_positions, positions, sizeof positions);
    f->nan_positions[4] = NAN;
    f->masses[0] = f->masses[1] = 1.0;
    for (int k = 0; k < 12; ++k) {
        f->triangles[k] = (unsigned)(k % 4);
        f->vertices[k] = (double)(k % 3 == k / 3);
    }
    set_up_contact(f);
    set_up_visual_mesh(f);
    memset(&f->mass, 0x5a, sizeof f->mass);
    memset(&f->method, 0x5a, sizeof f->method);
    set_up_extremes(f);
}

#define BAD_INPUTS(X)                                                                              \
    X("method_from_name: NULL", NULL_POINTER, tb_method_from_name(NULL, &f->method))               \
    X("method_from_name: unknown", INVALID_ARGUMENT, tb_method_from_name("rk5", &f->method))       \
    X("integrator_create: NULL system", NULL_POINTER,                                              \
      tb_integrator_create(NULL, &f->idef, 0, f->y, &f->other, NULL))                              \
    X("integrator_create: NaN t0", NOT_FINITE,                                                     \
      tb_integrator_create(&f->system, &f->idef, NAN, f->y, &f->other, NULL))                      \
    X("integrator_create: NULL y", NULL_POINTER,                                                   \
      tb_integrator_create(&f->system, &f->idef, 0, NULL, &f->other, NULL))                        \
    X("advance: NULL", NULL_POINTER, tb_integrator_advance(NULL, 1))                               \
    X("advance: NaN", NOT_FINITE, tb_integrator_advance(f->integrator, NAN))                       \
    X("advance: infinity", NOT_FINITE, tb_integrator_advance(f->integrator, INFINITY))             \
    X("advance: backwards", INVALID_ARGUMENT, tb_integrator_advance(f->integrator, -1))            \
    X("step: NULL", NULL_POINTER, tb_integrator_step(NULL))                                        \
    X("reset: NaN", NOT_FINITE, tb_integrator_reset(f->integrator, NAN))                           \
    X("reset: NULL", NULL_POINTER, tb_integrator_reset(NULL, 0))                                   \
    X("get_stats: NULL out", NULL_POINTER, tb_integrator_get_stats(f->integrator, NULL))           \
    X("sphere: NaN radius", NOT_FINITE, tb_mass_from_sphere(TB_MASS_GIVEN, 1, NAN, &f->mass, 0))   \
    X("sphere: unknown mode", INVALID_ARGUMENT,                                                    \
      tb_mass_from_sphere((tb_mass_mode)7, 1, 1, &f->mass, NULL))                                  \
    X("box: NULL size", NULL_POINTER, tb_mass_from_box(TB_MASS_GIVEN, 1, NULL, &f->mass, NULL))    \
    X("box: huge density", INVALID_ARGUMENT,                                                       \
      tb_mass_from_box(TB_MASS_DENSITY, 1e300, (double[]){1e100, 1e100, 1e100}, &f->mass, NULL))   \
    X("box: huge size (inertia overflows)", NOT_FINITE,                                            \
      tb_mass_from_box(TB_MASS_GIVEN, 1, (double[]){1e200, 1e200, 1}, &f->mass, NULL))             \
    X("cylinder: zero length", INVALID_ARGUMENT,                                                   \
      tb_mass_from_cylinder(TB_MASS_GIVEN, 1, 1, 0, &f->mass, NULL))                               \
    X("capsule: infinite radius", NOT_FINITE,                                                      \
      tb_mass_from_capsule(TB_MASS_GIVEN, 1, INFINITY, 1, &f->mass, NULL))                         \
    X("ellipsoid: NULL", NULL_POINTER, tb_mass_from_ellipsoid(TB_MASS_GIVEN, 1, 0, &f->mass, 0))   \
    X("points: NULL masses", NULL_POINTER,                                                         \
      tb_mass_from_points(f->positions, NULL, 2, &f->mass, NULL))                                  \
    X("points: NaN position", NOT_FINITE,                                                          \
      tb_mass_from_points(f->nan_positions, f->masses, 2, &f->mass, NULL))                         \
    X("points: two points (a line)", BAD_MASS_PROPERTIES,                                          \
      tb_mass_from_points(f->positions, f->masses, 2, &f->mass, NULL))                             \
    X("mesh: NULL vertices", NULL_POINTER,                                                         \
      tb_mass_from_mesh(TB_MASS_GIVEN, 1, NULL, 4, f->triangles, 4, &f->mass, NULL))               \
    X("mesh: three triangles", BAD_MESH,                                                           \
      tb_mass_from_mesh(TB_MASS_GIVEN, 1, f->vertices, 4, f->triangles, 3, &f->mass, NULL))        \
    X("tensor: zero", BAD_MASS_PROPERTIES,                                                         \
      tb_mass_from_tensor(1, f->v, (double[9]){0}, &f->mass, NULL))                                \
    X("tensor: NaN center", NOT_FINITE,                                                            \
      tb_mass_from_tensor(1, (double[]){NAN, 0, 0}, (double[]){1, 0, 0, 0, 1, 0, 0, 0, 1},         \
                          &f->mass, NULL))                                                         \
    X("combine: no parts", INVALID_ARGUMENT, tb_mass_combine(&f->part, 0, &f->mass, NULL))         \
    X("combine: NULL", NULL_POINTER, tb_mass_combine(NULL, 1, &f->mass, NULL))                     \
    X("tensor_inverse: NULL", NULL_POINTER, tb_mass_tensor_inverse(NULL, f->matrix, NULL))         \
    X("validate: negative moment", INVALID_ARGUMENT, tb_mass_validate(&f->bad_mass, NULL))         \
    X("scene_create: NULL def", NULL_POINTER, tb_scene_create(NULL, &f->other_scene, NULL))        \
    X("add_body: NULL def", NULL_POINTER, tb_scene_add_body(f->scene, NULL, NULL))                 \
    X("add_body: NULL scene", NULL_POINTER, tb_scene_add_body(NULL, &f->body, NULL))               \
    X("add_body: 99-character name", INVALID_ARGUMENT,                                             \
      tb_scene_add_body(f->scene, &f->long_name, NULL))                                            \
    X("add_body: duplicate name", INVALID_ARGUMENT,                                                \
      tb_scene_add_body(f->scene, &f->duplicate, NULL))                                            \
    X("get_state: id 9", OUT_OF_RANGE, tb_scene_get_state(f->scene, 9, &f->state))                 \
    X("set_state: infinite P", NOT_FINITE, tb_scene_set_state(f->scene, 0, &f->bad_state))         \
    X("set_state: NULL", NULL_POINTER, tb_scene_set_state(f->scene, 0, NULL))                      \
    X("set_velocity: NULL", NULL_POINTER, tb_scene_set_velocity(f->scene, 0, NULL, f->v))          \
    X("set_velocity: id 9", OUT_OF_RANGE, tb_scene_set_velocity(f->scene, 9, f->v, f->v))          \
    X("get_mass: id 9", OUT_OF_RANGE, tb_scene_get_mass(f->scene, 9, &f->mass))                    \
    X("body_rotation: NULL y", NULL_POINTER, tb_scene_body_rotation(f->scene, NULL, 0, f->matrix)) \
    X("body_velocity: id 9", OUT_OF_RANGE,                                                         \
      tb_scene_body_velocity(f->scene, tb_scene_states(f->scene), 9, f->v))                        \
    X("angular_velocity: NULL out", NULL_POINTER,                                                  \
      tb_scene_body_angular_velocity(f->scene, tb_scene_states(f->scene), 0, NULL))                \
    X("shape_pose: NULL orientation", NULL_POINTER,                                                \
      tb_scene_body_shape_pose(f->scene, tb_scene_states(f->scene), 0, f->v, NULL))                \
    X("kinetic_energy: NULL scene", NULL_POINTER, tb_scene_kinetic_energy(NULL, f->y, &f->value))  \
    X("potential_energy: NULL y", NULL_POINTER,                                                    \
      tb_scene_potential_energy(f->scene, NULL, &f->value))                                        \
    X("linear_momentum: NULL out", NULL_POINTER,                                                   \
      tb_scene_linear_momentum(f->scene, tb_scene_states(f->scene), NULL))                         \
    X("angular_momentum: NULL point", NULL_POINTER,                                                \
      tb_scene_angular_momentum(f->scene, tb_scene_states(f->scene), NULL, f->v))                  \
    X("conserved: NULL out", NULL_POINTER, tb_scene_conserved(f->scene, NULL))                     \
    X("find_body: unknown", OUT_OF_RANGE, tb_scene_find_body(f->scene, "nobody", &f->id))          \
    X("find_body: NULL name", NULL_POINTER, tb_scene_find_body(f->scene, NULL, &f->id))            \
    X("ode_system: NULL out", NULL_POINTER, tb_scene_ode_system(f->scene, NULL))                   \
    X("integrator_create on scene: NULL def", NULL_POINTER,                                        \
      tb_scene_integrator_create(f->scene, NULL, 0, &f->other))                                    \
    X("absolute_tolerances: zero scale", INVALID_ARGUMENT,                                         \
      tb_scene_absolute_tolerances(f->scene, 0.0, f->matrix))                                      \
    X("max_stable_step: NULL out", NULL_POINTER,                                                   \
      tb_scene_max_stable_step(f->scene, TB_METHOD_RK4, NULL, NULL))                               \
    X("add_gravity: infinite", NOT_FINITE,                                                         \
      tb_scene_add_gravity(f->scene, (double[]){0, 0, -INFINITY}))                                 \
    X("add_force: body 9", OUT_OF_RANGE,                                                           \
      tb_scene_add_force(f->scene, 9, f->v, f->v, TB_FRAME_WORLD))                                 \
    X("add_torque: NULL", NULL_POINTER, tb_scene_add_torque(f->scene, 0, NULL, TB_FRAME_BODY))     \
    X("add_drag: def not from default", INVALID_ARGUMENT, tb_scene_add_drag(f->scene, &f->drag))   \
    X("add_spring: body_b 9", OUT_OF_RANGE, tb_scene_add_spring(f->scene, &f->spring))             \
    X("add_ground: NaN offset", NOT_FINITE, tb_scene_add_ground(f->scene, &f->ground))             \
    X("set_contact_points: support 0", INVALID_ARGUMENT,                                           \
      tb_scene_set_contact_points(f->scene, 0, f->points, 2, 0))                                   \
    X("set_contact_points: NULL points", NULL_POINTER,                                             \
      tb_scene_set_contact_points(f->scene, 0, NULL, 3, 1))                                        \
    X("contact_points_box: no room", OUT_OF_RANGE,                                                 \
      tb_contact_points_box(f->v, f->points, 2, &f->count))                                        \
    X("add_user_effect: NULL fn", NULL_POINTER, tb_scene_add_user_effect(f->scene, NULL, NULL))    \
    X("run: NULL def", NULL_POINTER, tb_scene_run(f->scene, NULL, NULL, NULL, NULL, NULL))         \
    X("run: zero fps", INVALID_ARGUMENT,                                                           \
      tb_scene_run(f->scene, &f->zero_fps, NULL, NULL, NULL, NULL))                                \
    X("run: infinite duration", NOT_FINITE,                                                        \
      tb_scene_run(f->scene, &f->infinite_run, NULL, NULL, NULL, NULL))                            \
    X("load_file: NULL path", NULL_POINTER,                                                        \
      tb_scene_load_file(NULL, &f->other_scene, &f->run, NULL))                                    \
    X("load_file: a directory", IO_ERROR, tb_scene_load_file("/", &f->other_scene, &f->run, NULL)) \
    X("load_string: NULL json", NULL_POINTER,                                                      \
      tb_scene_load_string(NULL, "x", NULL, &f->other_scene, &f->run, NULL))                       \
    X("load_string: empty", PARSE_ERROR,                                                           \
      tb_scene_load_string("", "x", NULL, &f->other_scene, &f->run, NULL))                         \
    EXTREME_INPUTS(X)

/* Issue 11's classes: hangs, crashes, silent garbage at the ends of the double range. */
#define EXTREME_INPUTS(X)                                                                          \
    X("scene_create: effect_capacity 2^61", OUT_OF_MEMORY,                                         \
      tb_scene_create(&f->huge_effect_capacity, &f->other_scene, NULL))                            \
    X("points: subnormal masses", INVALID_ARGUMENT,                                                \
      tb_mass_from_points(f->positions, f->subnormal_masses, 2, &f->mass, NULL))                   \
    X("tensor: subnormal entries", BAD_MASS_PROPERTIES,                                            \
      tb_mass_from_tensor(1, f->v, f->subnormal_tensor, &f->mass, NULL))                           \
    X("mesh: index past the vertices", BAD_MESH,                                                   \
      tb_mass_from_mesh(TB_MASS_GIVEN, 1, f->vertices, 4, f->past_the_vertices, 4, &f->mass,       \
                        NULL))                                                                     \
    X("add_body: mass 5e-324", INVALID_ARGUMENT,                                                   \
      tb_scene_add_body(f->scene, &f->subnormal_mass, NULL))                                       \
    X("add_body: 1e100 kg at 1e300 m/s", NOT_FINITE,                                               \
      tb_scene_add_body(f->scene, &f->overflowing_momentum, NULL))                                 \
    X("set_velocity: omega 1.8e308", NOT_FINITE,                                                   \
      tb_scene_set_velocity(f->scene, 0, f->v, f->huge_omega))                                     \
    X("add_force: NULL force", NULL_POINTER,                                                       \
      tb_scene_add_force(f->scene, 0, NULL, NULL, TB_FRAME_WORLD))                                 \
    X("add_spring: point 6e246 m out", INVALID_ARGUMENT,                                           \
      tb_scene_add_spring(f->scene, &f->far_spring))                                               \
    X("set_contact_points: 1e200 m out", INVALID_ARGUMENT,                                         \
      tb_scene_set_contact_points(f->scene, 0, &f->far_point, 1, 1))                               \
    X("advance: 1e9 s at 1/240 s a step", TOO_MANY_STEPS,                                          \
      tb_integrator_advance(f->integrator, 1e9))                                                   \
    X("advance: the scene grew a body", LAYOUT_CHANGED, tb_integrator_advance(f->stale, 1.0))      \
    X("integrator_create on scene: t0 1e15", INVALID_ARGUMENT,                                     \
      tb_scene_integrator_create(f->scene, &f->idef, 1e15, &f->other))                             \
    X("integrator_create on scene: rk4 rtol", INVALID_ARGUMENT,                                    \
      tb_scene_integrator_create(f->scene, &f->rk4_with_rtol, 0, &f->other))                       \
    X("run_frame_count: 1e9 s at 60 fps", INVALID_ARGUMENT,                                        \
      tb_run_frame_count(1e9, 60, &f->count, NULL))                                                \
    X("run: dt 1e-300 (a frame over max_steps)", TOO_MANY_STEPS,                                   \
      tb_scene_run(f->scene, &f->tiny_dt_run, NULL, NULL, NULL, NULL))                             \
    X("set_body_shape: NaN radius", NOT_FINITE,                                                    \
      tb_scene_set_body_shape(f->scene, 0, &f->nan_sphere))                                        \
    X("set_body_shape: id 9", OUT_OF_RANGE, tb_scene_set_body_shape(f->scene, 9, &f->nan_sphere))  \
    X("set_body_shape: hull 1e101 m out", INVALID_ARGUMENT,                                        \
      tb_scene_set_body_shape(f->scene, 0, &f->far_hull))                                          \
    X("set_body_shape: a flat hull", INVALID_ARGUMENT,                                             \
      tb_scene_set_body_shape(f->scene, 0, &f->flat_hull))                                         \
    X("set_body_shape: NULL scene", NULL_POINTER, tb_scene_set_body_shape(NULL, 0, &f->far_hull))  \
    X("set_body_pieces: NULL pieces", NULL_POINTER,                                                \
      tb_scene_set_body_pieces(f->scene, 0, NULL, 1))                                              \
    X("set_body_pieces: count 0", INVALID_ARGUMENT,                                                \
      tb_scene_set_body_pieces(f->scene, 0, &f->nan_piece, 0))                                     \
    X("set_body_pieces: NaN radius", NOT_FINITE,                                                   \
      tb_scene_set_body_pieces(f->scene, 0, &f->nan_piece, 1))                                     \
    X("set_body_pieces: id 9", OUT_OF_RANGE,                                                       \
      tb_scene_set_body_pieces(f->scene, 9, &f->nan_piece, 1))                                     \
    X("set_body_pieces: NULL scene", NULL_POINTER, tb_scene_set_body_pieces(NULL, 0, NULL, 1))     \
    X("body_piece_count: NULL out", NULL_POINTER, tb_scene_body_piece_count(f->scene, 0, NULL))    \
    X("body_piece: no shape", OUT_OF_RANGE, tb_scene_body_piece(f->scene, 0, 0, &f->piece_out))    \
    X("body_piece: NULL out", NULL_POINTER, tb_scene_body_piece(f->scene, 0, 0, NULL))             \
    X("body_shape_bounds: no shape", INVALID_ARGUMENT,                                             \
      tb_scene_body_shape_bounds(f->scene, tb_scene_states_const(f->scene), 0, f->v, f->v))        \
    VISUAL_MESH_INPUTS(X)                                                                          \
    X("add_contact: restitution 2", INVALID_ARGUMENT,                                              \
      tb_scene_add_contact(f->scene, &f->bad_contact))                                             \
    X("add_contact: NULL def", NULL_POINTER, tb_scene_add_contact(f->scene, NULL))                 \
    X("add_contact: NULL bodies, count 2", NULL_POINTER,                                           \
      tb_scene_add_contact(f->scene, &f->null_bodies))                                             \
    COUNT_INPUTS(X)

/* Issue 22: the visual meshes (body 0 has the tetrahedron; none of these may touch it). */
#define VISUAL_MESH_INPUTS(X)                                                                      \
    X("set_body_visual_mesh: NULL scene", NULL_POINTER,                                            \
      tb_scene_set_body_visual_mesh(NULL, 0, 0, f->vertices, 4, f->triangles, 4))                  \
    X("set_body_visual_mesh: id 9", OUT_OF_RANGE,                                                  \
      tb_scene_set_body_visual_mesh(f->scene, 9, 0, f->vertices, 4, f->triangles, 4))              \
    X("set_body_visual_mesh: piece 1 of 1", OUT_OF_RANGE,                                          \
      tb_scene_set_body_visual_mesh(f->scene, 0, 1, f->vertices, 4, f->triangles, 4))              \
    X("set_body_visual_mesh: NULL vertices", NULL_POINTER,                                         \
      tb_scene_set_body_visual_mesh(f->scene, 0, 0, NULL, 4, f->triangles, 4))                     \
    X("set_body_visual_mesh: NULL triangles", NULL_POINTER,                                        \
      tb_scene_set_body_visual_mesh(f->scene, 0, 0, f->vertices, 4, NULL, 4))                      \
    X("set_body_visual_mesh: NaN vertex", NOT_FINITE,                                              \
      tb_scene_set_body_visual_mesh(f->scene, 0, 0, f->nan_vertices, 4, f->triangles, 4))          \
    X("set_body_visual_mesh: vertex 1e101 m out", INVALID_ARGUMENT,                                \
      tb_scene_set_body_visual_mesh(f->scene, 0, 0, f->far_vertices, 4, f->triangles, 4))          \
    X("set_body_visual_mesh: index past vertices", INVALID_ARGUMENT,                               \
      tb_scene_set_body_visual_mesh(f->scene, 0, 0, f->vertices, 4, f->past_the_vertices, 4))      \
    X("set_body_visual_mesh: 2 vertices", INVALID_ARGUMENT,                                        \
      tb_scene_set_body_visual_mesh(f->scene, 0, 0, f->vertices, 2, f->triangles, 4))              \
    X("set_body_visual_mesh: vertices, 0 triangles", INVALID_ARGUMENT,                             \
      tb_scene_set_body_visual_mesh(f->scene, 0, 0, f->vertices, 4, f->triangles, 0))              \
    X("set_body_visual_mesh: SIZE_MAX vertices", INVALID_ARGUMENT,                                 \
      tb_scene_set_body_visual_mesh(f->scene, 0, 0, f->vertices, SIZE_MAX, f->triangles, 4))       \
    X("set_body_visual_mesh: 2^62 triangles", INVALID_ARGUMENT,                                    \
      tb_scene_set_body_visual_mesh(f->scene, 0, 0, f->vertices, 4, f->triangles,                  \
                                    (size_t)1 << 62))                                              \
    X("set_body_shape: a mesh index past vertices", INVALID_ARGUMENT,                              \
      tb_scene_set_body_shape(f->scene, 0, &f->mesh_past_the_vertices))                            \
    X("body_visual_mesh: NULL out", NULL_POINTER, tb_scene_body_visual_mesh(f->scene, 0, 0, NULL)) \
    X("body_visual_mesh: piece 1 of 1", OUT_OF_RANGE,                                              \
      tb_scene_body_visual_mesh(f->scene, 0, 1, &f->visual_out))

/* Issue 19: counts near the wrap of size_t and contact inputs that failed the run. */
#define COUNT_INPUTS(X)                                                                            \
    X("add_contact: body_count 2^61 + 1", INVALID_ARGUMENT,                                        \
      tb_scene_add_contact(f->scene, &f->huge_body_count))                                         \
    X("add_contact: friction_points 2^61", OUT_OF_MEMORY,                                          \
      tb_scene_add_contact(f->scene, &f->huge_friction_points))                                    \
    X("add_contact: a listed body without a shape", INVALID_ARGUMENT,                              \
      tb_scene_add_contact(f->scene, &f->shapeless))                                               \
    X("add_contact: gravity 1e300", INVALID_ARGUMENT,                                              \
      tb_scene_add_contact(f->scene, &f->huge_gravity))                                            \
    X("add_contact: NaN restitution", NOT_FINITE,                                                  \
      tb_scene_add_contact(f->scene, &f->nan_restitution))                                         \
    X("add_ground: NaN restitution", NOT_FINITE,                                                   \
      tb_scene_add_ground(f->scene, &f->nan_ground_restitution))                                   \
    X("add_contact: a list of bodies, body_count 0", INVALID_ARGUMENT,                             \
      tb_scene_add_contact(f->scene, &f->forgotten_count))                                         \
    X("body_contact_point_count: NULL out", NULL_POINTER,                                          \
      tb_scene_body_contact_point_count(f->scene, 0, NULL))                                        \
    X("scene_create: body_capacity 2^61", OUT_OF_MEMORY,                                           \
      tb_scene_create(&f->huge_body_capacity, &f->other_scene, NULL))                              \
    X("mesh: 2^62 triangles", BAD_MESH,                                                            \
      tb_mass_from_mesh(TB_MASS_GIVEN, 1, f->vertices, 4, f->triangles, (size_t)1 << 62, &f->mass, \
                        NULL))

static tb_status attempt(size_t index, fixture *f)
{
    size_t i = 0;
#define AS_CALL(label, status, call)                                                               \
    if (index == i++) {                                                                            \
        return (call);                                                                             \
    }
    BAD_INPUTS(AS_CALL)
#undef AS_CALL
    return TB_STATUS_OK;
}

static const struct {
    const char *label;
    tb_status expected;
} cases[] = {
#define AS_ROW(label, status, call) {label, TB_STATUS_##status},
    BAD_INPUTS(AS_ROW)
#undef AS_ROW
};

typedef struct snapshot {
    size_t bodies, effects, size;
    double states[64];
    double time;
    tb_mass_properties mass;
    tb_body_state state;
    size_t pieces;
    tb_visual_mesh visual; /* body 0's, pointing into the scene */
    double visual_vertices[12];
    unsigned visual_triangles[12];
} snapshot;

static void take(const fixture *f, snapshot *s)
{
    memset(s, 0, sizeof *s);
    s->bodies = tb_scene_body_count(f->scene);
    s->effects = tb_scene_effect_count(f->scene);
    s->size = tb_scene_state_size(f->scene);
    memcpy(s->states, tb_scene_states_const(f->scene), s->size * sizeof(double));
    s->time = tb_integrator_time(f->integrator);
    s->mass = f->mass;
    s->state = f->state;
    tb_scene_body_piece_count(f->scene, 0, &s->pieces);
    tb_scene_body_visual_mesh(f->scene, 0, 0, &s->visual);
    memcpy(s->visual_vertices, s->visual.vertices, sizeof s->visual_vertices);
    memcpy(s->visual_triangles, s->visual.triangles, sizeof s->visual_triangles);
}

static void test_every_public_function_refuses_bad_input_and_changes_nothing(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        fixture f;
        set_up(&f);
        snapshot before, after;
        take(&f, &before);
        const tb_status status = attempt(i, &f);
        take(&f, &after);
        print_message("%-40s -> %s\n", cases[i].label, tb_status_name(status));
        assert_int_equal(status, cases[i].expected);
        assert_memory_equal(&before, &after, sizeof before);
        assert_null(f.other);
        assert_null(f.other_scene);
        tb_integrator_destroy(f.integrator);
        tb_integrator_destroy(f.stale);
        tb_scene_destroy(f.scene);
        tb_scene_destroy(f.grown_scene);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_public_function_refuses_bad_input_and_changes_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
