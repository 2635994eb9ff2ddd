/* The method table: one row per tb_method holding every fact about the method (name, order,
 * fixed or adaptive, multistep, cost, stability limits) and how the integrator runs it.
 * Everything else asks the row: the scene's stability guard, the CLI, the bindings. */
#include "ode/integrator.h"

#include "core/detail.h"
#include "core/validate.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

/* The stability limits are roots of |R(z)| = growth for each method's stability polynomial
 * R(z), z = h lambda:
 *   Euler     R = 1 + z                      imaginary |R(iy)|^2 = 1 + y^2:   y = sqrt(1.01^2 - 1)
 *   midpoint  R = 1 + z + z^2/2              |R(iy)|^2 = 1 + y^4/4:  y = (4 (1.01^2 - 1))^(1/4)
 *   RK4       R = sum_{k<=4} z^k / k!        |R(iy)| = 1 at y = 2 sqrt 2; R(-x) = 1 at
 *                                            x = 2.7852935634 (bisection to the last digit)
 * Euler and midpoint have |R(-2)| = 1. tests/test_ode.c measures each on the steppers. */
#define TB__EULER_IMAGINARY 0.14177446878757827
#define TB__MIDPOINT_IMAGINARY 0.5324931338291194
#define TB__RK4_IMAGINARY 2.8284271247461903
#define TB__RK4_REAL 2.7852935634052813

/* |R| at which Euler's and midpoint's imaginary limits are taken: they grow on the whole axis */
#define TB__SLOW_GROWTH 1.01

const tb__method_entry tb__methods[TB_METHOD_COUNT] = {
    [TB_METHOD_EULER] = {.info = {.name = "euler",
                                  .order = 1,
                                  .adaptive = 0,
                                  .multistep = 0,
                                  .derivative_evals_per_step = 1,
                                  .imaginary_limit = TB__EULER_IMAGINARY,
                                  .imaginary_growth = TB__SLOW_GROWTH,
                                  .real_limit = 2.0},
                         .reads = TB__READS_DT | TB__READS_MAX_STEPS,
                         .backend = &tb__fixed_step_backend,
                         .step = tb__euler_step,
                         .linearly_implicit = false},
    [TB_METHOD_MIDPOINT] = {.info = {.name = "midpoint",
                                     .order = 2,
                                     .adaptive = 0,
                                     .multistep = 0,
                                     .derivative_evals_per_step = 2,
                                     .imaginary_limit = TB__MIDPOINT_IMAGINARY,
                                     .imaginary_growth = TB__SLOW_GROWTH,
                                     .real_limit = 2.0},
                            .reads = TB__READS_DT | TB__READS_MAX_STEPS,
                            .backend = &tb__fixed_step_backend,
                            .step = tb__midpoint_step,
                            .linearly_implicit = false},
    [TB_METHOD_RK4] = {.info = {.name = "rk4",
                                .order = 4,
                                .adaptive = 0,
                                .multistep = 0,
                                .derivative_evals_per_step = 4,
                                .imaginary_limit = TB__RK4_IMAGINARY,
                                .imaginary_growth = 1.0,
                                .real_limit = TB__RK4_REAL},
                       .reads = TB__READS_DT | TB__READS_MAX_STEPS,
                       .backend = &tb__fixed_step_backend,
                       .step = tb__rk4_step,
                       .linearly_implicit = false},
    [TB_METHOD_CVODE_ADAMS] = {.info = {.name = "cvode-adams",
                                        .order = 12,
                                        .adaptive = 1,
                                        .multistep = 1,
                                        .derivative_evals_per_step = 0,
                                        .imaginary_limit = INFINITY,
                                        .imaginary_growth = 1.0,
                                        .real_limit = INFINITY},
                               .reads = TB__READS_TOLERANCES | TB__READS_MAX_STEPS,
                               .backend = &tb__cvode_backend,
                               .step = NULL,
                               .linearly_implicit = false},
    [TB_METHOD_CVODE_BDF] = {.info = {.name = "cvode-bdf",
                                      .order = 5,
                                      .adaptive = 1,
                                      .multistep = 1,
                                      .derivative_evals_per_step = 0,
                                      .imaginary_limit = INFINITY,
                                      .imaginary_growth = 1.0,
                                      .real_limit = INFINITY},
                             .reads = TB__READS_TOLERANCES | TB__READS_LINEAR_SOLVER |
                                      TB__READS_MAX_STEPS,
                             .backend = &tb__cvode_backend,
                             .step = NULL,
                             .linearly_implicit = false},
    /* ROS2 (rosenbrock.c): R(z) = (1 + (1 - 2 gamma) z) / (1 - gamma z)^2 is A- and L-stable */
    [TB_METHOD_ROSENBROCK] = {.info = {.name = "rosenbrock",
                                       .order = 2,
                                       .adaptive = 0,
                                       .multistep = 0,
                                       .derivative_evals_per_step = 2,
                                       .imaginary_limit = INFINITY,
                                       .imaginary_growth = 1.0,
                                       .real_limit = INFINITY},
                              .reads = TB__READS_DT | TB__READS_MAX_STEPS,
                              .backend = &tb__fixed_step_backend,
                              .step = NULL,
                              .linearly_implicit = true},
    [TB_METHOD_ARK_IMEX] = {.info = {.name = "ark-imex",
                                     .order = 5,
                                     .adaptive = 1,
                                     .multistep = 0,
                                     .derivative_evals_per_step = 0,
                                     .imaginary_limit = INFINITY,
                                     .imaginary_growth = 1.0,
                                     .real_limit = INFINITY},
                            .reads = TB__READS_TOLERANCES | TB__READS_LINEAR_SOLVER |
                                     TB__READS_MAX_STEPS,
                            .backend = &tb__arkode_backend,
                            .step = NULL,
                            .linearly_implicit = false},
};

