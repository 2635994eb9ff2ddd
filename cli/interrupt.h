/* Ctrl-C during a run: the run stops at its next frame and leaves no unfinished file. */
#ifndef TUMBLE_CLI_INTERRUPT_H
#define TUMBLE_CLI_INTERRUPT_H

/* Catches SIGINT, SIGTERM and SIGHUP, those not ignored already: the handler only notes the
 * signal (once: a second one ends the process at once, as it would have without the handler). */
void cli_interrupt_catch(void);

/* The signal caught, or 0. */
int cli_interrupt_caught(void);

/* After the output is cleaned up: ends the process by the signal caught, with its default
 * action (a shell sees 128 + its number); returns when none was caught. */
void cli_interrupt_finish(void);

#endif
