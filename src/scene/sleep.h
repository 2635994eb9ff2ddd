/* Sleeping islands: the flags the derivative and the effects read, and the step boundary's
 * decisions (sleep.c). Included by scene_internal.h after the scene's struct. */
#ifndef TUMBLE_SCENE_SLEEP_H
#define TUMBLE_SCENE_SLEEP_H

/* Sleeping islands (sleep.c). Bodies linked at a step boundary (a pair the contact effect
 * finds within its margin, a spring between them, a sleeping body's island) form islands; an
 * island whose bodies have all been slower than TB_SLEEP_SPEED for TB_SLEEP_TIME falls asleep,
 * and wakes when one of its bodies is linked to a moving one or changed from outside. Asleep
 * bodies' derivative is 0 (their 13 states, their ground anchors, the friction slots between
 * two of them) and the contact effect skips the narrow phase between two of them. The flags
 * change only at step boundaries (tb__scene_post_step), so the derivative is a pure function
 * of (t, y) between them. */
typedef struct tb__sleep {
    size_t capacity;         /* bodies the arrays hold */
    unsigned char *asleep;   /* per body */
    size_t asleep_count;     /* bodies asleep */
    size_t *parent;          /* union-find of the boundary's islands */
    size_t *island;          /* an asleep body's island (a body id) */
    double *still;           /* s each body has been slow (-1: touched by a moving
                                keyframed body since the last boundary) */
    unsigned char *decision; /* the last boundary's: 1 asleep, 0 awake */
    double *snapshot;        /* TB_STATE_SIZE per body: the state it fell asleep with */
    /* What a derivative visits (sleep_frozen.h): the awake slots as runs [runs[2k],
     * runs[2k + 1]) (run_count), the asleep bodies' slots (asleep_count), and per body whether
     * scene->motions holds its frozen motion; capacity + 1 runs and capacity of each. */
    size_t *runs, run_count, *asleep_slots;
    unsigned char *motion_kept;
    double last_t;                 /* the last boundary's time (NAN: none yet) */
    bool pending;                  /* a decision waits for the next acquire (adaptive methods) */
    unsigned long long generation; /* counts changes of the asleep set */
} tb__sleep;

/* Whether body id is asleep: its derivative is 0 and pairs of two asleep bodies are skipped.
 * Bodies added since the flags were made (capacity) are awake. */
static inline bool tb__body_asleep(const tb_scene *scene, size_t id)
{
    const tb__sleep *sleep = scene->sleep;
    return sleep != NULL && sleep->asleep_count > 0 && id < sleep->capacity && sleep->asleep[id];
}

/* Allocates the sleep arrays for the scene's bodies (tb_scene_ode_system of a scene whose
 * bodies interact); every body awake. Nothing changes on failure. */
tb_status tb__scene_sleep_prepare(tb_scene *scene);
void tb__scene_sleep_free(tb_scene *scene);
/* The boundary: begin resets the islands, the effects' post_step ops link the pairs they find
 * (tb__scene_sleep_link, through the const scene like the friction map), end decides from y
 * at time t. A fixed-step integrator made by tb_scene_integrator_create applies the decision
 * at once (having linked the pairs that could close the margin in its step); otherwise (CVODE,
 * whose history the flags would change under it) it waits for the next acquire, where the
 * integrator's rhs_generation check restarts it, or for an event stop while a body sleeps
 * (tb__scene_sleep_at_event). */
void tb__scene_sleep_begin(const tb_scene *scene);
void tb__scene_sleep_link(const tb_scene *scene, size_t a, size_t b);
/* Whether a and b (a != b) are in one island of the links made since begin: linking them again
 * would change nothing (the effects' passes skip such pairs). */
bool tb__scene_sleep_linked(const tb_scene *scene, size_t a, size_t b);
void tb__scene_sleep_end(tb_scene *scene, double t, const double *y);
void tb__scene_sleep_apply_pending(tb_scene *scene);
/* Wakes body id's island (a user change of its state or shape; every body for a body without
 * a state, which is in no island), or every body. */
void tb__scene_wake_body(tb_scene *scene, size_t id);
void tb__scene_wake_all(tb_scene *scene);
/* An integrator made or reset at t: before the sleep clock's last boundary (a run again from
 * an earlier time) the stillness counted belongs to another history, so every body wakes and
 * the clock restarts at t; so too after it in a scene with a keyframed body (its keys may have
 * moved it in the time passed over); at it (a run continued), or after it in a scene without
 * one, nothing changes. */
void tb__scene_sleep_restart(tb_scene *scene, double t);
/* An integrator made or reset at t from y: the sleep clock's restart, then every effect's
 * restart op (tb__effect_stepping.restart) and the constraints' (a joint broken later whole
 * again), so that nothing a run before left outside y changes a run from y. */
void tb__scene_restart(tb_scene *scene, double t, const double *y);
/* The adaptive methods' event stop (tb_ode_system.events.at_event, ctx the scene): while a body
 * sleeps, the islands are decided from y at t (pairs within the margin, tb__effect_stepping
 * wake_links) and the decision applied at once, so that the integrator restarts there with
 * an island woken before the pair that stopped it touches. */
void tb__scene_sleep_at_event(double t, const double *y, void *ctx);
/* dydt of asleep bodies set to 0. */
void tb__scene_sleep_zero(const tb_scene *scene, double *dydt);
/* Counts changes of the asleep set, for the scene's rhs_generation. */
unsigned long long tb__scene_sleep_generation(const tb_scene *scene);
/* tb_ode_system.events.rest_until of a scene whose bodies interact (ctx the scene): INFINITY
 * where every dynamic body sleeps with y its frozen state, no body is keyframed and the scene
 * sleeps (so nothing but a call from outside, which wakes an island, moves a body); t
 * otherwise. */
double tb__scene_rest_until(double t, const double *y, void *ctx);

#endif
