/* Ctrl-C during a run. The handler does what is safe in a handler, noting the signal; the
 * frame callback sees it and stops the run, the output is cleaned up as after any failed run
 * (the library's writer removes its side file; run.c removes a CSV file it had begun), and the
 * signal is raised again with its default action so that the caller learns how tumble ended. */
#define _POSIX_C_SOURCE 200809L /* sigaction */
#include "interrupt.h"

#include <signal.h>
#include <string.h>

static volatile sig_atomic_t caught = 0;

static void note(int signal_number)
{
    caught = signal_number;
}

void cli_interrupt_catch(void)
{
    struct sigaction action;
    memset(&action, 0, sizeof action);
    action.sa_handler = note;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESETHAND; /* the second signal has its default action */
    const int signals[] = {SIGINT, SIGTERM, SIGHUP};
    for (size_t k = 0; k < sizeof signals / sizeof signals[0]; ++k) {
        struct sigaction before;
        /* a signal ignored when tumble started stays ignored (nohup, a shell's background job) */
        if (sigaction(signals[k], NULL, &before) == 0 && before.sa_handler != SIG_IGN) {
            sigaction(signals[k], &action, NULL);
        }
    }
}

int cli_interrupt_caught(void)
{
    return caught;
}

void cli_interrupt_finish(void)
{
    const int signal_number = caught;
    if (signal_number != 0) {
        signal(signal_number, SIG_DFL);
        raise(signal_number);
    }
}
