/* timer.h - wall-clock timing for benchmarks, the viewer's frame counter and progress reports,
 * and the median every timing report uses.
 *
 * A monotonic clock: never jumps with NTP or date changes, so differences of two readings
 * are true elapsed time. The zero point is arbitrary; only differences mean anything. */
#ifndef SL_TIMER_H
#define SL_TIMER_H

/* Seconds since an arbitrary fixed point, monotonic, nanosecond resolution where the
 * system offers it. Thread-safe. */
double sl_now_seconds(void);

/* CPU time, in seconds from an arbitrary point, of the calling thread and of the whole process:
 * work done, without the time a thread waited or was descheduled (0 where the system has no
 * such clock). What splits a parallel region's wall time between the stages fused in it. */
double sl_thread_cpu_seconds(void);
double sl_process_cpu_seconds(void);

/* The median of n > 0 values (the mean of the middle two for even n); sorts `values` in place.
 * Timings on a shared machine have long tails: reports quote medians, not means. */
double sl_median(double *values, int n);

#endif
