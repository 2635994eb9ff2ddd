/* Fixed steps that end at onsets: a step of a system with root functions
 * (tb_ode_system.events.roots) whose end finds a function at or below zero that was above zero
 * at its start (for a scene: a body's gap closed, apart -> touching) is taken again, shorter, to
 * the first such crossing, located on the step's cubic Hermite interpolant. A right-hand side
 * that switches on at the onset (the contact's force, its friction) is then integrated by steps
 * that are smooth inside, as CVODE's roots give it; a step straddling the onset would integrate
 * the kink with an error of the step's order 1, which friction through an impact shows (a ball
 * landing with backspin: tests/test_contact_onset.c). Crossings the other way (separations,
 * rising through zero) end no step: the force reaches zero there continuously (its slope may
 * jump), and a step across one keeps that kink's error, which the impact's outcome is far less
 * sensitive to than to its start (the friction and the normal impulse are mostly spent by then);
 * locating them too would double the searches. */
#include "ode/integrator.h"

#include "core/detail.h"
#include "core/validate.h"

#include <math.h>
#include <stdlib.h>

/* Bisection on the interpolant stops when the onset is bracketed to this fraction of the step:
 * 24 halvings. A contact switching on at closing speed v is then located to v h 6e-8 of
 * penetration (at 1 m/s and h = 1e-4 s: 6e-12 m, against the default contact's 8e-7 m). */
#define TB__ONSET_TOLERANCE 6e-8

/* An onset this close to the step's start (a fraction of the step) is taken as at the start, and
 * the whole step is taken: the kink then lies inside the step's first 1e-3, where the force has
 * grown by at most k v 1e-3 h, and a position on a rounding plateau (a gap exactly 0 where the
 * scene puts a tiny positive value, scene_events.c) cannot cut step after step of that size, a
 * Zeno loop that the example dice fell into at 6e-8 (53 667 steps in 2.3e-7 s). */
#define TB__ONSET_AT_START 1e-3

struct tb__onset {
    double *buffer;  /* the allocation the vectors below are in */
    double *g_start; /* the roots at the step's start (valid if have_start) */
    double *g_end;   /* at the unhooked end of the trial step */
    double *g_probe; /* at the interpolant's probes; after a located onset, at its touching side */
    double *f_start, *f_end, *y_probe; /* n each: the interpolant's slopes and its state */
    bool have_start;
    long first_root; /* the lowest function that crossed in the last located step */
};

tb_status tb__onset_create(tb_integrator *integrator, tb_error *error)
{
    const tb_ode_system *system = &integrator->system;
    if (system->events.root_count == 0 || system->blocks.size > 0) {
        return TB_STATUS_OK; /* separable systems step in chunks: no whole state to search */
    }
    const size_t roots = system->events.root_count, n = system->n;
    struct tb__onset *onset = calloc(1, sizeof *onset);
    double *buffer = NULL;
    size_t count = 0;
    if (onset != NULL && tb__size_product(3, n, &count) && count <= (size_t)-1 - 3 * roots) {
        buffer = tb__malloc_array(count + 3 * roots, sizeof(double));
    }
    if (buffer == NULL) {
        free(onset);
        return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY,
                             "onset search of %zu states and %zu root values", n, roots);
    }
    onset->buffer = onset->g_start = buffer;
    onset->g_end = buffer + roots;
    onset->g_probe = buffer + 2 * roots;
    onset->f_start = buffer + 3 * roots;
    onset->f_end = onset->f_start + n;
    onset->y_probe = onset->f_end + n;
    integrator->onset = onset;
    return TB_STATUS_OK;
}

void tb__onset_destroy(tb_integrator *integrator)
{
    if (integrator->onset != NULL) {
        free(integrator->onset->buffer);
        free(integrator->onset);
        integrator->onset = NULL;
    }
}

void tb__onset_forget(tb_integrator *integrator)
{
    if (integrator->onset != NULL) {
        integrator->onset->have_start = false;
    }
}

/* The roots' signs at (t, y) into g: the search reads nothing else, so the system's cheaper
 * root_signs where it has them for these roots (a system that replaced roots keeps a stale
 * root_signs, which would leave its own functions unwritten). */
static int root_signs(const tb_ode_system *system, double t, const double *y, double *g)
{
    const tb_ode_events *events = &system->events;
    return events->root_signs != NULL && events->root_signs_for == events->roots
               ? events->root_signs(t, y, g, system->ctx)
               : events->roots(t, y, g, system->ctx);
}

/* y(s) on [t, t + h], s in [0, 1], from both ends' values and slopes. */
static void hermite(const double *y0, const double *f0, const double *y1, const double *f1,
                    double h, double s, double *out, size_t n)
{
    const double r = 1.0 - s;
    const double a = (1.0 + 2.0 * s) * r * r, b = s * r * r * h;
    const double c = s * s * (3.0 - 2.0 * s), d = s * s * (s - 1.0) * h;
    for (size_t i = 0; i < n; ++i) {
        out[i] = a * y0[i] + b * f0[i] + c * y1[i] + d * f1[i];
    }
}

