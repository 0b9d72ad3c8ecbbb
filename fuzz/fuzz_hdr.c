/* fuzz_hdr.c - libFuzzer target for the Radiance .hdr reader (src/core/hdr.c).
 *
 * Any input must either parse or fail with an error naming the file, without crashing,
 * hanging or leaking. What parses must hold finite, non-negative values, and must come
 * back from the writer and the reader again within the RGBE bound of image.h (half a
 * mantissa step of the largest component), which also fuzzes the RLE writer. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/image.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* An image memory budget that keeps a run within -rss_limit_mb and -timeout: old-style runs let
 * a few bytes declare millions of pixels, and the budget is what refuses them. */
#define FUZZ_BUDGET ((size_t)64 << 20)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sl_image img;
    sl_image_repairs rep;
    sl_error err = {0};
    if (!sl_image_parse_hdr(data, size, "fuzz.hdr", FUZZ_BUDGET, &img, &rep, &err)) {
        if (img.data || strncmp(err.msg, "fuzz.hdr: ", 10) != 0) {
            fprintf(stderr, "bad failure: data %p, message '%s'\n", (void *)img.data, err.msg);
            abort();
        }
        return 0;
    }
    size_t n = (size_t)img.width * (size_t)img.height;
    for (size_t i = 0; i < 3 * n; i++)
        if (!isfinite(img.data[i]) || img.data[i] < 0.0f)
            abort();
    unsigned char *bytes;
    size_t len;
    if (!sl_image_encode_hdr(&img, &bytes, &len, &err))
        abort();
    sl_image back;
    if (!sl_image_parse_hdr(bytes, len, "again.hdr", FUZZ_BUDGET, &back, NULL, &err)) {
        fprintf(stderr, "re-reading the written file failed: %s\n", err.msg);
        abort();
    }
    if (back.width != img.width || back.height != img.height || back.channels != 3)
        abort();
    for (size_t i = 0; i < n; i++) {
        const float *a = img.data + 3 * i, *b = back.data + 3 * i;
        double m = fmax(a[0], fmax(a[1], a[2]));
        for (int c = 0; c < 3; c++)
            if (fabs((double)a[c] - (double)b[c]) > m / 255.0 + 1e-32) {
                fprintf(stderr, "pixel %zu component %d: %.9g came back as %.9g\n", i, c, (double)a[c], (double)b[c]);
                abort();
            }
    }
    free(bytes);
    sl_image_free(&back);
    sl_image_free(&img);
    return 0;
}
