/* error.h - errors as values.
 *
 * Library code never exits or aborts on bad input: a function that can fail
 * takes an `sl_error *` (may be NULL), fills it with a code and one line of
 * text naming the file and the place (byte offset, line, JSON path), and
 * returns false or NULL. The command line prints err.msg and exits non-zero. */
#ifndef SL_ERROR_H
#define SL_ERROR_H

#include <stdbool.h>
#include <stddef.h>

#include <softlight/types.h>

/* sl_error_code and sl_error are public: softlight/types.h. */


/* Fill `err` (if not NULL) with a code and a printf-style message; returns false
 * so that `return sl_fail(err, ...)` reads as a failing return. */
bool sl_fail(sl_error *err, sl_error_code code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* Up to `max` bytes of the string s for a message, each byte that is not printable ASCII shown
 * as '?' and "..." after a longer one, so that an input file cannot put escape sequences or
 * broken UTF-8 on a terminal. Writes at most `out_size` bytes (the excerpt is shortened to fit,
 * "..." and the terminating NUL included), so no `max` can overrun `out`; returns out. */
const char *sl_error_excerpt(const char *s, size_t max, char *out, size_t out_size);

/* Prefix an existing message with context, e.g. "scene.json: " + "line 3: ...". */
void sl_error_prefix(sl_error *err, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

#endif
