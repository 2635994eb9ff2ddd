/* Private: the scene object, shared by the scene, read-out, effect and derivative sources. */
#ifndef TUMBLE_SCENE_INTERNAL_H
#define TUMBLE_SCENE_INTERNAL_H

#include "tumble/effects.h"
#include "tumble/scene.h"

/* What the derivative needs of a body, packed together for the hot loop. */
typedef struct tb__body {
    double mass;           /* kg */
    double inv_mass;       /* 1/kg */
    double inv_moments[3]; /* 1/(kg m^2), principal frame */
} tb__body;

typedef struct tb__effect tb__effect;

/* A body's visual meshes, what writers draw (src/contact/body_visuals.c): meshes[k] is piece
 * k's (the only one, k = 0, of a body without a shape), NULL where it has none; each one
 * allocation freed by free(). */
typedef struct tb__body_visuals {
    size_t count;
    struct tb__visual_mesh *meshes[];
} tb__body_visuals;

/* Adds the effect's forces into dydt[13 i + TB_STATE_P ..] and torques into
 * dydt[13 i + TB_STATE_L ..], and writes the derivatives of the states it owns. Pure: reads y,
 * writes only those slots. Returns 0, or the failure of a user callback. */
typedef int (*tb__effect_apply)(const tb__effect *effect, const tb_scene *scene, double t,
                                const double *y, double *dydt);

/* The same for an effect that acts on each body alone (no coupling, no states of its own): adds
 * into the bodies [first, first + count) only, y and dydt pointing at body first's state. The
 * whole derivative calls it with first = 0 and count = body_count; the chunked steppers of a
 * separable scene with ranges. */
typedef int (*tb__effect_apply_bodies)(const tb__effect *effect, const tb_scene *scene, double t,
                                       const double *y, double *dydt, size_t first, size_t count);

/* An effect's fastest modes at a state, for the stability guard, split by where their
 * eigenvalues lambda of the linearised motion lie: oscillation bounds |lambda| of the modes near
 * the imaginary axis, decay |lambda| of those on the negative real axis (1/s; 0: none), each
 * body's inverse mass and inverse inertia at the effect's arms included. *_body is where each is
 * fastest (TB_ALL_BODIES when none). */
typedef struct tb__effect_rate {
    double oscillation; /* 1/s, >= 0 */
    size_t oscillation_body;
    double decay; /* 1/s, >= 0 */
    size_t decay_body;
    double ringing; /* 1/s: its damped modes' fastest natural rate, overdamped too (impacts) */
} tb__effect_rate;

/* Raise out's fastest modes by a damped mode of natural rate omega and damping ratio zeta on
 * body: oscillating (|lambda| = omega) when underdamped, decaying at its fast root omega (zeta +
 * sqrt(zeta^2 - 1)) when overdamped, ringing at omega either way; or by a decay at rate (1/s). */
void tb__effect_rate_add_damped_mode(tb__effect_rate *out, double omega, double zeta, size_t body);
void tb__effect_rate_add_decay(tb__effect_rate *out, double rate, size_t body);

/* A per-body effect's lane forms on every body, one per vector path (lanes.h); an effect
 * without them is applied lane by lane through apply_bodies, with the same arithmetic. */
typedef struct tb__effect_lanes tb__effect_lanes;

typedef struct tb__event_pair tb__event_pair; /* below */
typedef struct tb__effect_stepping tb__effect_stepping;
struct tb__impact_law; /* below */

/* Visits one coupling for the Jacobian's pattern (scene_jacobian.c): the effect's states
 * [first_state, first_state + state_count) of y depend on, and act on, bodies body_a and body_b
 * (ids; TB_ALL_BODIES for none, body_b == body_a for one body). */
typedef void (*tb__coupling_visit)(void *ctx, size_t first_state, size_t state_count, size_t body_a,
                                   size_t body_b);

struct tb__jacobian_rows; /* an effect's analytic Jacobian rows being written: jacobian_rows.h */
/* One constant row per effect kind (the core row), defined in the kind's file in src/effects/:
 * every fact about the kind that the derivative, the read-outs, the stability guard and the
 * sleeping islands ask; nothing outside the effect's own files reads its parameters. An effect
 * that also shapes the steps (contact, ground) points to a second row, tb__effect_stepping;
 * a simple effect is its file and this one row. */
