/* How fast a contact scene's modes really are, against what the stability guard bounds them at
 * (issue 23, docs/contact.md "Stability"). At sampled times of a run (RK4 at the scene's default
 * step) it differentiates tb_scene_derivative numerically (central differences) over the states
 * of the scene's bodies, or of those within a radius of one body, together with the effect
 * states (friction anchors) they touch, and takes the eigenvalues of that Jacobian (GSL's
 * nonsymmetric solver, balanced). Printed per sample: the most negative real part (the fastest
 * decay), the largest imaginary part (the fastest oscillation), the largest |lambda|, and the
 * longest RK4 step h with |R(h lambda)| <= 1 for every eigenvalue of |lambda| > 100 1/s (R the
 * RK4 amplification 1 + z + z^2/2 + z^3/6 + z^4/24; the slow physics is resolved at any step
 * considered here), beside the guard's stable step (tb_scene_max_stable_step) and the default.
 *
 * usage: bench_contact_rate [--quick] [SCENE.json [--at T1,T2,...] [--near BODY --radius R]]
 * No scene: the example contact scenes (dice, dominoes, stack, bowl) at the times docs/effects.md
 * samples. --quick: the dice's scene at t = 0.3 s only (the smoke test).
 * Prints CSV: scene, t, states, differentiated (the states the Jacobian is taken over),
 * guard_dt_s, default_dt_s, fastest_decay_per_s,
 * fastest_growth_per_s, fastest_oscillation_per_s, largest_modulus_per_s, local_dt_s (RK4's),
 * ratio (local / guard). */
#include "tumble/tumble.h"

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_matrix.h>

#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_SAMPLES 32
#define SLOW_MODE 100.0 /* 1/s: modes slower than this are resolved at every step considered */

typedef struct options {
    const char *path;
    double at[MAX_SAMPLES];
    int samples;
    const char *near;
    double radius;
} options;

/* |R(z)| for RK4's amplification R(z) = 1 + z + z^2/2 + z^3/6 + z^4/24. */
static double rk4_gain(double complex z)
{
    return cabs(1.0 + z * (1.0 + z * (0.5 + z * (1.0 / 6.0 + z / 24.0))));
}

/* The longest h from 0 with |R(h lambda)| <= max(1, |exp(h lambda)|) all along (scanned in 0.1%
 * steps): a growing mode (a die tipping over an edge) may grow as fast as it does. */
static double rk4_step_for(double complex lambda)
{
    const double modulus = cabs(lambda);
    double h = 1e-3 / modulus;
    while (h * modulus < 3.0 &&
           rk4_gain(h * lambda) <= fmax(1.0, exp(h * creal(lambda))) * (1.0 + 1e-12)) {
        h *= 1.001;
    }
    return h / 1.001;
}

/* The states to differentiate over: the chosen bodies' 13 each, then every other state (effect
 * states) that a chosen body's column reaches. */
typedef struct selection {
    size_t *index;
    size_t count;
} selection;

static int chosen_body(const tb_scene *scene, const double *y, const options *o, size_t id,
                       const double centre[3])
{
    if (o->near == NULL) {
        return 1;
    }
    tb_body_state s;
    (void)y;
    tb_scene_get_state(scene, id, &s);
    const double d[3] = {s.x[0] - centre[0], s.x[1] - centre[1], s.x[2] - centre[2]};
    return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) <= o->radius;
}

static double step_of(const double *y, size_t j)
{
    return 1e-9 * fabs(y[j]) + 1e-12;
}

/* Column j of the Jacobian into col (n long), central differences. */
static void column(tb_scene *scene, double t, double *y, size_t n, size_t j, double *plus,
                   double *minus, double *col)
{
    const double keep = y[j], h = step_of(y, j);
    y[j] = keep + h;
    tb_scene_derivative(t, y, plus, scene);
    y[j] = keep - h;
    tb_scene_derivative(t, y, minus, scene);
    y[j] = keep;
    for (size_t i = 0; i < n; ++i) {
        col[i] = (plus[i] - minus[i]) / (2.0 * h);
    }
}

