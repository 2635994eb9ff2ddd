/* Contact events: when two bodies begin and end touching, and how hard they hit, handed to a
 * callback as the scene is stepped (a sound, a particle burst, a score). Units SI, vectors in the
 * world frame. docs/events.md describes the timing and the impulse and names their tests. */
#ifndef TUMBLE_CONTACT_EVENTS_H
#define TUMBLE_CONTACT_EVENTS_H

#include "tumble/export.h"

#include "tumble/effects.h" /* TB_WORLD */
#include "tumble/scene.h"
#include "tumble/status.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* What happened to a pair. At one time the order is begin, hit, end. */
typedef enum tb_contact_event_kind {
    TB_CONTACT_BEGIN = 0, /* the pair's deepest point went from apart (gap > 0) to touching */
    TB_CONTACT_HIT = 1,   /* a begin whose approach speed is at least the hit threshold */
    TB_CONTACT_END = 2,   /* the pair went from touching to apart */
} tb_contact_event_kind;

/* "begin", "hit", "end"; "unknown" for any other value. */
TB_API const char *tb_contact_event_kind_name(tb_contact_event_kind kind);

/* One event of a pair of bodies (contact between bodies, tb_scene_add_contact) or of a body and
 * a ground plane (tb_scene_add_ground: body_b is TB_WORLD). */
typedef struct tb_contact_event {
    tb_contact_event_kind kind;
    double t;              /* s: where the pair's gap crosses zero (docs/events.md) */
    size_t body_a, body_b; /* body ids, body_a < body_b; body_b TB_WORLD for a ground plane */
    double point[3];       /* m, world: the pair's deepest point */
    double normal[3];      /* unit, world, from body_a to body_b (into the ground for a plane) */
    double speed;          /* m/s: the normal speed at which the pair closes (begin, hit) or
                              separates (end) at t, >= 0 */
    double impulse;        /* N s: the normal impulse over the whole contact, at end; 0 else */
    size_t effect; /* the contact effect's or ground plane's index among the scene's effects */
} tb_contact_event;

/* Called at step boundaries (after a fixed step, at an adaptive method's step or event stop),
 * never inside a derivative; events come in the order of t, then body_a, body_b, effect, kind. It
 * must not change the scene (it is given none; changing calls refuse with TB_STATUS_BUSY), must
 * not step the scene's integrator, and must not destroy the scene. It may destroy the integrator
 * (to stop at the first hit): the advance stops at that step boundary (after the events of that
 * boundary) and returns TB_STATUS_OK, and the integrator is freed as it returns. */
typedef void (*tb_contact_event_fn)(const tb_contact_event *event, void *ctx);

typedef struct tb_contact_events_def {
    tb_contact_event_fn fn; /* required */
    void *ctx;              /* handed to fn */
    double hit_threshold;   /* m/s, >= 0: hits closing slower are not reported; default 0 */
    size_t pair_capacity;   /* pairs watched before the list grows (at a step boundary);
                               0 (default): 4 per body + 16 */
    int internal_cookie;
} tb_contact_events_def;

TB_API tb_contact_events_def tb_contact_events_def_default(void);

/* Starts reporting the events of every contact effect and ground plane of the scene, from the
 * next integrator made for it (tb_scene_integrator_create, tb_scene_run), to def->fn. Refuses
 * (changing nothing) a NULL def or fn (TB_STATUS_NULL_POINTER), a def not from
 * tb_contact_events_def_default, a negative threshold (TB_STATUS_INVALID_ARGUMENT), a NaN or
 * infinite one (TB_STATUS_NOT_FINITE); TB_STATUS_BUSY while an integrator steps the scene.
 * Setting again replaces the callback and forgets the pairs watched. */
TB_API tb_status tb_scene_set_contact_events(tb_scene *scene, const tb_contact_events_def *def);

/* Stops reporting events and frees what they used (NULL is fine). */
TB_API void tb_scene_clear_contact_events(tb_scene *scene);

/* Whether the events are whole: TB_STATUS_OUT_OF_MEMORY when the list of watched pairs could
 * not grow at some step boundary (pairs beyond it were not watched: events may be missing),
 * with the pairs left out, summed over the boundaries, in *out_dropped (may be NULL);
 * TB_STATUS_OK otherwise. (tests/test_contact_events_memory.c) */
TB_API tb_status tb_scene_contact_events_status(const tb_scene *scene, size_t *out_dropped);

/* One impact a fixed step did not resolve (tb_scene_unresolved_impacts). */
typedef struct tb_impact {
    double t;              /* s: when the pair began touching (its begin event's time) */
    size_t body_a, body_b; /* body ids, body_a < body_b; body_b TB_WORLD for a ground plane */
    size_t effect;         /* the contact effect's or ground plane's index among the effects */
    double speed;          /* m/s: the normal speed at which the pair closed at t */
    double duration;       /* s: how long the pair's law pushes through an impact */
    double steps;          /* duration / dt: the steps the impact lasted (below 1: inside one) */
} tb_impact;

/* What the newest integrator's fixed step left unresolved. An impact is a pair beginning to touch
 * (a contact event's begin) at a normal speed above g dt (g the law's gravity: slower, a body
 * settling on its support, whose bounce e v < g dt would rise less than g dt^2 / 2 and fall back
 * within two steps), whose law's rate omega (the pair taken as its landing point: omega
 * sqrt(M_light share / m) between bodies, omega0 sqrt(M share / m) on a plane, share the landing
 * point's part of the law: 1 / support for contact points, 1 / the points of the manifold landing
 * together for shapes; m the effective mass at the point) is too fast
 * for dt: dt omega above 0.1 for rosenbrock (its default step's resolution, where it keeps e = 0.5
 * within 2 %), above the stability limit for the explicit methods (allow_unstable only). Under
 * rosenbrock an impact of duration shorter than about 30 steps is counted; the restitution comes
 * out lower, the more so the fewer (docs/integrators.md, "Restitution"). */
typedef struct tb_unresolved_impacts {
    bool watched;      /* the step could leave an impact unresolved, so they were counted: a fixed
                          step with dt omega above the resolution on the scene's fastest oscillation
                          (the stability guard's bound) at the integrator's start; false for an
                          adaptive method (error control resolves impacts) or a resolving step */
    double dt;         /* s: the step counted against (0 when not watched) */
    double resolution; /* the dt omega above which an impact counts (0 when not watched) */
    size_t count;      /* impacts since the integrator was made; a tb_integrator_reset to t
                          keeps those at or before t, as a run stopped at t counted them */
    tb_impact first;   /* the earliest of them (zeros when count is 0) */
    tb_impact fastest; /* the one that closed fastest, the earliest of equals */
} tb_unresolved_impacts;

/* The count of the newest integrator made on the scene (tb_scene_integrator_create, tb_scene_run)
 * so far: nothing to set up, and nothing done per step unless watched (then a pass over the pairs
 * near each other per step, as contact events, and no change to any step's result). Refuses a
 * NULL pointer (TB_STATUS_NULL_POINTER); TB_STATUS_OUT_OF_MEMORY when the pairs' list could not
 * grow at some step (impacts may be missing; *out still written). (tests/test_impacts.c) */
TB_API tb_status tb_scene_unresolved_impacts(const tb_scene *scene, tb_unresolved_impacts *out);

#ifdef __cplusplus
}
#endif

#endif