typedef struct tb__effect_ops {
    const char *name;                     /* "gravity", "drag", "spring", "ground", ... */
    const tb__effect_lanes *lanes;        /* per-body effects: its lane forms, or NULL */
    tb__effect_apply apply;               /* effects that couple bodies or own states */
    tb__effect_apply_bodies apply_bodies; /* per-body effects: exactly one of the two is set */
    bool couples_bodies;                  /* its loads on one body depend on another's state */
    bool owns_states;                     /* keeps states of its own after the bodies' */
    bool conserves_momentum;              /* its loads sum to zero force and zero torque */
    /* Its loads sum to zero torque about the centre of mass of all bodies, though not to zero
     * force (uniform gravity: sum (x_i - c) x M_i g = 0 about c = sum M_i x_i / sum M_i). */
    bool no_torque_about_center_of_mass;
    /* Its potential energy (J) at y; NULL when it has none (non-conservative loads). */
    double (*potential_energy)(const tb__effect *effect, const tb_scene *scene, const double *y);
    /* True when it does no work besides its potential's (springs without damping); NULL: no. */
    bool (*conserves_energy)(const tb__effect *effect);
    /* Its fastest mode at y (see tb__effect_rate); NULL when it adds none (constant loads) or
     * cannot know (user callbacks). */
    void (*rate)(const tb__effect *effect, const tb_scene *scene, const double *y,
                 tb__effect_rate *out);
    /* Refuses a state it cannot start from (a body deep inside a ground plane) with a detail
     * naming the body, written into detail (TB_DETAIL_SIZE bytes); NULL: accepts every state. */
    tb_status (*check_start)(const tb__effect *effect, const tb_scene *scene, const double *y,
                             char *detail);
    /* Frees what the effect's parameters own (the contact effect's pair finder) when the scene
     * is destroyed; NULL: they own nothing. */
    void (*release)(tb__effect *effect);
    /* Sleeping islands (sleep.c): the body the effect ties effect->body to, so that the two
     * sleep and wake together (a spring's second body), or TB_ALL_BODIES; NULL: none. */
    size_t (*sleep_partner)(const tb__effect *effect);
    /* The effect's loads may change while the bodies rest (a user callback of t): while the
     * scene holds it, no body sleeps. */
    bool keeps_awake;
    /* The hooks of an effect that shapes the steps (events, step limits, impacts, step
     * boundaries, waking); NULL for an effect with none. */
    const tb__effect_stepping *stepping;
    /* For an effect that owns states: which bodies each group of its states belongs to at a
     * step boundary (scene_jacobian.c's pattern), visiting every state once. NULL: unknown (a
     * scene holding such an effect offers no Jacobian). */
    void (*state_owners)(const tb__effect *effect, const tb_scene *scene, tb__coupling_visit visit,
                         void *ctx);
    bool constant_loads; /* loads that do not depend on y (gravity): no Jacobian rows */
    /* Adds its analytic Jacobian rows at (t, y) (scene/jacobian_rows.h), pure and
     * allocation-free like apply; NULL: difference quotients (scene_jacobian_values.c). */
    int (*jacobian)(const tb__effect *effect, const tb_scene *scene, double t, const double *y,
                    struct tb__jacobian_rows *rows);
} tb__effect_ops;

/* The optional second row of an effect kind: what the events, the adaptive step limit, the
 * tunnelling and impact checks, the step boundaries and the waking of sleeping islands ask of
 * an effect that makes bodies touch (contact, ground). Each hook NULL: none. */
