/* The SVG chart of tumble accuracy: a 520 x 320 plot area at (60, 40), decades on both axes. */
#include "chart.h"

#include <math.h>

typedef struct axes {
    double x0, x1, y0, y1; /* decades: log10 of the axes' ends */
} axes;

static double chart_x(const axes *a, double ms)
{
    return 60.0 + 520.0 * (log10(ms) - a->x0) / (a->x1 - a->x0);
}

static double chart_y(const axes *a, double error)
{
    return 360.0 - 320.0 * (log10(error) - a->y0) / (a->y1 - a->y0);
}

static int plotted(const tb_accuracy_result *r)
{
    return r->status == TB_STATUS_OK && r->error > 0 && r->cpu_seconds > 0;
}

static axes choose_axes(const tb_accuracy_result *results, size_t count, double target)
{
    double lo_t = INFINITY, hi_t = 0, lo_e = target, hi_e = target;
    for (size_t k = 0; k < count; ++k) {
        if (plotted(&results[k])) {
            lo_t = fmin(lo_t, 1e3 * results[k].cpu_seconds);
            hi_t = fmax(hi_t, 1e3 * results[k].cpu_seconds);
            lo_e = fmin(lo_e, results[k].error);
            hi_e = fmax(hi_e, results[k].error);
        }
    }
    if (!(lo_t <= hi_t)) { /* nothing ran: one decade of time */
        lo_t = 1.0, hi_t = 10.0;
    }
    axes a = {floor(log10(lo_t)), ceil(log10(hi_t)), floor(log10(lo_e)), ceil(log10(hi_e))};
    a.x1 += a.x1 == a.x0;
    a.y1 += a.y1 == a.y0;
    return a;
}

static void frame_and_labels(cli_output *out, const axes *a, double target)
{
    cli_output_printf(out, "<svg xmlns='http://www.w3.org/2000/svg' width='760' height='420' "
                           "font-family='sans-serif' font-size='12'>\n<rect width='760' "
                           "height='420' fill='white'/>\n<rect x='60' y='40' width='520' "
                           "height='320' fill='none' stroke='black'/>\n");
    for (double e = a->x0; e <= a->x1; ++e) {
        cli_output_printf(out, "<text x='%.0f' y='378' text-anchor='middle'>1e%.0f</text>\n",
                          chart_x(a, pow(10, e)), e);
    }
    for (double e = a->y0; e <= a->y1; ++e) {
        cli_output_printf(out, "<text x='55' y='%.0f' text-anchor='end'>1e%.0f</text>\n",
                          chart_y(a, pow(10, e)) + 4, e);
    }
    cli_output_printf(out,
                      "<text x='320' y='400' text-anchor='middle'>CPU time (ms)</text>\n"
                      "<text x='15' y='200' transform='rotate(-90 15 200)' "
                      "text-anchor='middle'>largest error (m)</text>\n<line x1='60' x2='580' "
                      "y1='%.1f' y2='%.1f' stroke='gray' stroke-dasharray='4'/>\n",
                      chart_y(a, target), chart_y(a, target));
}

void chart_write(cli_output *out, const tb_accuracy_result *results, size_t count, double target)
{
    const axes a = choose_axes(results, count, target);
    frame_and_labels(out, &a, target);
    static const char *const colours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd"};
    for (int m = 0; m < TB_METHOD_COUNT; ++m) {
        cli_output_printf(out, "<polyline fill='none' stroke='%s' stroke-width='2' points='",
                          colours[m % 5]);
        for (size_t k = 0; k < count; ++k) {
            const tb_accuracy_result *r = &results[k];
            if ((int)r->method == m && plotted(r)) {
                cli_output_printf(out, "%.1f,%.1f ", chart_x(&a, 1e3 * r->cpu_seconds),
                                  chart_y(&a, r->error));
            }
        }
        cli_output_printf(out, "'/>\n<text x='595' y='%d' fill='%s'>%s</text>\n", 60 + 20 * m,
                          colours[m % 5], tb_method_name((tb_method)m));
    }
    cli_output_printf(out, "</svg>\n");
}
