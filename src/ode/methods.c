/* The method table: one row per tb_method holding every fact about the method (name, order,
 * fixed or adaptive, multistep, cost, stability limits) and how the integrator runs it.
 * Everything else asks the row: the scene's stability guard, the CLI, the bindings. */
#include "ode/integrator.h"

#include "core/detail.h"

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
    [TB_METHOD_EULER] = {{"euler", 1, 0, 0, 1, TB__EULER_IMAGINARY, TB__SLOW_GROWTH, 2.0},
                         TB__READS_DT,
                         &tb__fixed_step_backend,
                         tb__euler_step},
    [TB_METHOD_MIDPOINT] = {{"midpoint", 2, 0, 0, 2, TB__MIDPOINT_IMAGINARY, TB__SLOW_GROWTH, 2.0},
                            TB__READS_DT,
                            &tb__fixed_step_backend,
                            tb__midpoint_step},
    [TB_METHOD_RK4] = {{"rk4", 4, 0, 0, 4, TB__RK4_IMAGINARY, 1.0, TB__RK4_REAL},
                       TB__READS_DT,
                       &tb__fixed_step_backend,
                       tb__rk4_step},
    [TB_METHOD_CVODE_ADAMS] = {{"cvode-adams", 12, 1, 1, 0, INFINITY, 1.0, INFINITY},
                               TB__READS_TOLERANCES,
                               &tb__cvode_backend,
                               NULL},
    [TB_METHOD_CVODE_BDF] = {{"cvode-bdf", 5, 1, 1, 0, INFINITY, 1.0, INFINITY},
                             TB__READS_TOLERANCES | TB__READS_LINEAR_SOLVER,
                             &tb__cvode_backend,
                             NULL},
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

/* Equal ignoring ASCII case (strcasecmp is POSIX, not C11, and follows the locale). */
static bool same_name(const char *a, const char *b)
{
    for (;; ++a, ++b) {
        const int ca = *a >= 'A' && *a <= 'Z' ? *a - 'A' + 'a' : *a;
        const int cb = *b >= 'A' && *b <= 'Z' ? *b - 'A' + 'a' : *b;
        if (ca != cb) {
            return false;
        }
        if (ca == '\0') {
            return true;
        }
    }
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
        if (same_name(name, tb__methods[m].info.name)) {
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
