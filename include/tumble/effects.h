/* Effects beyond gravity and constant forces: drag, springs, contact with a ground plane
 * with friction, and user callbacks. Each adds to the forces F and torques tau of the bodies
 * it names; a scene pays only for the effects it holds. Units SI, vectors world frame unless
 * stated. Every def is filled by its *_def_default() and checked when added; a refused
 * effect changes nothing. */
#ifndef TUMBLE_EFFECTS_H
#define TUMBLE_EFFECTS_H

#include "tumble/export.h"

#include "tumble/scene.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Stands for "every body" where an effect takes a body id. */
#define TB_ALL_BODIES ((size_t)-1)
/* Stands for the fixed world where a spring takes its second body. */
#define TB_WORLD ((size_t)-1)

/* --- drag ---------------------------------------------------------------------------------
 * F = -linear v - quadratic |v| v,   tau = -angular omega - angular_quadratic |omega| omega,
 * on the centre-of-mass velocity v and angular velocity omega. */
typedef struct tb_drag_def {
    size_t body;              /* a body id or TB_ALL_BODIES (default) */
    double linear;            /* N s/m, >= 0 */
    double quadratic;         /* N s^2/m^2, >= 0 */
    double angular;           /* N m s, >= 0 */
    double angular_quadratic; /* N m s^2, >= 0 */
    int internal_cookie;
} tb_drag_def;

TB_API tb_drag_def tb_drag_def_default(void);
TB_API tb_status tb_scene_add_drag(tb_scene *scene, const tb_drag_def *def);

/* --- springs ------------------------------------------------------------------------------
 * A Hooke spring with damping between point_a fixed in body_a and point_b fixed in body_b
 * (both in the bodies' shape frames, m) or, with body_b = TB_WORLD, the world point point_b.
 * With d = p_a - p_b: F_a = -k (|d| - rest_length) d/|d| - c ((v_a - v_b) . d/|d|) d/|d| at
 * p_a, and -F_a at p_b. At |d| = 0 the direction is undefined and the spring exerts nothing. */
typedef struct tb_spring_def {
    size_t body_a;
    double point_a[3];
    size_t body_b; /* a body id or TB_WORLD (default) */
    double point_b[3];
    double stiffness;   /* k, N/m, >= 0 */
    double damping;     /* c, N s/m, >= 0 */
    double rest_length; /* m, >= 0 */
    int internal_cookie;
} tb_spring_def;

TB_API tb_spring_def tb_spring_def_default(void);
TB_API tb_status tb_scene_add_spring(tb_scene *scene, const tb_spring_def *def);

