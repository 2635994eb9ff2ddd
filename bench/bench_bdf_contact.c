/* CVODE BDF on contact, by linear solver: the dense difference-quotient Jacobian, GMRES with a
 * banded preconditioner (auto picks dense up to 512 unknowns for bodies that interact, Krylov
 * above: the dice's 611), and the contact's sparse Jacobian with KLU (TB_LINEAR_SOLVER_SPARSE).
 * Three scenes (their unknowns go to stderr):
 *   dice    examples/scenes/dice.json (twelve 16 mm dice thrown onto a table), its first 0.25 s;
 *   column  ten 10 cm, 0.5 kg boxes standing on the ground, each on the one below, 1 s;
 *   impact  two 10 cm, 1 kg boxes meeting head-on at 1 m/s (slightly turned, no gravity), 0.05 s;
 *   stack   examples/scenes/stack.json (five boxes stacked and settling), its first 0.05 s.
 * rtol 1e-6 (the scene's absolute tolerances), frames at 60 per second (a tenth of the span when
 * that is shorter). Prints CSV: scene,
 * solver, status (ok, the failure, or budget: stopped after the CPU budget), simulated s reached,
 * steps, error-test failures, Newton convergence failures, Newton iterations, Jacobians,
 * derivative evaluations (CVODE's; the sparse Jacobian's own quotients are not among them), CPU
 * s, CPU s per simulated second. The processor and the load go to stderr.
 *
 * usage: bench_bdf_contact [--quick] [--solver dense|krylov|sparse] [--scene NAME] [EXAMPLES_DIR]
 * (--quick: 0.1% of each span, 0.5 s of CPU at most a run, checked at each frame; without it
 * 20 s) */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "bench_args.h"
#include "bench_common.h"
#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef BENCH_EXAMPLES
#define BENCH_EXAMPLES "examples/scenes"
#endif

static size_t add_box(tb_scene *scene, double mass, double edge, const double x[3],
                      const double v[3], double turn)
{
    tb_body_def def = tb_body_def_default();
    const double size[3] = {edge, edge, edge};
    tb_mass_from_box(TB_MASS_GIVEN, mass, size, &def.mass, NULL);
    memcpy(def.position, x, sizeof def.position);
    memcpy(def.velocity, v, sizeof def.velocity);
    def.orientation[0] = cos(0.5 * turn);
    def.orientation[3] = sin(0.5 * turn);
    size_t id = 0;
    tb_scene_add_body(scene, &def, &id);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_BOX;
    memcpy(shape.size, size, sizeof size);
    tb_scene_set_body_shape(scene, id, &shape);
    return id;
}

static tb_scene *empty_scene(void)
{
    tb_scene_def def = tb_scene_def_default();
    tb_scene *scene = NULL;
    return tb_scene_create(&def, &scene, NULL) == TB_STATUS_OK ? scene : NULL;
}

/* Ten boxes, each resting on the one below at its static deflection (about 1 um a contact). */
static tb_scene *column(void)
{
    tb_scene *scene = empty_scene();
    for (int k = 0; k < 10; ++k) {
        const double x[3] = {0.0, 0.0, 0.05 + 0.1 * k}, v[3] = {0.0, 0.0, 0.0};
        add_box(scene, 0.5, 0.1, x, v, 0.0);
    }
    tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -9.81});
    tb_ground_def ground = tb_ground_def_default();
    tb_contact_def contact = tb_contact_def_default();
    tb_scene_add_ground(scene, &ground);
    tb_scene_add_contact(scene, &contact);
    return scene;
}

static tb_scene *impact(void)
{
    tb_scene *scene = empty_scene();
    const double xa[3] = {0.0, 0.0, 0.0}, va[3] = {0.5, 0.0, 0.0};
    const double xb[3] = {0.106, 0.01, 0.0}, vb[3] = {-0.5, 0.0, 0.0}; /* 3 mm apart */
    add_box(scene, 1.0, 0.1, xa, va, 0.0);
    add_box(scene, 1.0, 0.1, xb, vb, 0.05);
    tb_contact_def contact = tb_contact_def_default();
    tb_scene_add_contact(scene, &contact);
    return scene;
}