struct tb__effect_stepping {
    /* Events (effect_contact_events.c): lowers gap[i] (m, filled with TB__EVENT_LOOKAHEAD) to
     * body i's gap to what the effect makes it touch, where that is smaller: negative in
     * contact, continuous in y. The scene's root functions are these gaps, one per body, so an
     * adaptive step ends where a body's contact begins or ends. With signs, only whether each
     * gap is below zero need be exact (tb__scene_root_signs). NULL: no events. */
    void (*event_gaps)(const tb__effect *effect, const tb_scene *scene, const double *y,
                       double *gap, bool signs);
    /* Waking under adaptive methods (sleep.c): lowers wake[i] (filled with
     * TB__EVENT_LOOKAHEAD) to the distance beyond TB__WAKE_DISTANCE of the nearest pair the
     * effect finds between body i and a body of the other sleep state (one asleep, one
     * awake), continuous in y while the flags stay. The scene's second set of root functions,
     * so that CVODE stops before such a pair can touch and wakes the island there. NULL: the
     * effect brings no body to a sleeping one (but through sleep_partner). With gap not NULL
     * it also does event_gaps' work on gap, in the same pass over the pairs (the two root sets
     * come at the same (t, y); an effect with wake_gaps has event_gaps); signs as there. */
    void (*wake_gaps)(const tb__effect *effect, const tb_scene *scene, const double *y, double *gap,
                      double *wake, bool signs);
    /* Links (tb__scene_sleep_link) every pair of its bodies that could come within its margin
     * in a step of dt from y (dt 0: within the margin now), so that a fixed step never starts
     * with a sleeping body that it would bring into contact. NULL: none. */
    void (*wake_links)(const tb__effect *effect, const tb_scene *scene, const double *y, double dt);
    /* The longest adaptive step from y (with dydt its derivative there, NULL before the first
     * step) that cannot step over one of the effect's pushes whole (s, INFINITY for none): a
     * collision between bodies of finite thickness is a push with nothing before or after it,
     * which a long step would never sample. Long where bodies are far apart for their speeds,
     * short near a contact. NULL: none. */
    double (*adaptive_step_limit)(const tb__effect *effect, const tb_scene *scene, const double *y,
                                  const double *dydt);
    /* The longest fixed step from y in which no body it makes touch can pass through another
     * (s, INFINITY for none), the pair that sets it in which (TB_DETAIL_SIZE bytes): a quick
     * bound; where dt (the step checked, s; 0: none) is longer, each pair's own, at least as
     * long. NULL: the effect has no bodies to pass through. */
    double (*tunnel_step)(const tb__effect *effect, const tb_scene *scene, const double *y,
                          double dt, char *which, size_t size);
    /* Refuses a state from which a body could pass through another under every method and step
     * (faster than the effect's law can stop before the thinner body's middle), with a detail
     * naming both in detail (TB_DETAIL_SIZE bytes); run at integrator creation and before every
     * advance (tb__scene_check_impacts). NULL: none. */
    tb_status (*check_impacts)(const tb__effect *effect, const tb_scene *scene, const double *y,
                               char *detail);
    /* Bookkeeping outside y the derivative reads (the friction slot map), at each step boundary
     * with its accepted state: post_step after every fixed step, CVODE output and BDF projection,
     * step_start before every adaptive step (tb__scene_step_limit; Adams has no other), no islands
     * linked. Never inside a derivative; y and the derivative at y stay. NULL: none. */
    void (*post_step)(const tb__effect *effect, const tb_scene *scene, const double *y);
    void (*step_start)(const tb__effect *effect, const tb_scene *scene, const double *y);
    /* An integrator made or reset at t from y (tb__scene_restart): that bookkeeping starts again
     * from y alone, unless it continues where the last boundary was, so that a run from a state
     * is the same whatever ran on the scene before. NULL: none. */
    void (*restart)(const tb__effect *effect, const tb_scene *scene, double t, const double *y);
    /* Body id's shape was set or removed (scene idle): the effect may change its state count (the
     * scene lays the states out once all passed) or fail (detail); shapes_settled(undo) ends each
     * that ran, the failing one too: undo (a failure anywhere) puts all back. */
    tb_status (*shapes_changed)(tb__effect *effect, tb_scene *scene, size_t id);
    void (*shapes_settled)(tb__effect *effect, bool undo);
    /* Before any effect's shapes_changed: whether body id's new shape (set, or NULL: removed)
     * is one the effect can push; a refusal (the scene's detail naming the body and the effect)
     * leaves the old shape in place. Changes nothing. NULL: every shape will do. */
    tb_status (*check_shape)(const tb__effect *effect, tb_scene *scene, size_t id);
    /* Body id's points were just set: contacts[first .. contact_count). Refuses, as check_start
     * would, what the change made wrong for body id alone, at y (the other bodies as check_start
     * last saw them); uncheck_points undoes what it changed when a later effect's refuses. */
    tb_status (*check_points)(const tb__effect *effect, const tb_scene *scene, const double *y,
                              size_t id, size_t first, char *detail);
    void (*uncheck_points)(const tb__effect *effect);
    /* Contact events (scene/contact_event_watch.c): writes the effect's pairs within
     * TB__EVENT_LOOKAHEAD at y, the first capacity of them into out (tb__event_pair), and
     * returns how many there are. Called at step boundaries only. NULL: no contact events. */
    size_t (*event_pairs)(const tb__effect *effect, const tb_scene *scene, const double *y,
                          tb__event_pair *out, size_t capacity);
    /* Unresolved impacts (impact_watch.c): the law a pair of its bodies meets as an impact,
     * pair as its event_pairs gave it where it began to touch (ids, body_b TB_WORLD for a ground
     * plane; the inverse mass and the law's share at the point). NULL: no impacts (an effect
     * with event_pairs has it). */
    void (*impact_law)(const tb__effect *effect, const tb_scene *scene,
                       const struct tb__event_pair *pair, struct tb__impact_law *out);
};