static selection choose(tb_scene *scene, double t, double *y, size_t n, const options *o,
                        double *work)
{
    selection sel = {calloc(n, sizeof(size_t)), 0};
    char *in = calloc(n, 1);
    double centre[3] = {0, 0, 0};
    size_t near_id = 0;
    if (o->near != NULL && tb_scene_find_body(scene, o->near, &near_id) == TB_STATUS_OK) {
        tb_body_state s;
        tb_scene_get_state(scene, near_id, &s);
        memcpy(centre, s.x, sizeof centre);
    }
    size_t body_states = 0;
    for (size_t id = 0; id < tb_scene_body_count(scene); ++id) {
        size_t slot;
        if (tb_scene_body_slot(scene, id, &slot) != TB_STATUS_OK) {
            continue;
        }
        body_states = fmax(body_states, 13 * (slot + 1));
        if (chosen_body(scene, y, o, id, centre)) {
            for (size_t k = 0; k < 13; ++k) {
                in[13 * slot + k] = 1;
            }
        }
    }
    double *plus = work, *minus = work + n, *col = work + 2 * n;
    for (size_t j = 0; j < body_states; ++j) {
        if (in[j] == 1) {
            column(scene, t, y, n, j, plus, minus, col);
            for (size_t i = body_states; i < n; ++i) {
                in[i] |= col[i] != 0.0 ? 2 : 0;
            }
        }
    }
    for (size_t j = 0; j < n; ++j) {
        if (in[j] != 0) {
            sel.index[sel.count++] = j;
        }
    }
    free(in);
    return sel;
}

typedef struct modes {
    double decay, growth, oscillation, modulus, rk4_dt;
    size_t differentiated; /* the states the Jacobian is taken over */
} modes;

static modes eigen_modes(tb_scene *scene, double t, const options *o)
{
    const size_t n = tb_scene_state_size(scene);
    double *y = malloc(n * sizeof *y), *work = malloc(3 * n * sizeof *work);
    memcpy(y, tb_scene_states_const(scene), n * sizeof *y);
    selection sel = choose(scene, t, y, n, o, work);
    gsl_matrix *J = gsl_matrix_alloc(sel.count, sel.count);
    for (size_t b = 0; b < sel.count; ++b) {
        column(scene, t, y, n, sel.index[b], work, work + n, work + 2 * n);
        for (size_t a = 0; a < sel.count; ++a) {
            gsl_matrix_set(J, a, b, work[2 * n + sel.index[a]]);
        }
    }
    gsl_vector_complex *eval = gsl_vector_complex_alloc(sel.count);
    gsl_eigen_nonsymm_workspace *w = gsl_eigen_nonsymm_alloc(sel.count);
    gsl_eigen_nonsymm_params(0, 1, w);
    modes m = {0.0, 0.0, 0.0, 0.0, INFINITY, sel.count};
    if (gsl_eigen_nonsymm(J, eval, w) == 0) {
        for (size_t k = 0; k < sel.count; ++k) {
            const gsl_complex e = gsl_vector_complex_get(eval, k);
            const double complex lambda = GSL_REAL(e) + I * GSL_IMAG(e);
            m.decay = fmax(m.decay, -creal(lambda));
            m.growth = fmax(m.growth, creal(lambda));
            m.oscillation = fmax(m.oscillation, fabs(cimag(lambda)));
            m.modulus = fmax(m.modulus, cabs(lambda));
            if (cabs(lambda) > SLOW_MODE) {
                m.rk4_dt = fmin(m.rk4_dt, rk4_step_for(lambda));
            }
        }
    }
    gsl_eigen_nonsymm_free(w);
    gsl_vector_complex_free(eval);
    gsl_matrix_free(J);
    free(sel.index);
    free(work);
    free(y);
    return m;
}

static int parse(int argc, char **argv, options *o)
{
    *o = (options){NULL, {0.3}, 1, NULL, 0.0};
    for (int a = 1; a < argc; ++a) {
        if (strcmp(argv[a], "--quick") == 0) {
            o->path = TUMBLE_SCENES_DIR "/dice.json";
        } else if (strcmp(argv[a], "--at") == 0 && a + 1 < argc) {
            o->samples = 0;
            for (char *s = strtok(argv[++a], ","); s && o->samples < MAX_SAMPLES;
                 s = strtok(NULL, ",")) {
                o->at[o->samples++] = atof(s);
            }
        } else if (strcmp(argv[a], "--near") == 0 && a + 1 < argc) {
            o->near = argv[++a];
        } else if (strcmp(argv[a], "--radius") == 0 && a + 1 < argc) {
            o->radius = atof(argv[++a]);
        } else if (argv[a][0] != '-') {
            o->path = argv[a];
        } else {
            return 0;
        }
    }
    return 1;
}

