/* Sleeping islands: bodies at rest stop costing derivative work until something touches them.
 * At each step boundary the bodies linked by the effects (a pair the contact effect finds
 * within its margin, a spring between two bodies) and the islands of asleep bodies are joined
 * by union-find; an island all of whose bodies have been slower than TB_SLEEP_SPEED for
 * TB_SLEEP_TIME falls asleep, and an island holding an asleep body and a moving one (or an
 * asleep body whose state was changed from outside) wakes. Waking is never late: a fixed step
 * links the pairs that could come within the margin during the next step, and under CVODE the
 * pairs of an awake and an asleep body are root functions (TB__WAKE_DISTANCE) at whose stop
 * the islands are decided and CVODE restarts (tb__scene_sleep_at_event, effect_contact_events.c).
 * Box2D's islands work the same way (b2_timeToSleep 0.5 s) at a game's 5 cm/s; tumble's speed
 * is 500 times smaller, so a body asleep for a time T is at most TB_SLEEP_SPEED T from where it
 * would be (docs/effects.md). */
#include "scene/scene_internal.h"
#include "scene/sleep_frozen.h"

#include "core/detail.h"
#include "math/tb_math.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void tb__scene_sleep_free(tb_scene *scene)
{
    tb__sleep *sleep = scene->sleep;
    if (sleep != NULL) {
        free(sleep->asleep);
        free(sleep->parent);
        free(sleep->island);
        free(sleep->still);
        free(sleep->decision);
        free(sleep->snapshot);
        free(sleep->runs);
        free(sleep->asleep_slots);
        free(sleep->motion_kept);
        free(sleep);
        scene->sleep = NULL;
    }
}

/* The derivative's lists from the flags (scene_internal.h): the runs of awake slots and the
 * asleep bodies' slots; and the motions kept for bodies that fell asleep or woke dropped. */
static void make_lists(tb_scene *scene)
{
    tb__sleep *sleep = scene->sleep;
    size_t runs = 0, asleep = 0;
    for (size_t s = 0; s < scene->slot_count && sleep->capacity == scene->body_count; ++s) {
        const size_t id = scene->slot_ids[s];
        if (sleep->asleep[id]) {
            sleep->asleep_slots[asleep++] = s;
        } else if (runs > 0 && sleep->runs[2 * runs - 1] == s) {
            sleep->runs[2 * runs - 1] = s + 1;
        } else {
            sleep->runs[2 * runs] = s;
            sleep->runs[2 * runs + 1] = s + 1;
            ++runs;
        }
        sleep->motion_kept[id] &= sleep->asleep[id];
    }
    sleep->run_count = runs;
}

tb_status tb__scene_sleep_prepare(tb_scene *scene)
{
    const size_t n = scene->body_count;
    if (scene->sleep != NULL && scene->sleep->capacity == n) {
        return TB_STATUS_OK;
    }
    tb__sleep *sleep = calloc(1, sizeof *sleep);
    /* n bodies' states were allocated, so 13 n doubles do not overflow */
    if (sleep != NULL) {
        sleep->asleep = calloc(n, 1);
        sleep->parent = malloc(n * sizeof(size_t));
        sleep->island = malloc(n * sizeof(size_t));
        sleep->still = calloc(n, sizeof(double));
        sleep->decision = calloc(n, 1);
        sleep->snapshot = malloc(n * TB_STATE_SIZE * sizeof(double));
        sleep->runs = malloc((n + 1) * 2 * sizeof(size_t));
        sleep->asleep_slots = malloc((n + 1) * sizeof(size_t));
        sleep->motion_kept = calloc(n + 1, 1);
    }
    if (sleep == NULL || sleep->asleep == NULL || sleep->parent == NULL || sleep->island == NULL ||
        sleep->still == NULL || sleep->decision == NULL || sleep->snapshot == NULL ||
        sleep->runs == NULL || sleep->asleep_slots == NULL || sleep->motion_kept == NULL) {
        tb_scene keep = {.sleep = sleep};
        tb__scene_sleep_free(&keep);
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "sleep flags for %zu bodies", n);
    }
    const unsigned long long generation = scene->sleep != NULL ? scene->sleep->generation + 1 : 0;
    tb__scene_sleep_free(scene);
    sleep->capacity = n;
    for (size_t i = 0; i < n; ++i) {
        sleep->island[i] = i;
    }
    sleep->last_t = NAN;
    sleep->generation = generation;
    scene->sleep = sleep;
    make_lists(scene);
    return TB_STATUS_OK;
}