/* What a pair's impact is under an effect's law (tb__effect_stepping.impact_law): the whole pair
 * taken as one point (a centred hit, a flat landing: the law's own oscillator). */
struct tb__impact_law {
    double rate;     /* rad/s: the pair's natural rate, omega sqrt(M k_share / m_eff) */
    double duration; /* s: how long the force acts (tb__contact_push_duration / rate) */
    double gravity;  /* m/s^2: the gravity the law was sized for (its penetration's) */
};

/* A pair as the contact events see it at a state (tb__effect_ops.event_pairs). */
struct tb__event_pair {
    size_t body_a, body_b; /* body_a < body_b; body_b TB_WORLD for a ground plane */
    size_t effect;         /* the effect's index (set by the watch, not the op) */
    double gap;            /* m: minus the deepest point's depth (negative: touching) */
    double gap_rate;       /* m/s: d gap / dt, (v_b - v_a) . normal at the point */
    double point[3];       /* the deepest point, world */
    double normal[3];      /* unit, from a to b */
    double inverse_mass;   /* 1/kg: of the pair's relative motion along the normal at the point */
    double share;          /* the part of the law's stiffness that pushes at the point alone: a
                              ground contact point's share of its body's weight (1 / support),
                              1 / the manifold's points within the law's margin for a pair of
                              shapes (between bodies, or a body's and a plane) */
    double gravity;        /* m/s^2: the uniform acceleration closing the pair that its own
                              motion does not cancel (a body on a ground plane: the plane's g) */
};

/* The gap (m) the event functions start from: a body farther than this from everything it can
 * touch has this gap, and the adaptive step limit sees the pairs closer than it. */
#define TB__EVENT_LOOKAHEAD 0.05

/* m: a pair of an awake and an asleep body this close wakes the asleep one's island at an
 * adaptive method's event stop (half the contact's 1 mm margin, so that the pair the stop
 * finds is surely within the margin that links it). */
#define TB__WAKE_DISTANCE 5e-4

/* One entry of the compiled effect list: its row and its parameters. The scene sees no kind:
 * each kind's parameter struct is its effect file's (or its kind header's in src/effects/), and
 * only that file reads it, through params. */
struct tb__effect {
    const tb__effect_ops *ops;
    size_t body;               /* the body acted on, or TB_ALL_BODIES (the derivative's order) */
    size_t slot;               /* body's slot, TB_NO_SLOT for none (set when pushed) */
    size_t states_per_contact; /* states owned per contact point (ground planes: 2) */
    size_t fixed_states;       /* states owned whatever the points (contact's friction slots) */
    size_t state_offset;       /* where in y those states start */
    double state_scale;        /* natural size of those states, for absolute tolerances */
    /* The kind's parameters: one allocation the scene owns (tb__scene_push_effect copies
     * them), freed after the row's release has freed what they own. */
    void *params;
};

/* The row of an effect without stepping hooks: every hook NULL. */
extern const tb__effect_stepping tb__effect_no_stepping;

/* The effect's stepping row, or tb__effect_no_stepping. */
static inline const tb__effect_stepping *tb__stepping_of(const tb__effect *effect)
{
    return effect->ops->stepping != NULL ? effect->ops->stepping : &tb__effect_no_stepping;
}

/* A contact point of a body, for ground planes. Points of one body are contiguous. */
typedef struct tb__contact {
    size_t body;
    double r[3];   /* principal frame, from the centre of mass, m */
    double radius; /* m */
    double share;  /* 1 / (number of the body's contact points) */
} tb__contact;

#include "scene/constraint_ops.h" /* the row the scene holds its constraints by */