static bool is_method(tb_method method)
{
    return (int)method >= 0 && method < TB_METHOD_COUNT;
}

tb_status tb_method_get_info(tb_method method, tb_method_info *out_info)
{
    if (out_info == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    if (!is_method(method)) {
        return TB_STATUS_INVALID_ARGUMENT;
    }
    *out_info = tb__methods[method].info;
    return TB_STATUS_OK;
}

const char *tb_method_name(tb_method method)
{
    return is_method(method) ? tb__methods[method].info.name : NULL;
}

int tb_method_order(tb_method method)
{
    return is_method(method) ? tb__methods[method].info.order : 0;
}

int tb_method_is_adaptive(tb_method method)
{
    return is_method(method) ? tb__methods[method].info.adaptive : 0;
}

/* "euler, midpoint, rk4, cvode-adams, cvode-bdf" from the table. */
static void list_methods(char *out, size_t size)
{
    out[0] = '\0';
    for (int m = 0; m < TB_METHOD_COUNT; ++m) {
        const size_t used = strlen(out);
        snprintf(out + used, size - used, "%s%s", m > 0 ? ", " : "", tb__methods[m].info.name);
    }
}

tb_status tb_method_parse(const char *name, tb_method *out_method, tb_error *out_error)
{
    tb__clear_error(out_error);
    if (name == NULL || out_method == NULL) {
        return tb__set_error(out_error, TB_STATUS_NULL_POINTER, "%s is NULL",
                             name == NULL ? "name" : "out_method");
    }
    for (int m = 0; m < TB_METHOD_COUNT; ++m) {
        if (tb__same_name(name, tb__methods[m].info.name)) {
            *out_method = (tb_method)m;
            return TB_STATUS_OK;
        }
    }
    char methods[128];
    list_methods(methods, sizeof methods);
    return tb__set_error(out_error, TB_STATUS_INVALID_ARGUMENT,
                         "unknown method \"%.64s\"; methods: %s", name, methods);
}

tb_status tb_method_from_name(const char *name, tb_method *out_method)
{
    return tb_method_parse(name, out_method, NULL);
}

/* Every setting a method may read, by its name in tb_integrator_def (allow_unstable is the
 * scene's: its stability guard judges a fixed step), and the group of the rows' `reads` it
 * belongs to. The loader's, the CLI's and the bindings' keys are these names. */
static const struct {
    const char *name;
    unsigned group;
} settings[] = {
    {"dt", TB__READS_DT},
    {"threads", TB__READS_DT},
    {"allow_unstable", TB__READS_DT},
    {"rtol", TB__READS_TOLERANCES},
    {"atol", TB__READS_TOLERANCES},
    {"atol_vector", TB__READS_TOLERANCES},
    {"initial_step", TB__READS_TOLERANCES},
    {"max_step", TB__READS_TOLERANCES},
    {"max_order", TB__READS_TOLERANCES},
    {"linear_solver", TB__READS_LINEAR_SOLVER},
    {"preconditioner_half_bandwidth", TB__READS_LINEAR_SOLVER},
    {"max_steps", TB__READS_MAX_STEPS},
};
#define TB__SETTING_COUNT (sizeof settings / sizeof settings[0])

/* The setting's group, 0 for an unknown name. */
static unsigned setting_group(const char *setting)
{
    for (size_t k = 0; k < TB__SETTING_COUNT; ++k) {
        if (strcmp(settings[k].name, setting) == 0) {
            return settings[k].group;
        }
    }
    return 0;
}

bool tb__method_reads(tb_method method, const char *setting)
{
    return (tb__methods[method].reads & setting_group(setting)) != 0;
}

/* The methods whose reads have group, as "fixed-step methods (euler, midpoint, rk4)" when
 * they are all the fixed-step ones, "adaptive methods (...)" when all the adaptive ones, else
 * "cvode-bdf only". */
static void readers(unsigned group, char *out, size_t size)
{
    char names[128] = "";
    bool all_fixed = true, all_adaptive = true;
    for (int m = 0; m < TB_METHOD_COUNT; ++m) {
        const bool reads = (tb__methods[m].reads & group) != 0;
        const bool adaptive = tb__methods[m].info.adaptive != 0;
        all_fixed = all_fixed && reads == !adaptive;
        all_adaptive = all_adaptive && reads == adaptive;
        if (reads) {
            const size_t used = strlen(names);
            snprintf(names + used, sizeof names - used, "%s%s", used > 0 ? ", " : "",
                     tb__methods[m].info.name);
        }
    }
    if (all_fixed || all_adaptive) {
        snprintf(out, size, "%s methods (%s)", all_fixed ? "fixed-step" : "adaptive", names);
    } else {
        snprintf(out, size, "%s only", names);
    }
}

void tb__setting_readers(tb_method method, const char *setting, char *out, size_t size)
{
    char who[160];
    readers(setting_group(setting), who, sizeof who);
    snprintf(out, size, "applies to %s, not to %s", who, tb__methods[method].info.name);
}

/* "dt, threads, allow_unstable, ..." */
static void list_settings(char *out, size_t size)
{
    out[0] = '\0';
    for (size_t k = 0; k < TB__SETTING_COUNT; ++k) {
        const size_t used = strlen(out);
        snprintf(out + used, size - used, "%s%s", k > 0 ? ", " : "", settings[k].name);
    }
}

tb_status tb_method_check_setting(tb_method method, const char *setting, tb_error *out_error)
{
    tb__clear_error(out_error);
    if (setting == NULL) {
        return tb__set_error(out_error, TB_STATUS_NULL_POINTER, "setting is NULL");
    }
    if (!is_method(method)) {
        return tb__set_error(out_error, TB_STATUS_INVALID_ARGUMENT, "method: unknown method %d",
                             (int)method);
    }
    if (setting_group(setting) == 0) {
        char names[256];
        list_settings(names, sizeof names);
        return tb__set_error(out_error, TB_STATUS_INVALID_ARGUMENT,
                             "unknown setting \"%.64s\"; settings: %s", setting, names);
    }
    if (tb__method_reads(method, setting)) {
        return TB_STATUS_OK;
    }
    char message[TB_DETAIL_SIZE];
    tb__setting_readers(method, setting, message, sizeof message);
    return tb__set_error(out_error, TB_STATUS_UNSUPPORTED, "%s", message);
}