/* The lowest function above zero at the start and at or below zero in g; -1 if none. */
static long first_onset(const double *g_start, const double *g, size_t count)
{
    for (size_t i = 0; i < count; ++i) {
        if (g_start[i] > 0.0 && !(g[i] > 0.0)) {
            return (long)i;
        }
    }
    return -1;
}

/* Bisects [0, 1] for the first onset on the interpolant; *s_touch the bracket's touching end.
 * Returns a callback's non-zero status. */
static int bisect(tb_integrator *integrator, const double *y0, const double *y1, double h,
                  double *s_touch)
{
    const tb_ode_system *system = &integrator->system;
    struct tb__onset *onset = integrator->onset;
    const size_t n = system->n, count = system->events.root_count;
    double low = 0.0, high = 1.0;
    for (size_t i = 0; i < count; ++i) {
        onset->g_probe[i] = onset->g_end[i];
    }
    double *trial = onset->g_end; /* g_end is spent once the search starts */
    while (high - low > TB__ONSET_TOLERANCE) {
        const double s = 0.5 * (low + high);
        hermite(y0, onset->f_start, y1, onset->f_end, h, s, onset->y_probe, n);
        const int rc = root_signs(system, integrator->t + s * h, onset->y_probe, trial);
        if (rc != 0) {
            return rc;
        }
        if (first_onset(onset->g_start, trial, count) >= 0) {
            high = s;
            double *swap = onset->g_probe;
            onset->g_probe = trial;
            trial = swap;
        } else {
            low = s;
        }
    }
    onset->g_end = trial;
    *s_touch = high;
    return 0;
}

int tb__onset_locate(tb_integrator *integrator, const double *y0, const double *y1, double h,
                     long *evals, double *h_onset)
{
    const tb_ode_system *system = &integrator->system;
    struct tb__onset *onset = integrator->onset;
    const size_t count = system->events.root_count;
    const double t = integrator->t;
    *h_onset = h;
    int rc = onset->have_start ? 0 : root_signs(system, t, y0, onset->g_start);
    rc = rc != 0 ? rc : root_signs(system, t + h, y1, onset->g_end);
    if (rc != 0) {
        return rc;
    }
    if (first_onset(onset->g_start, onset->g_end, count) < 0) {
        /* the next step starts here: its start's roots are these (of the state before the
         * post-step hook, which moves it by round-off) */
        double *swap = onset->g_start;
        onset->g_start = onset->g_end;
        onset->g_end = swap;
        onset->have_start = true;
        return 0;
    }
    onset->have_start = false;
    /* the slopes at both ends: f(t, y0) again (the stepper's first stage is overwritten) and
     * f(t + h, y1), paid only by a step with an onset */
    *evals += 2;
    rc = system->derivative(t, y0, onset->f_start, system->ctx);
    rc = rc != 0 ? rc : system->derivative(t + h, y1, onset->f_end, system->ctx);
    double s = 1.0;
    rc = rc != 0 ? rc : bisect(integrator, y0, y1, h, &s);
    if (rc != 0) {
        return rc;
    }
    onset->first_root = first_onset(onset->g_start, onset->g_probe, count);
    /* an onset at the start (the state there a hair apart after a step cut at the crossing
     * before, or on a rounding plateau) is where the step begins: the whole step is taken */
    if (s > TB__ONSET_AT_START && t + s * h > t) {
        *h_onset = s * h;
    }
    return 0;
}

void tb__onset_reached(tb_integrator *integrator)
{
    const tb_ode_system *system = &integrator->system;
    struct tb__onset *onset = integrator->onset;
    tb_integrator_events *events = &integrator->events;
    events->count++;
    events->last_time = integrator->t;
    events->last_root = onset->first_root;
    events->last_direction = -1;
    /* the next step starts on the touching side the search found, so that the same crossing
     * is not searched again; at_event may change the right-hand side (a scene wakes bodies) */
    for (size_t i = 0; i < system->events.root_count; ++i) {
        onset->g_start[i] = onset->g_probe[i];
    }
    onset->have_start = true;
    if (system->events.at_event == NULL) {
        return;
    }
    system->events.at_event(integrator->t, integrator->y, system->ctx);
    /* the roots anew (at_event may have changed them), but the functions found touching stay
     * touching at the start: the step to the onset may end a rounding error apart */
    if (root_signs(system, integrator->t, integrator->y, onset->g_start) != 0) {
        onset->have_start = false; /* the next step's search reports the failure */
        return;
    }
    for (size_t i = 0; i < system->events.root_count; ++i) {
        onset->g_start[i] = onset->g_probe[i] > 0.0 ? onset->g_start[i] : onset->g_probe[i];
    }
}