/* --- contact with a ground plane ------------------------------------------------------------
 * Bodies touch the plane through contact points: points fixed in the body (shape frame) with
 * a radius (0 for a corner, r for a sphere's centre). A point whose sphere dips below the
 * plane n . x = offset by delta gets a normal force N = max(0, k delta + c delta') at the
 * sphere's lowest point (delta' the rate of sinking; never pulling), with k = M g / (support
 * penetration) for a body of mass M whose weight rests on `support` of its points (4 of a box's
 * 8 corners): at rest the body sinks by `penetration`, whatever its mass, and the contact rings
 * at omega = sqrt(g / penetration) rad/s. The dashpot is sized where it acts, c = 2 zeta
 * sqrt(k m) with m the point's share of the effective mass 1 / (1/M + (r x n) . I^-1 (r x n)) at
 * the touching points' centre of pressure r (M / support for a face landing flat, the point's
 * own for one point), and fades in from touchdown (c w delta / (w delta + delta' / 2),
 * w = sqrt(k / m)) so that N is continuous. The damping ratio zeta is chosen from `restitution`
 * so that a point that hits the plane alone at v, anywhere on the body, leaves at e v whatever
 * v (e below 0.062 gets zeta = 3, e = 0.062).
 *
 * Friction is Coulomb's, static and kinetic, through a stick anchor with plastic slip: each
 * contact point carries a tangential deflection z, a spring k = m g mu_s / presliding
 * (m = M / support) and damper sqrt(k m_t) (m_t its share of the effective mass across the
 * normal, at most m) whose force is capped at mu N. z follows the point while it sticks;
 * beyond the static cone mu_s N / k the excess relaxes at 400 per second, which makes
 * w = 400 (excess) the slip speed, and mu = mu_k + (mu_s - mu_k) exp(-(w / stribeck_velocity)^2)
 * falls with the slip, not with the velocity: a body released at rest under a load below
 * mu_s N stays, with the spring deflected by less than `presliding`, and does not creep.
 * Sliding, the force is mu_k N. The deflections are extra state (2 doubles per contact point and
 * plane) kept after the bodies' states; they relax to zero when a point leaves the plane. The
 * defaults are stiff enough for impacts (a 5 cm die dropped from 1 m sinks at most 2 mm), which
 * makes fixed-step methods need more than 240 steps per second: give them dt = 0 for the scene's
 * default step (tb_scene_default_step). A body whose contact point starts deeper than 10
 * penetrations inside the plane is refused (TB_STATUS_INVALID_ARGUMENT, naming it and its depth)
 * by tb_scene_add_ground or tb_scene_set_contact_points, whichever comes last: the contact would
 * launch it. So is a point, or a shape the plane meets (there and at tb_scene_set_body_shape),
 * reaching so far from its body's centre of mass that its depth's rounding (the reach times
 * 2^-52) exceeds the penetration, or that the contact's rate M reach^2 / I overflows: the force
 * would be noise larger than the body's weight (a 1e90 m sphere on 1 kg). A rate
 * sqrt(gravity / penetration) of 0 or above 1e9 rad/s is refused, as the contact's is, and so is
 * a friction spring rate sqrt(gravity static_friction / presliding) above 1e9 rad/s. A plane
 * facing the way an
 * earlier ground plane faces (normals within 1e-6 rad) is refused (TB_STATUS_INVALID_ARGUMENT
 * naming the earlier one): the two would push the same points twice, or one would lie buried in the
 * other's ground (tests/test_effects.c). */
typedef struct tb_ground_def {
    double normal[3];         /* pointing out of the ground, any finite nonzero length (normalised,
                                 scaled first: (0,0,1e-300) is up); default (0,0,1) */
    double offset;            /* the plane is n . x = offset with n the unit normal (the
                                 plane's signed distance from the origin whatever the normal's
                                 length: (0, 0, 2) with offset 1 is z = 1), m; default 0 */
    double gravity;           /* g used to size the contact, m/s^2, > 0; default 9.81 */
    double penetration;       /* static sinking under a body's own weight, m, > 0; 8e-7 */
    double restitution;       /* e in [0, 1]: a point hits at v and leaves at e v; default 0.3 */
    double static_friction;   /* mu_s >= mu_k; default 0.6 */
    double kinetic_friction;  /* mu_k >= 0; default 0.5 */
    double stribeck_velocity; /* m/s, > 0: speed over which mu falls from mu_s to mu_k;
                                 default 0.01 */
    double presliding;        /* deflection at breakaway under a body's own weight, m, > 0;
                                 default 5e-7; the friction spring's rate sqrt(gravity
                                 static_friction / presliding) at most 1e9 rad/s, as the
                                 normal law's (so >= 5.9e-18 m at mu_s 0.6, g 9.81) */
    int internal_cookie;
} tb_ground_def;

TB_API tb_ground_def tb_ground_def_default(void);
TB_API tb_status tb_scene_add_ground(tb_scene *scene, const tb_ground_def *def);

typedef struct tb_contact_point {
    double position[3]; /* in the body's shape frame, m */
    double radius;      /* >= 0, m */
} tb_contact_point;

/* Sets (replaces) body id's contact points; count 0 removes them. Copies the array. support
 * (1 .. count) is how many of them carry the body's weight when it rests: it sizes the
 * contact stiffness (4 for a box's corners, 1 for a sphere, 2 for a capsule lying down). */
