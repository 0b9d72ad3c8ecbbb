/* fuzz_exr.c - libFuzzer target for the OpenEXR reader (src/core/exr.c) over OpenEXRCore.
 *
 * The input is fed from memory through the reader's stream callbacks, as an environment (R, G,
 * B or Y) and as a layer read (signed values kept). Any input must either parse or fail with an
 * error naming the file, without crashing, hanging or leaking; this also fuzzes the library's
 * own header and chunk decoding, which the reader guards (chunk sizes against the file and the
 * header). What parses as an environment must hold finite, non-negative values and come back
 * bit for bit from the writer and the reader again (this found OpenEXRCore 3.1's writer storing
 * chunks that compress to exactly their raw size as compressed: exr.c's compress_or_store_raw). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/exr.h"
#include "core/image.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sl_image img;
    sl_error err = {0};
    if (sl_exr_parse_layer(data, size, "normal", NULL, (size_t)64 << 20, &img, &err))
        sl_image_free(&img);
    else if (img.data || strncmp(err.msg, "(memory): ", 10) != 0) {
        fprintf(stderr, "bad failure: data %p, message '%s'\n", (void *)img.data, err.msg);
        abort();
    }
    sl_image_repairs rep;
    if (!sl_image_parse_exr(data, size, "fuzz.exr", (size_t)64 << 20, &img, &rep, &err)) {
        if (img.data || strncmp(err.msg, "fuzz.exr: ", 10) != 0) {
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
    if (!sl_image_encode_exr(&img, &bytes, &len, &err))
        abort();
    sl_image back;
    if (!sl_image_parse_exr(bytes, len, "again.exr", (size_t)64 << 20, &back, NULL, &err)) {
        fprintf(stderr, "re-reading the written file failed: %s\n", err.msg);
        abort();
    }
    if (back.width != img.width || back.height != img.height || memcmp(back.data, img.data, n * sizeof(float)) != 0) {
        fprintf(stderr, "the written file reads back different\n");
        abort();
    }
    free(bytes);
    sl_image_free(&back);
    sl_image_free(&img);
    return 0;
}
