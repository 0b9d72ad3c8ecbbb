/* error.c - filling sl_error values (see error.h). */
#include "error.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

bool sl_fail(sl_error *err, sl_error_code code, const char *fmt, ...)
{
    if (!err)
        return false;
    err->code = code;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->msg, sizeof err->msg, fmt, ap);
    va_end(ap);
    return false;
}

void sl_error_prefix(sl_error *err, const char *fmt, ...)
{
    if (!err)
        return;
    char prefix[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(prefix, sizeof prefix, fmt, ap);
    va_end(ap);
    /* Truncation is acceptable here: the message stays one bounded line. */
    char old[sizeof err->msg];
    memcpy(old, err->msg, sizeof old);
    size_t n = strlen(prefix);
    if (n >= sizeof err->msg)
        n = sizeof err->msg - 1;
    memcpy(err->msg, prefix, n);
    size_t rest = strnlen(old, sizeof old - 1);
    if (rest > sizeof err->msg - 1 - n)
        rest = sizeof err->msg - 1 - n;
    memcpy(err->msg + n, old, rest);
    err->msg[n + rest] = '\0';
}

const char *sl_error_excerpt(const char *s, size_t max, char *out, size_t out_size)
{
    if (out_size < 4) { /* no room for one byte and "...": say nothing rather than overrun */
        if (out_size)
            out[0] = '\0';
        return out;
    }
    if (max > out_size - 4)
        max = out_size - 4;
    size_t n = 0;
    for (; s[n] && n < max; n++) {
        unsigned char ch = (unsigned char)s[n];
        out[n] = ch >= 32 && ch < 127 ? (char)ch : '?';
    }
    if (s[n]) {
        memcpy(out + n, "...", 3);
        n += 3;
    }
    out[n] = '\0';
    return out;
}
