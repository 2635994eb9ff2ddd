/* tumble accuracy's chart: error against CPU time, one line per method, as SVG. */
#ifndef TUMBLE_CLI_CHART_H
#define TUMBLE_CLI_CHART_H

#include "output.h"

#include "tumble/tumble.h"

/* Writes the chart of the results that ran (log-log), with target (m) as a dashed line. */
void chart_write(cli_output *out, const tb_accuracy_result *results, size_t count, double target);

#endif