struct tb_scene {
    size_t body_count;
    size_t body_capacity;
    double *states;        /* 13 * body_count body states, then extra_count effect states */
    size_t state_capacity; /* doubles allocated in states */
    size_t extra_count;
    /* Body kinds and slots (body_motion.c). slots[id] is body id's slot: the index of its 13
     * doubles in y and of its constants in bodies, or TB_NO_SLOT for a body with no state;
     * slot_ids[slot] is the body of a slot. Slots are given in the order bodies are added, so
     * both maps are increasing. slot_count dynamic bodies; body_capacity entries each. */
    size_t *slots;
    size_t *slot_ids;
    size_t slot_count;
    /* The bodies with no state (static, keyframed), in the order added: body_count - slot_count
     * of them (body_capacity entries). */
    size_t *fixed_ids;
    struct tb__body_kind *kinds; /* body_capacity, by id: each body's kind and fixed pose */
    double *reactions; /* NULL, or 6 per body while tb_scene_body_reaction runs the derivative:
                          the force and torque the effects put on bodies without a state */
    /* The time (s) of the scene's states: 0 at creation, set where an integrator writes its
     * states back and by tb_scene_set_time; the time read-outs without a t ask bodies with no
     * state for their motion at. */
    double time;
    tb__body *bodies; /* body_capacity, by slot */
    /* Scratch of tb_scene_derivative, body_capacity entries by id: each body's motion at the y
     * being evaluated (tb__body_motion), filled by its kinematics stage once per evaluation and
     * read by the coupled effects (tb__derivative_motion), so that no effect recomputes a body's
     * rotation and angular velocity per point or per pair. Written through the const scene,
     * like the contact pair finder's scratch. */
    struct tb__motion *motions;
    tb_mass_properties *mass_props; /* body_capacity, as given */
    char (*names)[TB_NAME_SIZE];    /* body_capacity */
    tb__effect *effects;
    size_t effect_count;
    size_t effect_capacity;
    /* The order the derivative applies effects in, as indices into effects: per-body effects
     * on every body (in the order added), then per-body effects on one body (by body, stably,
     * so a chunk of bodies finds its own by bisection), then coupled effects (in the order
     * added). effect_capacity entries. */
    size_t *effect_order;
    size_t all_body_effect_count, single_body_effect_count, coupled_effect_count;
    tb__contact *contacts;
    size_t contact_count;
    size_t contact_capacity;
    size_t contact_bodies_end; /* 1 + the largest id of a body with points (0: none) */
    /* Collision shapes (src/contact/collision_shape.c): shapes[i] is body i's, NULL when it has
     * none; shape_capacity entries (at most body_count), each one allocation freed by free(). */
    struct tb__collision_shape **shapes;
    size_t shape_capacity;
    /* Visual meshes (src/contact/body_visuals.c): visuals[i] is body i's, NULL when none of its
     * pieces has one; visual_capacity entries (at most body_count). */
    struct tb__body_visuals **visuals;
    size_t visual_capacity;
    /* Counts changes of the effects that leave the layout alone (an effect added): the
     * right-hand side changed, so an integrator with a history of it (CVODE) restarts. */
    unsigned long long effects_generation;
    /* The first refused tb_effect_add_force/_torque of the user effect being applied, which
     * then fails the derivative (written through the const scene, like the detail). */
    tb_status user_load_status;
    struct tb__run_watch *watch; /* NULL, or the accuracy sweep's (run_watch.h) */
    bool renormalize;
    int vector_path; /* tb_vector_path: what tb_scene_ode_system offers integrators */
    /* The bodies' constants per lane group for the lane kernels (lanes.h), made by
     * tb_scene_ode_system; lane_constants_size doubles allocated. */
    double *lane_constants;
    size_t lane_constants_size;
    double quaternion_drift; /* largest | |q| - 1 | seen by the renormalisation hook */
    char detail[TB_DETAIL_SIZE];

    /* Names by hash: open addressing with linear probing, name_slot_count (a power of two, at
     * least twice body_count) slots holding body id + 1, 0 for empty. */
    size_t *name_slots;
    size_t name_slot_count;

