/* The ground's analytic rows of the scene Jacobian (tb__effect_ops.jacobian): one pass over its
 * bodies' contact points as apply_ground makes (effect_ground.c), each touching point's normal law
 * and stick anchor (z in the plane's tangent basis: world z = t1 z_1 + t2 z_2) differentiated at
 * its depth, rate, tangential velocity and anchor (contact_law.h, friction_jacobian.h) and chained
 * to its body's state (scene/jacobian_rows.h); then the bodies it meets through their shapes
 * (effect_ground_shapes.c). Held fixed: the point's sphere centre on the body (the lowest point
 * moves with it), the dashpots' effective masses, the load's shares. */
#include "effects/effect_ground.h"

#include "contact/contact_law.h"
#include "effects/friction_jacobian.h"
#include "math/tb_math.h"

/* Point c of a touching body, its two anchor states at y[k], as contact() (effect_ground.c). */
static void point_rows(const tb__ground_params *ground, const tb_scene *scene, const tb__contact *c,
                       const tb__motion *motion, const tb__body_load *load, const double *y,
                       size_t k, tb__jacobian_rows *rows)
{
    const double *n = ground->normal;
    tb__point_jacobian p = {.body_a = TB_WORLD, .body_b = c->body, .state_first = k};
    const double depth = tb__ground_point_depth(ground, c, motion, p.arm_b);
    if (depth <= 0.0) {
        tb__jacobian_set_diagonal(rows, k, 2, -TB__BRISTLE_RELEASE_RATE);
        return;
    }
    tb__v3_axpy(p.arm_b, -c->radius, n); /* the sphere's lowest point touches */
    double velocity[3], tangent[3];
    tb__point_velocity(motion, p.arm_b, velocity);
    const tb__body *body = tb__body_constants(scene, c->body);
    const double mass = body->mass * c->share;
    const double part = c->share * depth / load->total;
    double dashpot = load->normal * part;
    if (dashpot > mass) {
        dashpot = fmin(dashpot, fmax(mass, 1.0 / tb__inverse_mass_along(body, motion, p.arm_b, n)));
    }
    const double k_n = mass * ground->omega * ground->omega, rate = -tb__v3_dot(n, velocity);
    const double N = tb__contact_point_force(k_n, dashpot, ground->damping_ratio, depth, rate);
    double dN[2];
    tb__contact_point_force_derivatives(k_n, dashpot, ground->damping_ratio, depth, rate, dN);
    if (!(ground->static_friction > 0.0)) { /* frictionless: z relaxes */
        tb__contact_point_rows(n, dN[0], dN[1], NULL, NULL, 0, &p);
        tb__jacobian_add_point(rows, scene, &p);
        tb__jacobian_set_diagonal(rows, k, 2, -TB__BRISTLE_RELEASE_RATE);
        return;
    }
    double T[3][3] = {{0.0}}, z[3];
    for (int a = 0; a < 3; ++a) {
        tangent[a] = velocity[a] + rate * n[a];
        T[a][0] = ground->tangent[0][a];
        T[a][1] = ground->tangent[1][a];
        z[a] = T[a][0] * y[k] + T[a][1] * y[k + 1];
    }
    const tb__friction_law law = {ground->static_friction, ground->kinetic_friction,
                                  ground->stribeck_velocity, 0.0};
    const double stiffness = mass * ground->gravity * ground->bristle_stiffness;
    const double damping = sqrt(stiffness * fmin(load->tangential * part, mass));
    tb__friction_jacobian fr;
    tb__anchor_jacobian(&law, stiffness, damping, N, n, tangent, z, &fr);
    tb__contact_point_rows(n, dN[0], dN[1], &fr, &T[0][0], 2, &p);
    tb__jacobian_add_point(rows, scene, &p);
}

/* The points of one body, [first, end), as apply_ground's loop body. */
static void body_rows(const tb__effect *effect, const tb_scene *scene, size_t first, size_t end,
                      const double *y, tb__jacobian_rows *rows)
{
    const tb__ground_params *ground = tb__ground_of(effect);
    const size_t body = scene->contacts[first].body, per = effect->states_per_contact;
    if (tb__body_asleep(scene, body)) {
        return; /* frozen anchors: zero rows */
    }
    const tb__motion *motion = tb__derivative_motion(scene, body);
    if (tb__ground_body_clear(ground, scene, first, end, motion)) {
        tb__jacobian_set_diagonal(rows, effect->state_offset + per * first, per * (end - first),
                                  -TB__BRISTLE_RELEASE_RATE);
        return;
    }
    tb__body_load load;
    tb__ground_body_load(ground, scene, first, end, motion, NULL, &load);
    for (size_t j = first; j < end; ++j) {
        const size_t k = effect->state_offset + per * j;
        point_rows(ground, scene, &scene->contacts[j], motion, &load, y, k, rows);
    }
}

int tb__ground_jacobian(const tb__effect *effect, const tb_scene *scene, double t, const double *y,
                        tb__jacobian_rows *rows)
{
    size_t first = 0;
    while (first < scene->contact_count) {
        const size_t end = tb__ground_run_end(scene, first);
        body_rows(effect, scene, first, end, y, rows);
        first = end;
    }
    tb__ground_shapes_jacobian(effect, scene, t, y, rows);
    return 0;
}