static size_t find(size_t *parent, size_t i)
{
    while (parent[i] != i) {
        parent[i] = parent[parent[i]]; /* path halving */
        i = parent[i];
    }
    return i;
}

void tb__scene_sleep_begin(const tb_scene *scene)
{
    tb__sleep *sleep = scene->sleep;
    if (sleep == NULL) {
        return;
    }
    for (size_t i = 0; i < sleep->capacity; ++i) {
        sleep->parent[i] = i;
    }
}

/* i's root, the parents left as they are */
static size_t root_of(const size_t *parent, size_t i)
{
    while (parent[i] != i) {
        i = parent[i];
    }
    return i;
}

bool tb__scene_sleep_linked(const tb_scene *scene, size_t a, size_t b)
{
    const tb__sleep *sleep = scene->sleep;
    return sleep != NULL && a != b && a < sleep->capacity && b < sleep->capacity &&
           root_of(sleep->parent, a) == root_of(sleep->parent, b);
}

/* Whether keyframed body id moves (or is about to: an acceleration from rest) at the scene's
 * time, when the links are made. */
static bool keyframed_moving(const tb_scene *scene, size_t id)
{
    if (tb__body_static(scene, id)) {
        return false;
    }
    tb__motion motion;
    double a[3], alpha[3];
    tb__body_motion_at(scene, scene->time, scene->states, id, &motion);
    tb__fixed_body_acceleration_at(scene, scene->time, id, a, alpha);
    return tb__v3_norm(motion.v) > 0.0 || tb__v3_norm(motion.omega) > 0.0 || tb__v3_norm(a) > 0.0 ||
           tb__v3_norm(alpha) > 0.0;
}

void tb__scene_sleep_link(const tb_scene *scene, size_t a, size_t b)
{
    tb__sleep *sleep = scene->sleep;
    if (sleep == NULL || a >= sleep->capacity || b >= sleep->capacity) {
        return;
    }
    /* a body that cannot move joins no island: a table would merge every box on it into one;
     * a keyframed body that moves marks the dynamic body it touches moving (update_still) */
    const bool fixed_a = tb__body_fixed(scene, a), fixed_b = tb__body_fixed(scene, b);
    if (fixed_a != fixed_b && keyframed_moving(scene, fixed_a ? a : b)) {
        sleep->still[fixed_a ? b : a] = -1.0;
    }
    if (fixed_a || fixed_b) {
        return;
    }
    const size_t root_a = find(sleep->parent, a), root_b = find(sleep->parent, b);
    /* the smaller id is the root, so islands are named the same whatever the link order */
    if (root_a < root_b) {
        sleep->parent[root_b] = root_a;
    } else {
        sleep->parent[root_a] = root_b;
    }
}

/* Whether body i at state s moves slower than TB_SLEEP_SPEED, its centre and the points at its
 * radius of gyration about its softest axis, sqrt(I_max / M). */
static bool slow(const tb_scene *scene, size_t i, const double *s)
{
    const tb__body *body = tb__body_constants(scene, i);
    const double *moments = scene->mass_props[i].moments;
    const double largest = fmax(moments[0], fmax(moments[1], moments[2]));
    double omega[3];
    tb__angular_velocity(body, s, omega);
    const double speed = tb__v3_norm(s + TB_STATE_P) * body->inv_mass;
    const double spin = tb__v3_norm(omega) * sqrt(largest * body->inv_mass);
    return speed < TB_SLEEP_SPEED && spin < TB_SLEEP_SPEED;
}