typedef struct sampler {
    tb_scene *scene;
    const options *o;
    double dt;
    int next;
} sampler;

/* At each sample time: the guard's step and the Jacobian's modes at the run's state there. */
static int on_frame(size_t frame, double t, const tb_scene *scene, void *ctx)
{
    (void)frame;
    sampler *s = ctx;
    if (s->next >= s->o->samples || t < s->o->at[s->next] - 0.5 * s->dt) {
        return 0;
    }
    s->next += 1;
    double stable = 0.0;
    tb_scene_max_stable_step(scene, TB_METHOD_RK4, &stable, NULL);
    const modes m = eigen_modes(s->scene, t, s->o);
    const char *name = strrchr(s->o->path, '/') ? strrchr(s->o->path, '/') + 1 : s->o->path;
    printf("%s,%g,%zu,%zu,%.3e,%.3e,%.3e,%.3e,%.3e,%.3e,%.3e,%.2f\n", name, t,
           tb_scene_state_size(scene), m.differentiated, stable, s->dt, m.decay, m.growth,
           m.oscillation, m.modulus, m.rk4_dt, m.rk4_dt / stable);
    fflush(stdout);
    return s->next >= s->o->samples;
}

/* One scene: a run at RK4's default step, sampled at o->at. */
static int measure(const options *o)
{
    tb_scene *scene = NULL;
    tb_run_def run;
    tb_error error;
    if (tb_scene_load_file(o->path, &scene, &run, &error) != TB_STATUS_OK) {
        fprintf(stderr, "%s\n", error.message);
        return 1;
    }
    tb_integrator_def_set_method(&run.integrator, TB_METHOD_RK4);
    tb_scene_set_sleeping(scene, false); /* a sleeping body has no derivative to linearise */
    sampler s = {scene, o, 0.0, 0};
    tb_scene_default_step(scene, TB_METHOD_RK4, &s.dt);
    run.integrator.dt = s.dt;
    run.fps = 240.0;
    run.duration = o->at[o->samples - 1] + 1.0 / 240.0;
    const tb_status status = tb_scene_run(scene, &run, on_frame, &s, NULL, &error);
    tb_scene_destroy(scene);
    if (status != TB_STATUS_OK && status != TB_STATUS_CANCELLED) {
        fprintf(stderr, "%s\n", error.message);
        return 1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    options o;
    if (!parse(argc, argv, &o)) {
        fprintf(stderr, "usage: bench_contact_rate [--quick] [SCENE.json [--at T1,T2,...] "
                        "[--near BODY --radius R]]\n");
        return 2;
    }
    printf("scene,t,states,differentiated,guard_dt_s,default_dt_s,fastest_decay_per_s,"
           "fastest_growth_per_s,fastest_oscillation_per_s,largest_modulus_per_s,local_dt_s,"
           "ratio\n");
    if (o.path != NULL) {
        return measure(&o);
    }
    /* no scene: the example contact scenes at the times docs/effects.md's table samples */
    static const options examples[] = {
        {TUMBLE_SCENES_DIR "/dice.json", {0.3, 0.6, 0.9}, 3, NULL, 0.0},
        {TUMBLE_SCENES_DIR "/dominoes.json", {0.1, 0.3, 0.6, 1.0, 1.3}, 5, NULL, 0.0},
        {TUMBLE_SCENES_DIR "/stack.json", {0.5, 2.0}, 2, NULL, 0.0},
        {TUMBLE_SCENES_DIR "/bowl.json", {0.5, 1.4}, 2, NULL, 0.0},
    };
    for (size_t k = 0; k < sizeof examples / sizeof examples[0]; ++k) {
        if (measure(&examples[k]) != 0) {
            return 1;
        }
    }
    return 0;
}