TB_API tb_status tb_scene_set_contact_points(tb_scene *scene, size_t id,
                                             const tb_contact_point *points, size_t count,
                                             size_t support);

/* Contact points for common shapes, in the shape frame. out has room for `capacity` points;
 * *out_count receives the number written (8 for a box, 1 for a sphere, 2 for a capsule);
 * their support is 4, 1 and 2. */
TB_API tb_status tb_contact_points_box(const double size[3], tb_contact_point *out, size_t capacity,
                                       size_t *out_count);
TB_API tb_status tb_contact_points_sphere(double radius, tb_contact_point *out, size_t capacity,
                                          size_t *out_count);
TB_API tb_status tb_contact_points_capsule(double radius, double length, tb_contact_point *out,
                                           size_t capacity, size_t *out_count);

/* --- contact between bodies -----------------------------------------------------------------
 * Bodies with collision shapes (tb_scene_set_body_shape, include/tumble/shape.h) push each other
 * apart where they overlap, with the ground's normal law (see above) at each point of a pair's
 * contact manifold (up to 4 points, src/contact/narrow_phase.h): per point k = M_min g /
 * (points penetration), the damping from `restitution` at the point's share of the effective
 * mass at the pair's centre of pressure (both bodies' 1/M + (r x n) . I^-1 (r x n)), so that two
 * free bodies meeting at one point, anywhere on them, part at e times their approach speed.
 * Friction: the ground's stick anchor (above) at each touching point that holds one of the effect's
 * friction_points slots: a tangential deflection z, 3 doubles of state per slot in the first body's
 * principal frame, a spring k = M_min g mu_s / (points presliding) capped at mu N, mu falling from
 * mu_s to mu_k with the slip speed over stribeck_velocity; a load below mu_s N is held without
 * creep. The slots are allocated here, so the state's length is fixed when the effect is
 * added; a point finds its slot again by its position in the first body's frame, a slot is
 * freed at a step boundary once its pair has parted and its spring relaxed, and a point that
 * finds no free slot gets the memoryless mu(v) N v / sqrt(v^2 + v_reg^2), v_reg = sqrt(mu_s g
 * presliding) (1.7 mm/s at the defaults), which creeps (counted: tb_scene_contact_friction_stats).
 * Forces on the two bodies are equal and opposite at the same world point: linear and angular
 * momentum are conserved. bodies NULL (body_count 0): every body of the scene when the effect is
 * added; bodies added later are not included. */
typedef struct tb_contact_def {
    const size_t *bodies; /* ids, each at most once, copied; NULL: every body */
    size_t body_count;
    double restitution;       /* e in [0, 1]; default 0.3 */
    double static_friction;   /* mu_s >= mu_k; default 0.6 */
    double kinetic_friction;  /* mu_k >= 0; default 0.5 */
    double penetration;       /* m, > 0: sets omega = sqrt(g / penetration); default 8e-7 */
    double gravity;           /* m/s^2, > 0, sizes the contact; default 9.81 */
    double stribeck_velocity; /* m/s, > 0; default 0.01 */
    double presliding;        /* m, > 0: the spring's deflection at breakaway; default 5e-7;
                                 bounded as the ground's (its rate at most 1e9 rad/s) */
    /* Touching points that keep a friction state (slots of the pool); 0 (default): 6 per
     * body of the effect (a box on a box takes 4). At most 8 per pair of pieces of the effect's
     * bodies as they are when it is added (a manifold of 4 touching points per piece pair, each
     * with a slot relaxing beside it; a plain shape is one piece) or 6 per body, if more. */
    size_t friction_points;
    int internal_cookie;
} tb_contact_def;