/* Each body's still time after dt more seconds at y; an asleep body changed from outside
 * (its state no longer the one it fell asleep with) counts as moving. */
static void update_still(tb_scene *scene, const double *y, double dt)
{
    tb__sleep *sleep = scene->sleep;
    for (size_t i = 0; i < sleep->capacity; ++i) {
        const double *s = tb__body_state(scene, y, i);
        if (s == NULL || sleep->still[i] < 0.0) { /* static and keyframed bodies never sleep;
                                                     -1: touched by a moving keyframed body */
            sleep->still[i] = 0.0;
        } else if (sleep->asleep[i]) {
            const double *kept = sleep->snapshot + TB_STATE_SIZE * i;
            for (int k = 0; k < TB_STATE_SIZE; ++k) {
                if (s[k] != kept[k]) {
                    sleep->still[i] = 0.0;
                }
            }
        } else {
            sleep->still[i] = slow(scene, i, s) ? sleep->still[i] + dt : 0.0;
        }
    }
}

/* Links from the effects' rows (springs between two bodies) and the asleep bodies' islands;
 * true when some effect keeps every body awake. */
static bool link_effects(tb_scene *scene)
{
    tb__sleep *sleep = scene->sleep;
    bool awake = false;
    for (size_t e = 0; e < scene->effect_count; ++e) {
        const tb__effect *effect = &scene->effects[e];
        awake = awake || effect->ops->keeps_awake;
        const size_t partner =
            effect->ops->sleep_partner != NULL ? effect->ops->sleep_partner(effect) : TB_ALL_BODIES;
        if (partner != TB_ALL_BODIES && effect->body != TB_ALL_BODIES) {
            tb__scene_sleep_link(scene, effect->body, partner);
        }
    }
    if (scene->constraint_ops != NULL) { /* jointed bodies sleep and wake together */
        scene->constraint_ops->link_islands(scene->constraints, scene);
    }
    for (size_t i = 0; i < sleep->capacity; ++i) {
        if (sleep->asleep[i]) {
            tb__scene_sleep_link(scene, i, sleep->island[i]);
        }
    }
    return awake;
}

/* Applies the last decision: bodies fall asleep with y as their frozen state, or wake. */
static void apply(tb_scene *scene, const double *y)
{
    tb__sleep *sleep = scene->sleep;
    bool changed = false;
    for (size_t i = 0; i < sleep->capacity; ++i) {
        if (sleep->decision[i] == sleep->asleep[i]) {
            continue;
        }
        changed = true;
        sleep->asleep[i] = sleep->decision[i];
        if (sleep->asleep[i]) {
            memcpy(sleep->snapshot + TB_STATE_SIZE * i, tb__body_state(scene, y, i),
                   TB_STATE_SIZE * sizeof(double));
            sleep->asleep_count++;
        } else {
            sleep->still[i] = 0.0;
            sleep->asleep_count--;
        }
    }
    sleep->generation += changed;
    sleep->pending = false;
    if (changed) {
        make_lists(scene);
    }
}

/* Links the pairs the effects find that could come within their margin in a step of dt. */
static void link_near(const tb_scene *scene, const double *y, double dt)
{
    for (size_t e = 0; e < scene->effect_count; ++e) {
        const tb__effect *effect = &scene->effects[e];
        if (tb__stepping_of(effect)->wake_links != NULL) {
            tb__stepping_of(effect)->wake_links(effect, scene, y, dt);
        }
    }
}

