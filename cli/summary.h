/* The run's summary on standard error: the integrator's work and the drift of what the
 * scene's effects conserve. */
#ifndef TUMBLE_CLI_SUMMARY_H
#define TUMBLE_CLI_SUMMARY_H

#include "tumble/tumble.h"

/* What is conserved, measured at one time. L is about the centre of mass: the body's own for
 * a single body, the system's (sum M_i x_i / sum M_i) for several. */
typedef struct invariants {
    double energy, P[3], L[3];
} invariants;

void summary_measure(const tb_scene *scene, invariants *out);

/* "1 body", "2 bodies": count and the noun in the right number. */
const char *summary_plural(size_t count, const char *one, const char *many);

/* ", 2 joints" (", 1 joint") into out, or "" for a scene without joints. */
void summary_joints(const tb_scene *scene, char *out, size_t size);

/* The fixed step run takes on the scene at its current state: its integrator's dt, or for
 * dt 0 the scene's default step (tb_scene_default_step; ask before the run, at the start).
 * 0 for an adaptive method. */
double summary_step(const tb_scene *scene, const tb_run_def *run);

/* For a fixed-step method stable on the whole imaginary axis (rosenbrock): the scene's default
 * step, the one that resolves its fastest oscillation, at the scene's current state; INFINITY
 * for the other methods (the explicit ones' guard and default step already hold them to it). */
double summary_resolving_step(const tb_scene *scene, const tb_run_def *run);

/* Says, when dt is longer than resolving, that bounces are not resolved. */
void summary_print_resolution(const tb_run_def *run, double dt, double resolving);

/* The impacts the fixed step did not resolve (tb_scene_unresolved_impacts) and the fastest of
 * them, where the run's step could leave any unresolved. */
void summary_print_impacts(const tb_scene *scene);

/* dt: the fixed step the run took (summary_step before it), unused for an adaptive method. */
void summary_print(const char *path, const tb_scene *scene, const tb_run_def *run, double dt,
                   const tb_integrator_stats *stats, double seconds, const invariants *first,
                   const invariants *last);

#endif