TB_API tb_contact_def tb_contact_def_default(void);
/* Refuses (TB_STATUS_INVALID_ARGUMENT, naming the field or the bodies; nothing added) a bad
 * field (NaN or infinite: TB_STATUS_NOT_FINITE); a list of bodies with body_count 0, of one body,
 * or of static and keyframed bodies only (an effect that touches nothing); a contact rate
 * sqrt(gravity / penetration) above 1e9 rad/s (an impact shorter than 3 ns), or a friction spring
 * rate sqrt(gravity static_friction / presliding) above it; friction_points past its bound; a
 * repeated id (so a
 * body_count past the scene's is refused after reading at most body count + 1 ids), an id past
 * the scene (TB_STATUS_OUT_OF_RANGE); a listed body without a collision shape, or with one whose
 * reach from its centre of mass is too large for penetration (as a ground plane's shapes are;
 * tb_scene_set_body_shape refuses the same later, and refuses to remove a listed body's shape);
 * and a set that shares two bodies with an earlier contact effect (that pair would be pushed by
 * both).
 * tb_scene_integrator_create, and every advance, step and reset after the state (or a shape) was
 * changed from outside, then refuse a state in which a pair lies deeper inside each other than 10
 * times the depth that carries the heavier body's weight, or past the thinner body's middle. */
TB_API tb_status tb_scene_add_contact(tb_scene *scene, const tb_contact_def *def);

/* What a contact effect's friction pool did, counted at step boundaries (after every fixed
 * step, before every adaptive step and at every output). */
typedef struct tb_contact_friction_stats {
    size_t slots; /* the pool's size (friction_points) */
    /* slots claimed at the last boundary: by touching points, reserved for points within the
     * contact margin, or relaxing before they are free again */
    size_t in_use;
    size_t peak_in_use;            /* the most claimed at once */
    unsigned long long boundaries; /* step boundaries seen */
    unsigned long long overflows;  /* touching points found without a free slot, summed over
                                      boundaries: they had the memoryless law */
} tb_contact_friction_stats;

/* The stats of effect number `effect` (0 .. tb_scene_effect_count - 1, in the order added),
 * which must be a contact effect (TB_STATUS_INVALID_ARGUMENT otherwise). */
TB_API tb_status tb_scene_contact_friction_stats(const tb_scene *scene, size_t effect,
                                                 tb_contact_friction_stats *out_stats);

/* --- user effects -------------------------------------------------------------------------
 * A callback that adds forces and torques. It receives the time and the scene's state array y
 * as the derivative sees it (read it with the tb_scene_body_* read-outs, passing y), and adds
 * its loads into dydt with tb_effect_add_force / tb_effect_add_torque only. Return 0, or
 * non-zero to fail the derivative (> 0 recoverable, < 0 fatal). It must not change the scene
 * (changing calls refuse with TB_STATUS_BUSY while the scene is being stepped), and must not
 * allocate if the no-allocation guarantee is to hold. */
typedef int (*tb_user_effect_fn)(double t, const tb_scene *scene, const double *y, double *dydt,
                                 void *ctx);

TB_API tb_status tb_scene_add_user_effect(tb_scene *scene, tb_user_effect_fn fn, void *ctx);

/* For user effects: adds force f (N, world) at world point p (m) to body id: F += f,
 * tau += (p - x) x f. Refuses, adding nothing and naming the argument in the scene's detail:
 * a NULL y, dydt, force or point (TB_STATUS_NULL_POINTER), id past the body count
 * (TB_STATUS_OUT_OF_RANGE), NaN or infinity in force or point (TB_STATUS_NOT_FINITE). A
 * refused load fails the derivative (as if the callback returned -1) unless the callback itself
 * returns non-zero, so that a missing force never passes silently. */
TB_API tb_status tb_effect_add_force(const tb_scene *scene, const double *y, double *dydt,
                                     size_t id, const double force[3], const double point[3]);

/* For user effects: adds torque (N m, world) to body id; refuses as tb_effect_add_force. */
TB_API tb_status tb_effect_add_torque(const tb_scene *scene, double *dydt, size_t id,
                                      const double torque[3]);

#ifdef __cplusplus
}
#endif

#endif