void tb__scene_sleep_end(tb_scene *scene, double t, const double *y)
{
    tb__sleep *sleep = scene->sleep;
    if (sleep == NULL || sleep->capacity != scene->body_count) {
        return;
    }
    /* A fixed step of h moves a pair apart by more than the margin into contact when it closes
     * faster than margin / h: such a pair wakes now, before the step whose stages would push
     * an asleep body (the post_step ops linked only the pairs within the margin). */
    if (scene->guard_dt > 0.0 && sleep->asleep_count > 0) {
        link_near(scene, y, scene->guard_dt);
    }
    /* CVODE hands out interpolated outputs behind its last step: time only counts forward */
    const double dt = isfinite(sleep->last_t) && t > sleep->last_t ? t - sleep->last_t : 0.0;
    sleep->last_t = isfinite(sleep->last_t) ? fmax(sleep->last_t, t) : t;
    update_still(scene, y, dt);
    const bool awake = link_effects(scene) || !scene->sleeping;
    /* decision[root] first holds whether the island is quiet, then each body takes its root's */
    for (size_t i = 0; i < sleep->capacity; ++i) {
        sleep->decision[i] = !awake;
    }
    for (size_t i = 0; i < sleep->capacity; ++i) {
        if (sleep->still[i] < TB_SLEEP_TIME) {
            sleep->decision[find(sleep->parent, i)] = 0;
        }
    }
    for (size_t i = 0; i < sleep->capacity; ++i) {
        const size_t root = find(sleep->parent, i);
        sleep->decision[i] = sleep->decision[root];
        sleep->island[i] = root;
    }
    sleep->pending = true;
    if (scene->guard_dt > 0.0) { /* a fixed step: no history to restart */
        apply(scene, y);
    }
}

void tb__scene_sleep_at_event(double t, const double *y, void *ctx)
{
    tb_scene *scene = ctx;
    tb__sleep *sleep = scene->sleep;
    if (sleep == NULL || sleep->capacity != scene->body_count || sleep->asleep_count == 0) {
        return; /* nothing to wake: falling asleep waits for the next output */
    }
    tb__scene_sleep_begin(scene);
    link_near(scene, y, 0.0);
    tb__scene_sleep_end(scene, t, y);
    apply(scene, y); /* the integrator restarts from y when the asleep set changed */
}

void tb__scene_sleep_apply_pending(tb_scene *scene)
{
    if (scene->sleep != NULL && scene->sleep->pending &&
        scene->sleep->capacity == scene->body_count) {
        apply(scene, scene->states);
    }
}

static void wake_where(tb_scene *scene, size_t island, bool every)
{
    tb__sleep *sleep = scene->sleep;
    if (sleep == NULL) {
        return;
    }
    for (size_t i = 0; i < sleep->capacity; ++i) {
        if (every || sleep->island[i] == island) {
            sleep->decision[i] = 0;
            sleep->still[i] = 0.0;
        }
    }
    const bool pending = sleep->pending;
    apply(scene, scene->states);
    sleep->pending = pending; /* a fall asleep decided before still waits, now without them */
}

void tb__scene_wake_body(tb_scene *scene, size_t id)
{
    /* island[] holds every body's island of the last boundary: a decision to put the body's
     * island to sleep that waits for the next acquire is cancelled too. A body without a state
     * joins no island (tb__scene_sleep_link), so the bodies resting on it (a table's shape
     * changed) may be in any: every body wakes */
    if (scene->sleep != NULL && id < scene->sleep->capacity) {
        wake_where(scene, scene->sleep->island[id], tb__body_fixed(scene, id));
    }
}

void tb__scene_wake_all(tb_scene *scene)
{
    wake_where(scene, 0, true);
}

/* Whether the scene has a keyframed body (one that moves by time). */
static bool has_keyframed(const tb_scene *scene)
{
    for (size_t id = 0; id < scene->body_count; ++id) {
        if (tb__body_fixed(scene, id) && !tb__body_static(scene, id)) {
            return true;
        }
    }
    return false;
}

