/* threads.h - the thread count of a parallel region: the caller's, 0 (or less) meaning every core
 * OpenMP offers (omp_get_max_threads). The library never sets OpenMP's default team size; each
 * entry point that opens a region takes its count from its desc or an argument and passes it to
 * num_threads(sl_threads(n)). */
#ifndef SL_THREADS_H
#define SL_THREADS_H

#include <omp.h>

static inline int sl_threads(int threads) { return threads > 0 ? threads : omp_get_max_threads(); }

#endif