    /* Lifetimes (scene_ode.c). The generation counts layout changes (bodies, effect-owned
     * states, coupling) and integrators made on the scene; an integrator steps only while its
     * generation is the scene's. */
    unsigned long long layout_generation;
    char layout_change[TB_DETAIL_SIZE / 2]; /* what bumped the generation last */
    bool separable_at_claim; /* whether the newest integrator saw independent bodies */
    bool busy;               /* an advance, step or reset is in progress */
    bool allow_unstable;     /* tb_scene_set_allow_unstable */
    /* The fixed step of the newest integrator made by tb_scene_integrator_create, checked
     * against the scene's rates at every advance; guard_dt 0 for none. */
    tb_method guard_method;
    double guard_dt;
    /* Sleeping islands (sleep.c): on unless tb_scene_set_sleeping(false); the flags and
     * islands, allocated by tb_scene_ode_system for a scene whose bodies interact (NULL
     * before). */
    bool sleeping;
    struct tb__sleep *sleep;
    /* The state the newest integrator last left (states_left_size doubles, 0 for none; room for
     * states_left_capacity, made by tb_scene_ode_system), kept when an effect checks starts: a
     * state that differs at the next advance, step or reset (tb_scene_set_state, a write through
     * tb_scene_states), or once shapes or motions were set (set_since says which), is checked. */
    double *states_left;
    size_t states_left_size, states_left_capacity;
    const char *set_since; /* "bodies' shapes were", "keyframed bodies' motions were", NULL */
    /* Contact events (contact_event_watch.c): NULL until tb_scene_set_contact_events. */
    struct tb__event_watch *contact_events;
    /* Unresolved impacts (impact_watch.c): NULL until an integrator of a step too long for some
     * impact was made. */
    struct tb__impacts *impacts;
    /* Constraints (src/constraints/): NULL until the first joint; constraint_ops their row.
     * stabilise: the integrator made last has no projection (CVODE Adams), so the constraint
     * stage adds its Baumgarte terms (set by tb_scene_integrator_create). */
    void *constraints;
    const tb__constraint_ops *constraint_ops;
    bool stabilise_constraints;
    /* The contact Jacobian's pattern and scratch (scene_jacobian.c): NULL until asked. */
    struct tb__scene_jacobian *jacobian;
};

/* Contact events (contact_event_watch.c): the scene's state at a step boundary at time t,
 * from a fixed step's post-step hook (fixed = true), or an adaptive method's accepted step or
 * event stop (fixed = false); only the integrator kind the watch was started for is heard.
 * start begins a watch at an integrator's first time; free releases it. */
void tb__scene_events_observe(tb_scene *scene, double t, const double *y, bool fixed);
void tb__scene_events_start(tb_scene *scene, double t0, bool fixed);
void tb__scene_events_free(tb_scene *scene);

/* A watch of the scene's own (unresolved impacts, impact_watch.c), as the contact events' but
 * with no callback and no hits: on_begin(ctx, event, pair) at each begin, pair the effect's
 * tb__event_pair where it began. create returns NULL when out of memory; free accepts NULL;
 * dropped counts the pairs it could not watch. */
struct tb_contact_event;
typedef void (*tb__event_begin_fn)(void *ctx, const struct tb_contact_event *event,
                                   const tb__event_pair *pair);
struct tb__event_watch *tb__event_watch_create(const tb_scene *scene, tb__event_begin_fn on_begin,
                                               void *ctx);
void tb__event_watch_free(struct tb__event_watch *watch);
size_t tb__event_watch_dropped(const struct tb__event_watch *watch);

/* Unresolved impacts (impact_watch.c, include/tumble/contact_events.h): prepare makes the count
 * for an integrator of method at fixed step dt made on the scene at y, into *out_pending: a watch
 * where impacts could be too fast for the step, NULL where none can (TB_STATUS_OUT_OF_MEMORY
 * with the detail set when it cannot); commit puts it in the scene once the integrator exists
 * (NULL: no count), discard frees it on a failed creation; watch is the committed watch or
 * NULL; free releases it at the scene's destruction. */
struct tb__impacts;
tb_status tb__scene_impacts_prepare(tb_scene *scene, const double *y, tb_method method, double dt,
                                    struct tb__impacts **out_pending);
void tb__scene_impacts_commit(tb_scene *scene, struct tb__impacts *pending);
void tb__scene_impacts_discard(struct tb__impacts *pending);
/* An integrator reset to t (tb_integrator_reset, accepted): the count keeps the impacts at or
 * before t (from zero if memory ran out for their log). */
void tb__scene_impacts_reset(tb_scene *scene, double t);
struct tb__event_watch *tb__scene_impact_watch(const tb_scene *scene);
void tb__scene_impacts_free(tb_scene *scene);

/* The h omega a fixed method resolves an impact at; out: the impacts' rates' bound (stability.c) */
double tb__scene_impact_resolution(const tb_scene *scene, const double *y, tb_method method,
                                   double *out_oscillation);

/* The contact's sparse Jacobian (scene_jacobian.c): whether the scene offers one (bodies that
 * interact, every effect's couplings known), its tb_ode_system.jacobian callbacks (ctx the
 * scene), and the free at destruction. */
bool tb__scene_has_jacobian(const tb_scene *scene);
size_t tb__scene_jacobian_capacity(double t, const double *y, void *ctx);
int tb__scene_jacobian(double t, const double *y, const double *fy, tb_ode_sparse *J, void *ctx);
void tb__scene_jacobian_free(tb_scene *scene);
/* tb_ode_system.events.at_event of a scene with events: the watch, then the sleep's. */
void tb__scene_at_event(double t, const double *y, void *ctx);

