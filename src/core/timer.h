/* timer.h - wall-clock timing for benchmarks, the viewer's frame counter and progress reports.
 *
 * A monotonic clock: never jumps with NTP or date changes, so differences of two readings
 * are true elapsed time. The zero point is arbitrary; only differences mean anything. */
#ifndef SL_TIMER_H
#define SL_TIMER_H

/* Seconds since an arbitrary fixed point, monotonic, nanosecond resolution where the
 * system offers it. Thread-safe. */
double sl_now_seconds(void);

#endif