void tb__scene_sleep_restart(tb_scene *scene, double t)
{
    /* the clock counts forward only (tb__scene_sleep_end): left at a later run's end, it would
     * count no stillness in this run until it passed that time. Later than the clock, keys may
     * have moved a keyframed body in the time passed over (a platform lowered under a box
     * asleep on it), which no boundary saw */
    if (scene->sleep != NULL && isfinite(scene->sleep->last_t) &&
        (t < scene->sleep->last_t || (t > scene->sleep->last_t && has_keyframed(scene)))) {
        tb__scene_wake_all(scene);
        scene->sleep->last_t = NAN;
    }
}

void tb__scene_sleep_zero(const tb_scene *scene, double *dydt)
{
    const tb__sleep *sleep = scene->sleep;
    if (sleep == NULL || sleep->asleep_count == 0) {
        return;
    }
    for (size_t k = 0; k < sleep->asleep_count && sleep->capacity == scene->body_count; ++k) {
        double *d = dydt + TB_STATE_SIZE * sleep->asleep_slots[k];
        for (int i = 0; i < TB_STATE_SIZE; ++i) { /* stored inline: a memset call per body cost
                                                     as much as the rest of an asleep body */
            d[i] = 0.0;
        }
    }
    for (size_t i = 0; i < sleep->capacity && sleep->capacity != scene->body_count; ++i) {
        if (sleep->asleep[i]) { /* bodies added since the lists were made */
            memset(tb__body_state_mut(scene, dydt, i), 0, TB_STATE_SIZE * sizeof(double));
        }
    }
}

double tb__scene_rest_until(double t, const double *y, void *ctx)
{
    const tb_scene *scene = ctx;
    const tb__sleep *sleep = scene->sleep;
    /* the flags count dynamic bodies only: all asleep is asleep_count == slot_count */
    if (sleep == NULL || !scene->sleeping || sleep->pending || sleep->asleep_count == 0 ||
        sleep->asleep_count != scene->slot_count || sleep->capacity != scene->body_count) {
        return t;
    }
    for (size_t i = 0; i < sleep->capacity; ++i) {
        /* a keyframed body moves by time; a body not frozen was changed from outside, and the
         * next boundary wakes its island */
        if (tb__body_state(scene, y, i) == NULL ? !tb__body_static(scene, i)
                                                : !tb__body_frozen(scene, y, i)) {
            return t;
        }
    }
    /* The derivative of asleep bodies is 0 and the post-step hook leaves them as they fell
     * asleep (update_still would wake a body it changed); a boundary over bodies that are all
     * asleep links no pair closing (none moves), so none wakes until a call changes one. */
    return INFINITY;
}

unsigned long long tb__scene_sleep_generation(const tb_scene *scene)
{
    return scene->sleep != NULL ? scene->sleep->generation : 0;
}

/* --- public ------------------------------------------------------------------------------ */

tb_status tb_scene_set_sleeping(tb_scene *scene, bool sleeping)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    const tb_status status = tb__scene_check_idle(scene, "tb_scene_set_sleeping");
    if (status != TB_STATUS_OK) {
        return status;
    }
    scene->sleeping = sleeping;
    if (!sleeping) {
        tb__scene_wake_all(scene);
    }
    return TB_STATUS_OK;
}

bool tb_scene_sleeping(const tb_scene *scene)
{
    return scene != NULL && scene->sleeping;
}

tb_status tb_scene_asleep_count(const tb_scene *scene, size_t *out_count)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (out_count == NULL) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "out_count is NULL");
    }
    *out_count = scene->sleep != NULL ? scene->sleep->asleep_count : 0;
    return TB_STATUS_OK;
}

tb_status tb_scene_body_asleep(const tb_scene *scene, size_t id, bool *out_asleep)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (out_asleep == NULL) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "out_asleep is NULL");
    }
    const tb_status status = tb__scene_check_id(scene, id, "id");
    if (status == TB_STATUS_OK) {
        *out_asleep = tb__body_asleep(scene, id);
    }
    return status;
}