/* The example scenes by name (dice, stack) from the folder examples; column and impact built. */
static tb_scene *make(const char *name, const char *examples)
{
    if (strcmp(name, "column") == 0 || strcmp(name, "impact") == 0) {
        return strcmp(name, "column") == 0 ? column() : impact();
    }
    char path[4096];
    snprintf(path, sizeof path, "%s/%s.json", examples, name);
    tb_scene *scene = NULL;
    tb_run_def run;
    return tb_scene_load_file(path, &scene, &run, NULL) == TB_STATUS_OK ? scene : NULL;
}

/* A run stops at the first frame after budget CPU seconds (status "budget"): BDF takes minutes of
 * CPU a simulated second on the dice with the dense and Krylov solvers. */
static void run(const char *name, const char *examples, tb_linear_solver solver, const char *label,
                double span, double budget)
{
    tb_scene *scene = make(name, examples);
    if (scene == NULL) {
        fprintf(stderr, "bench_bdf_contact: cannot make %s\n", name);
        exit(1);
    }
    if (solver == TB_LINEAR_SOLVER_DENSE) { /* once a scene: what auto would pick */
        fprintf(stderr, "bench_bdf_contact: %s has %zu unknowns\n", name,
                tb_scene_state_size(scene));
    }
    tb_integrator_def def = tb_integrator_def_default();
    tb_integrator_def_set_method(&def, TB_METHOD_CVODE_BDF);
    def.linear_solver = solver;
    tb_integrator *integrator = NULL;
    tb_status status = tb_scene_integrator_create(scene, &def, 0.0, &integrator);
    if (status != TB_STATUS_OK) {
        fprintf(stderr, "bench_bdf_contact: %s %s: %s\n", name, label, tb_scene_detail(scene));
    }
    const double start = bench_cpu_seconds();
    double t = 0.0;
    const char *what = status == TB_STATUS_OK ? "ok" : tb_status_name(status);
    for (int frame = 1; status == TB_STATUS_OK && t < span - 1e-12; ++frame) {
        status =
            tb_integrator_advance(integrator, fmin(span, frame * fmin(1.0 / 60.0, span / 10.0)));
        if (status == TB_STATUS_OK) {
            t = tb_integrator_time(integrator);
            if (bench_cpu_seconds() - start > budget && t < span - 1e-12) {
                what = "budget";
                break;
            }
        } else {
            what = tb_status_name(status);
            fprintf(stderr, "bench_bdf_contact: %s %s: %s\n", name, label,
                    tb_integrator_detail(integrator));
        }
    }
    const double cpu = bench_cpu_seconds() - start;
    tb_integrator_stats stats = {0};
    if (integrator != NULL) {
        tb_integrator_get_stats(integrator, &stats);
    }
    printf("%s,%s,%s,%.4g,%ld,%ld,%ld,%ld,%ld,%ld,%.4g,%.4g\n", name, label, what, t, stats.steps,
           stats.error_test_failures, stats.nonlinear_failures, stats.nonlinear_iterations,
           stats.jacobian_evals, stats.derivative_evals, cpu, t > 0.0 ? cpu / t : NAN);
    fflush(stdout);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

int main(int argc, char **argv)
{
    const bench_args args = bench_parse_args(argc, argv, BENCH_EXAMPLES, true);
    bench_print_machine("bench_bdf_contact");
    printf("scene,solver,status,reached_s,steps,error_test_failures,newton_failures,"
           "newton_iterations,jacobians,derivatives,cpu_s,cpu_s_per_s\n");
    static const struct {
        const char *name;
        double span;
    } scenes[] = {{"dice", 0.25}, {"column", 1.0}, {"impact", 0.05}, {"stack", 0.05}};
    static const struct {
        tb_linear_solver solver;
        const char *label;
    } solvers[] = {{TB_LINEAR_SOLVER_DENSE, "dense"},
                   {TB_LINEAR_SOLVER_KRYLOV, "krylov"},
                   {TB_LINEAR_SOLVER_SPARSE, "sparse"}};
    for (size_t s = 0; s < sizeof scenes / sizeof scenes[0]; ++s) {
        for (size_t k = 0; k < sizeof solvers / sizeof solvers[0]; ++k) {
            if (!bench_wanted(args.solver, solvers[k].label) ||
                !bench_wanted(args.scene, scenes[s].name)) {
                continue;
            }
            run(scenes[s].name, args.examples, solvers[k].solver, solvers[k].label,
                scenes[s].span * (args.quick ? 0.001 : 1.0), args.quick ? 0.5 : 20.0);
        }
    }
    return 0;
}
