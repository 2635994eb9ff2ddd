/* The run's summary. Angular momentum is taken about the centre of mass, where uniform
 * gravity exerts no torque: a box thrown under gravity keeps it, so its drift measures the
 * integrator, not the physics. */
#include "summary.h"

#include "tumble/joints.h"

#include <math.h>
#include <stdio.h>

static void center_of_mass(const tb_scene *scene, const double *y, double out[3])
{
    const size_t count = tb_scene_body_count(scene);
    if (count == 1) { /* exactly x, not M x / M rounded */
        for (int k = 0; k < 3; ++k) {
            out[k] = y[TB_STATE_X + k];
        }
        return;
    }
    double total = 0.0, sum[3] = {0, 0, 0};
    for (size_t i = 0; i < count; ++i) {
        tb_mass_properties mass;
        size_t slot = TB_NO_SLOT;
        tb_scene_get_mass(scene, i, &mass);
        tb_scene_body_slot(scene, i, &slot);
        if (slot == TB_NO_SLOT) { /* a body that cannot move: not part of the moving mass */
            continue;
        }
        total += mass.mass;
        for (int k = 0; k < 3; ++k) {
            sum[k] += mass.mass * y[TB_STATE_SIZE * slot + TB_STATE_X + k];
        }
    }
    for (int k = 0; k < 3; ++k) {
        out[k] = total > 0 ? sum[k] / total : 0.0;
    }
}

void summary_measure(const tb_scene *scene, invariants *out)
{
    const double *y = tb_scene_states_const(scene);
    double kinetic = 0.0, potential = 0.0, center[3] = {0, 0, 0};
    tb_scene_kinetic_energy(scene, y, &kinetic);
    tb_scene_potential_energy(scene, y, &potential);
    out->energy = kinetic + potential;
    tb_scene_linear_momentum(scene, y, out->P);
    if (tb_scene_body_count(scene) > 0) {
        center_of_mass(scene, y, center);
    }
    tb_scene_angular_momentum(scene, y, center, out->L);
}

const char *summary_plural(size_t count, const char *one, const char *many)
{
    return count == 1 ? one : many;
}

void summary_joints(const tb_scene *scene, char *out, size_t size)
{
    const size_t joints = tb_scene_joint_count(scene);
    out[0] = '\0';
    if (joints > 0) {
        snprintf(out, size, ", %zu %s", joints, summary_plural(joints, "joint", "joints"));
    }
}

/* hypot: a momentum of 1e200 kg m/s has a length, though its square overflows */
static double distance(const double a[3], const double b[3])
{
    return hypot(hypot(a[0] - b[0], a[1] - b[1]), a[2] - b[2]);
}

static double length(const double a[3])
{
    return hypot(hypot(a[0], a[1]), a[2]);
}

/* about: where a moment is taken, "" for none; by: what in the scene may change it */
static void report_drift(const char *what, int conserved, double change, double scale,
                         const char *unit, const char *about, const char *by)
{
    if (!conserved) {
        fprintf(stderr, "  %-24s not conserved by this scene's %s%s\n", what, by, about);
    } else if (!isfinite(scale) || !isfinite(change)) {
        /* an energy past 1.8e308 J is infinite in doubles, and inf - inf is NaN */
        fprintf(stderr, "  %-24s drift n/a (not finite: %g %s at the start%s)%s\n", what, scale,
                unit, isfinite(scale) ? ", not finite at the end" : "", about);
    } else if (scale > 0) {
        fprintf(stderr, "  %-24s drift %.3g %s (%.3g relative)%s\n", what, change, unit,
                change / scale, about);
    } else {
        fprintf(stderr, "  %-24s drift %.3g %s%s\n", what, change, unit, about);
    }
}

double summary_step(const tb_scene *scene, const tb_run_def *run)
{
    const tb_integrator_def *i = &run->integrator;
    double dt = i->dt;
    if (tb_method_is_adaptive(i->method)) {
        return 0.0;
    }
    if (dt == 0.0 && tb_scene_default_step(scene, i->method, &dt) != TB_STATUS_OK) {
        return 0.0; /* the run refuses it and says why */
    }
    return dt;
}

double summary_resolving_step(const tb_scene *scene, const tb_run_def *run)
{
    tb_method_info info;
    double dt = INFINITY;
    if (tb_method_get_info(run->integrator.method, &info) != TB_STATUS_OK || info.adaptive ||
        !isinf(info.imaginary_limit) ||
        tb_scene_default_step(scene, run->integrator.method, &dt) != TB_STATUS_OK) {
        return INFINITY;
    }
    return dt;
}