/* Writes scene->detail and returns status. */
tb_status tb__scene_fail(tb_scene *scene, tb_status status, const char *format, ...)
#if defined(__GNUC__) || defined(__clang__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* v non-NULL with three finite numbers, else a detail naming what. */
tb_status tb__check_vector(tb_scene *scene, const double *v, const char *what);

/* Names by hash (body_names.c). reserve makes room for body_count names (nothing changes on
 * failure); insert adds body id's name, which must be new; lookup finds a name. */
tb_status tb__scene_reserve_names(tb_scene *scene, size_t body_count);
void tb__scene_insert_name(tb_scene *scene, size_t id);
bool tb__scene_lookup_name(const tb_scene *scene, const char *name, size_t *out_id);

/* Clears the detail: the first thing every public scene function does once scene is known to
 * be non-NULL (the detail is the one part of a scene a const function may write). */
void tb__scene_clear_detail(const tb_scene *scene);

/* Checks id against the body count, writing the detail on failure. */
tb_status tb__scene_check_id(const tb_scene *scene, size_t id, const char *what);

/* Room for capacity effects (effects and effect_order); nothing changes on failure. */
tb_status tb__scene_reserve_effects(tb_scene *scene, size_t capacity);

/* Appends an effect, growing the list if needed, and records the change (effects_generation,
 * and the layout's when the effect owns states); nothing changes on failure. TB_STATUS_BUSY
 * while the scene is being stepped. The entry's parameters are a copy of the params_size bytes
 * at effect->params, which the scene owns from then on (what they point to too: the row's
 * release frees it); on failure the caller still owns what they point to. */
tb_status tb__scene_push_effect(tb_scene *scene, const tb__effect *effect, size_t params_size);

/* Whether an effect has a post_step op, and the scene's post-step hook for such scenes
 * (tb_ode_hook, ctx the scene): the quaternions renormalised if the scene asks for it, then
 * every effect's post_step op on the result. */
bool tb__scene_has_post_step_effects(const tb_scene *scene);
int tb__scene_post_step(double t, double *y, void *ctx);

/* Asks every effect's row whether the scene can start from y (tb__effect_ops.check_start: no
 * body deep inside a ground plane); the first refusal's status, with its detail. */
tb_status tb__scene_check_effects_start(tb_scene *scene, const double *y);

/* Every check_points op for body id's points, contacts[first ..], at y: the first refusal. */
tb_status tb__scene_check_points(tb_scene *scene, const double *y, size_t id, size_t first);

/* Every effect's check_shape, shapes_changed, then the layout if a state count changed, after
 * body id's shape was set or removed: all or nothing (on failure every effect as it was). */
tb_status tb__scene_shapes_changed(tb_scene *scene, size_t id);

/* TB_STATUS_BUSY (detail naming `what`) while an integrator is stepping the scene: a call from
 * inside a derivative, hook or user effect must not change what the step is reading. */
tb_status tb__scene_check_idle(tb_scene *scene, const char *what);

/* Records a change of the scene's layout (what the state's components mean, how many there
 * are, or whether bodies are independent): integrators made before refuse to step with
 * TB_STATUS_LAYOUT_CHANGED, their detail quoting `what` ("body 3 added"). Effects that
 * change the layout call it after the change succeeded. */
