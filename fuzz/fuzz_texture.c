/* fuzz_texture.c - libFuzzer target for texture files as sl_texture_load reads them
 * (src/raster/texture.c): PNG through libpng and JPEG through libjpeg-turbo (src/core/png_decode.c,
 * jpeg_decode.c: 8 and 16 bits, 1 to 4 channels), BMP and TGA through softlight's own decoders
 * (bmp_decode.c, tga_decode.c), Radiance .hdr through hdr.c, told apart by their first bytes (a
 * TGA, which has none, by its name: every input is named fuzz.tga), then the mip chain.
 *
 * Any input must either load or fail with an error naming the file, leaving no texture,
 * without crashing, hanging or leaking. What loads must hold a whole chain whose samples are
 * finite (the .hdr reader repairs NaN and Inf), at every level and filter. Debian's libpng and
 * libjpeg-turbo are not instrumented, so coverage guides through softlight's side only (and
 * ASan sees only what they do to softlight's memory): the seeds in fuzz/corpus/fuzz_texture
 * therefore include valid files of every layout (valid_*, fuzz/make_image_seeds.c) for the
 * mutations to start from, beside files written byte by byte (PNG chunks with zlib data, a
 * baseline JPEG of one DC-only block per component, a flat .hdr) and reproducers of past
 * findings; test_texture reads some of them too. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raster/texture.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* A few bytes of header can declare millions of pixels: a 121x16392 grey JPEG (found by the
 * fuzzer, within a 64 MiB budget) took 1.3 s to decode and build mips in the sanitized build, 6 s
 * on a loaded machine, over the 5 s timeout. 4 MiB still admits images of a few hundred thousand
 * pixels, so every decoder path and the mip builder run, and keeps each input well under a second. */
#define FUZZ_BUDGET ((size_t)4 << 20)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sl_texture *t = NULL;
    sl_error err = {0};
    bool srgb = size % 2 == 1; /* both kinds of 8-bit colour, from the same corpus */
    if (!sl_texture_load_memory(data, size, "fuzz.tga", srgb, FUZZ_BUDGET, &t, &err)) {
        if (t || strncmp(err.msg, "fuzz.tga: ", 10) != 0) {
            fprintf(stderr, "bad failure: texture %p, message '%s'\n", (void *)t, err.msg);
            abort();
        }
        return 0;
    }
    sl_sampler2D s = {t, sl_sampler_default()};
    s.state.min_filter = SL_LINEAR_MIPMAP_LINEAR;
    int levels = sl_texture_levels(t);
    ivec2 top = textureSize(&s, levels - 1);
    if (top.x != 1 || top.y != 1 || textureSize(&s, levels).x != 0)
        abort();
    for (int l = 0; l < levels; l++) {
        vec4 v = textureLod(&s, vec2(0.37f, 0.61f), (float)l + 0.5f);
        vec4 f = texelFetch(&s, ivec2(0, 0), l);
        if (!isfinite(v.x) || !isfinite(v.y) || !isfinite(v.z) || !isfinite(v.w) || !isfinite(f.x) ||
            !isfinite(f.y) || !isfinite(f.z) || !isfinite(f.w)) {
            fprintf(stderr, "level %d: non-finite sample\n", l);
            abort();
        }
    }
    sl_texture_destroy(t);
    return 0;
}