void summary_print_resolution(const tb_run_def *run, double dt, double resolving)
{
    if (dt > resolving * (1.0 + 1e-9)) {
        fprintf(stderr,
                "  %-24s not resolved: dt %g s is longer than %g s, where %s resolves the "
                "scene's fastest oscillation (its default step, dt 0); impacts shorter than "
                "a few steps are damped by the step and bounce back less than their restitution "
                "says (docs/integrators.md)\n",
                "restitution", dt, resolving, tb_method_name(run->integrator.method));
    }
}

static const char *body_name(const tb_scene *scene, size_t id)
{
    return id == TB_WORLD ? "ground" : tb_scene_body_name(scene, id);
}

void summary_print_impacts(const tb_scene *scene)
{
    tb_unresolved_impacts found;
    const tb_status status = tb_scene_unresolved_impacts(scene, &found);
    if (!found.watched) {
        return;
    }
    fprintf(stderr, "  %-24s %zu, too fast for dt %g s (dt omega above %.3g)%s\n",
            "unresolved impacts", found.count, found.dt, found.resolution,
            status == TB_STATUS_OK ? "" : " (pairs left unwatched: out of memory)");
    if (found.count > 0) {
        const tb_impact *w = &found.fastest;
        fprintf(stderr,
                "  %-24s %s and %s at t = %.6g s, closing at %.3g m/s, pushing %.3g s (%.3g "
                "steps): it bounces back less than its restitution says\n",
                "fastest", body_name(scene, w->body_a), body_name(scene, w->body_b), w->t, w->speed,
                w->duration, w->steps);
    }
}

static void print_work(const tb_run_def *run, double dt, const tb_integrator_stats *stats,
                       double seconds)
{
    const tb_integrator_def *i = &run->integrator;
    if (tb_method_is_adaptive(i->method)) {
        fprintf(stderr, "  %-24s %s, rtol %g, atol %s\n", "integrator", tb_method_name(i->method),
                i->rtol, i->atol > 0 ? "given" : "per body");
    } else {
        fprintf(stderr, "  %-24s %s, dt %g s%s (%.6g steps per simulated second)\n", "integrator",
                tb_method_name(i->method), dt, i->dt == 0.0 ? " (the scene's default step)" : "",
                1.0 / dt);
    }
    fprintf(stderr, "  %-24s %ld (%ld failed attempts)\n", "steps", stats->steps,
            stats->failed_steps);
    fprintf(stderr, "  %-24s %ld\n", "derivative evaluations", stats->derivative_evals);
    if (stats->rest_time > 0.0) {
        fprintf(stderr, "  %-24s %.6g s passed without steps, every body asleep\n", "at rest",
                stats->rest_time);
    }
    fprintf(stderr, "  %-24s %.3f s\n", "wall time", seconds);
}

void summary_print(const char *path, const tb_scene *scene, const tb_run_def *run, double dt,
                   const tb_integrator_stats *stats, double seconds, const invariants *first,
                   const invariants *last)
{
    const size_t bodies = tb_scene_body_count(scene), effects = tb_scene_effect_count(scene);
    char joints[48];
    summary_joints(scene, joints, sizeof joints);
    fprintf(stderr, "tumble: %s: %zu %s, %zu %s%s, %.6g s at %.6g fps\n", path, bodies,
            summary_plural(bodies, "body", "bodies"), effects,
            summary_plural(effects, "effect", "effects"), joints, run->duration, run->fps);
    print_work(run, dt, stats, seconds);
    size_t asleep = 0;
    if (tb_scene_sleeping(scene) && tb_scene_asleep_count(scene, &asleep) == TB_STATUS_OK) {
        fprintf(stderr, "  %-24s %zu of %zu %s at the end\n", "asleep", asleep, bodies,
                summary_plural(bodies, "body", "bodies"));
    }
    tb_conserved c;
    tb_scene_conserved(scene, &c);
    const char *by = tb_scene_joint_count(scene) > 0 ? "effects and joints" : "effects";
    report_drift("energy", c.energy, fabs(last->energy - first->energy), fabs(first->energy), "J",
                 "", by);
    report_drift("linear momentum", c.linear_momentum, distance(last->P, first->P),
                 length(first->P), "kg m/s", "", by);
    report_drift("angular momentum", c.angular_momentum_about_center_of_mass,
                 distance(last->L, first->L), length(first->L), "kg m^2/s",
                 bodies == 1 ? ", about the centre of mass" : ", about the bodies' centre of mass",
                 by);
}
