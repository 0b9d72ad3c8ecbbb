/* fuzz_pfm.c - libFuzzer target for the .pfm reader (src/core/pfm.c).
 *
 * Any input must either parse or fail with an error naming the file, without crashing,
 * hanging or leaking. What parses must hold finite, non-negative values (repaired on
 * load) and must come back bit for bit from the writer and the reader again. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/image.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sl_image img;
    sl_image_repairs rep;
    sl_error err = {0};
    if (!sl_image_parse_pfm(data, size, "fuzz.pfm", (size_t)64 << 20, &img, &rep, &err)) {
        if (img.data || strncmp(err.msg, "fuzz.pfm: ", 10) != 0) {
            fprintf(stderr, "bad failure: data %p, message '%s'\n", (void *)img.data, err.msg);
            abort();
        }
        return 0;
    }
    size_t n = (size_t)img.width * (size_t)img.height * (size_t)img.channels;
    for (size_t i = 0; i < n; i++)
        if (!isfinite(img.data[i]) || img.data[i] < 0.0f)
            abort();
    unsigned char *bytes;
    size_t len;
    if (!sl_image_encode_pfm(&img, &bytes, &len, &err))
        abort();
    sl_image back;
    if (!sl_image_parse_pfm(bytes, len, "again.pfm", (size_t)64 << 20, &back, NULL, &err)) {
        fprintf(stderr, "re-reading the written file failed: %s\n", err.msg);
        abort();
    }
    if (back.width != img.width || back.height != img.height || back.channels != img.channels ||
        memcmp(back.data, img.data, n * sizeof(float)) != 0)
        abort();
    free(bytes);
    sl_image_free(&back);
    sl_image_free(&img);
    return 0;
}