void tb__scene_layout_changed(tb_scene *scene, const char *format, ...)
#if defined(__GNUC__) || defined(__clang__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Recomputes where effect-owned states live (after the slot_count dynamic bodies' states),
 * grows the state array if needed and zeroes those states; records the layout change
 * (slot_count above the scene's: a body is being added). TB_STATUS_BUSY while the scene is
 * being stepped. On failure nothing changes. */
tb_status tb__scene_layout_states(tb_scene *scene, size_t slot_count);

/* A point fixed in a body's shape frame, as an offset from the centre of mass in the
 * principal frame. */
void tb__shape_point_to_principal(const tb_mass_properties *props, const double point[3],
                                  double out[3]);
/* A direction fixed in a body's shape frame, in the principal frame. */
void tb__shape_vector_to_principal(const tb_mass_properties *props, const double v[3],
                                   double out[3]);

/* The quaternion of slot i in y (y at a body's state and i 0, or y at a range's first slot
 * and i local to it), normalised, into q. */
void tb__unit_quaternion(const double *y, size_t i, double q[4]);

/* omega (world) of a body from its 13 states s. */
void tb__angular_velocity(const tb__body *body, const double *s, double omega[3]);

/* How many states effect owns after the bodies': per contact point and fixed. */
static inline size_t tb__effect_state_count(const tb__effect *effect, const tb_scene *scene)
{
    return effect->states_per_contact * scene->contact_count + effect->fixed_states;
}

/* Body `body`'s index in a range of `count` bodies from `first`, or false if outside it. */
static inline bool tb__local_body(size_t body, size_t first, size_t count, size_t *local)
{
    *local = body - first;
    return body >= first && body - first < count;
}

/* 1/m + |r|^2 / I_min (1/kg): the largest inverse mass a force at offset r (m, from the centre
 * of mass) can meet, through the body's translation and its rotation about its softest axis. */
static inline double tb__inverse_mass_at(const tb__body *body, const double r[3])
{
    const double *inverse = body->inv_moments;
    const double largest = inverse[0] > inverse[1] ? inverse[0] : inverse[1];
    const double r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    return body->inv_mass + r2 * (largest > inverse[2] ? largest : inverse[2]);
}

/* True when every effect acts on each body alone: the derivative of a body's 13 states then
 * depends on those states only, and the scene's ODE system is separable into bodies. */
bool tb__scene_separable(const tb_scene *scene);

/* Where in effect_order the single-body effects on the bodies [first, first + count) are:
 * [*begin, *end). */
void tb__scene_single_body_effects(const tb_scene *scene, size_t first, size_t count, size_t *begin,
                                   size_t *end);

/* Raises the scene's quaternion_drift to drift if larger; safe from concurrent hooks. */
void tb__scene_note_drift(tb_scene *scene, double drift);

/* The tb_ode_system block functions of a separable scene (ctx is the scene). */
/* ark-imex's explicit part of tb_scene_derivative (tb_ode_system.split): the loads of the
 * effects without a mode of their own (gravity, constant forces, user callbacks), zero in the
 * kinematic rows and the effects' states; the same signature and convention. */
int tb__scene_explicit_part(double t, const double *y, double *dydt, void *ctx);

int tb__scene_block_derivative(double t, const double *y, double *dydt, size_t first, size_t count,
                               void *ctx);
int tb__scene_block_normalize(double t, double *y, size_t first, size_t count, void *ctx);

/* The run-time stability gate (stability.c): TB_STATUS_UNSTABLE_STEP, with a detail (of
 * TB_DETAIL_SIZE bytes) naming the body or effect, its rate and the largest stable step, when
 * a fixed step dt of method is beyond the scene's limit at y, unless the scene allows it. */
tb_status tb__scene_check_step(const tb_scene *scene, const double *y, tb_method method, double dt,
                               char *detail);

/* Events (scene_events.c): whether some effect has them; the scene's root functions (one
 * gap per body, tb__effect_stepping.event_gaps) and adaptive step limit, for tb_ode_system. */
bool tb__scene_has_events(const tb_scene *scene);
int tb__scene_event_gaps(double t, const double *y, double *gap, void *ctx);
double tb__scene_step_limit(double t, const double *y, const double *dydt, void *ctx);
/* The scene's root functions: the effects' gaps, where bodies can sleep each body's wake gap
 * (tb__effect_stepping.wake_gaps), then tb__constraint_ops.roots; root_signs exact in sign. */
size_t tb__scene_root_count(const tb_scene *scene);
int tb__scene_roots(double t, const double *y, double *g, void *ctx);
int tb__scene_root_signs(double t, const double *y, double *g, void *ctx);
/* The longest fixed step at y in which no body can pass through another (INFINITY: none): the
 * least of the effects' tunnel_step for a step dt (0: their quick bounds alone, as the default
 * step uses), the pair that sets it in which (TB_DETAIL_SIZE bytes). */
double tb__scene_tunnel_step(const tb_scene *scene, const double *y, double dt, char *which);
/* tb_ode_events.split_limit: tb__scene_tunnel_step at t for a step h. */
double tb__scene_split_limit(double t, const double *y, double h, void *ctx);
/* Every effect's check_impacts at y; the detail (TB_DETAIL_SIZE bytes) names the effect. */
tb_status tb__scene_check_impacts(const tb_scene *scene, const double *y, char *detail);
/* The step tb_scene_default_step describes, for the scene at state y (stability.c). */
double tb__scene_default_step(const tb_scene *scene, const double *y, tb_method method);

#include "scene/motion_loads.h" /* a body's motion and the loads on it, for effects */
#include "scene/sleep.h"        /* sleeping islands */
#include "scene/body_motion.h"  /* the body-motion accessor, by id */

#endif
