/* timer.c - sl_now_seconds on CLOCK_MONOTONIC (see timer.h). */
#include "timer.h"

#include <time.h>

double sl_now_seconds(void)
{
    struct timespec ts;
    /* CLOCK_MONOTONIC cannot fail on Linux with a valid pointer; 0 keeps the contract simple. */
    if (clock_gettime(CLOCK_MONOTONIC, &ts) != 0)
        return 0.0;
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}
