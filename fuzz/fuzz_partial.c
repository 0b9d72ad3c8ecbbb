/* fuzz_partial.c - libFuzzer target for the partial-file reader (src/core/partial.c): any bytes
 * must parse or fail with an error, never read or allocate beyond the input's own size. A parsed
 * partial is encoded again and must parse back the same. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/partial.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sl_partial p;
    sl_error err;
    if (!sl_partial_parse(data, size, "fuzz", &p, &err))
        return 0;
    unsigned char *bytes;
    size_t n;
    if (sl_partial_encode(&p, &bytes, &n, &err)) {
        sl_partial q;
        if (!sl_partial_parse(bytes, n, "again", &q, &err) || q.entry_count != p.entry_count || q.y0 != p.y0)
            abort();
        sl_partial_free(&q);
        free(bytes);
    }
    sl_partial_free(&p);
    return 0;
}
