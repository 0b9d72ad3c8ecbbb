/* texture.c - bench_texture: the cost of one texture sample per format (not a test).
 *
 * What a textured fragment pays: for each texture format, a 1024x1024 texture with its mip
 * chain (random texels) is sampled by a 512x512 "screen" whose uv steps 1.4/512 per pixel
 * across it (rho = 2.8 texels of level 0 per pixel: lambda 1.49, trilinear between levels 1
 * and 2, as a receding textured floor gives), row by row as the rasterizer's spans would. Per
 * format: storage (bytes per texel of level 0, and the whole chain), then ns per textureGrad
 * sample with LINEAR_MIPMAP_LINEAR (8 texel reads), with LINEAR (magnified, 4 reads) and with
 * NEAREST (1 read); the median of --rounds passes of the 262144 samples, one thread. The
 * formats are run alternately inside each round, so a slow minute on a shared machine hits
 * them all alike.
 *
 * usage: bench_texture [--rounds 7] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/timer.h"
#include "raster/texture.h"

#define SIZE 1024
#define SCREEN 512
#define MAX_ROUNDS 64

/* One pass over the screen; returns seconds, adds the samples to *sink so nothing is elided. */
static double pass(const sl_sampler2D *s, float lod_or_grad, bool grad, float *sink)
{
    const float step = 1.4f / SCREEN;
    vec2 dx = vec2(step, 0), dy = vec2(0, step);
    float acc = 0.0f;
    double t0 = sl_now_seconds();
    for (int y = 0; y < SCREEN; y++)
        for (int x = 0; x < SCREEN; x++) {
            vec2 uv = vec2(((float)x + 0.5f) * step, ((float)y + 0.5f) * step);
            vec4 v = grad ? textureGrad(s, uv, dx, dy) : textureLod(s, uv, lod_or_grad);
            acc += v.x + v.w;
        }
    double t = sl_now_seconds() - t0;
    *sink += acc;
    return t;
}

int main(int argc, char **argv)
{
    int rounds = 7;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--rounds") && i + 1 < argc) {
            rounds = atoi(argv[++i]);
        } else {
            fprintf(stderr, "usage: bench_texture [--rounds 7]\n");
            return 2;
        }
    }
    if (rounds < 1 || rounds > MAX_ROUNDS) {
        fprintf(stderr, "bench_texture: --rounds must be 1..%d\n", MAX_ROUNDS);
        return 2;
    }
    sl_texture_format fmts[SL_TEX_FORMAT_COUNT];
    sl_texture *tex[SL_TEX_FORMAT_COUNT];
    unsigned char *data = malloc((size_t)SIZE * SIZE * 16);
    if (!data)
        return 1;
    srand(1);
    for (size_t i = 0; i < (size_t)SIZE * SIZE * 16; i++)
        data[i] = (unsigned char)(rand() & 0xff);
    for (int f = 0; f < SL_TEX_FORMAT_COUNT; f++) {
        fmts[f] = (sl_texture_format)f;
        if (f >= SL_TEX_R32F) /* random bytes are not all finite floats: values in [0, 1) */
            for (size_t i = 0; i < (size_t)SIZE * SIZE * 4; i++) {
                float v = (float)(rand() & 0xffff) / 65536.0f;
                memcpy(data + 4 * i, &v, 4);
            }
        sl_error err = {0};
        if (!sl_texture_create(fmts[f], SIZE, SIZE, data, true, &tex[f], &err)) {
            fprintf(stderr, "bench_texture: %s\n", err.msg);
            return 1;
        }
    }
    free(data);
    /* [format][mode][round]: mode 0 trilinear (textureGrad), 1 bilinear (magnified), 2 nearest */
    static double times[SL_TEX_FORMAT_COUNT][3][MAX_ROUNDS];
    float sink = 0.0f;
    for (int r = 0; r < rounds; r++)
        for (int f = 0; f < SL_TEX_FORMAT_COUNT; f++) {
            sl_sampler2D s = {tex[f], sl_sampler_default()};
            s.state.min_filter = SL_LINEAR_MIPMAP_LINEAR;
            times[f][0][r] = pass(&s, 0.0f, true, &sink);
            times[f][1][r] = pass(&s, -1.0f, false, &sink);
            s.state.mag_filter = SL_NEAREST;
            times[f][2][r] = pass(&s, -1.0f, false, &sink);
        }
    printf("bench_texture: %dx%d textures with mips, %d samples a pass, median of %d rounds, 1 thread\n", SIZE,
           SIZE, SCREEN * SCREEN, rounds);
    printf("%-14s %8s %12s %14s %14s %14s\n", "format", "B/texel", "chain bytes", "trilinear ns", "bilinear ns",
           "nearest ns");
    for (int f = 0; f < SL_TEX_FORMAT_COUNT; f++) {
        double ns[3];
        for (int m = 0; m < 3; m++)
            ns[m] = sl_median(times[f][m], rounds) * 1e9 / (SCREEN * SCREEN);
        printf("%-14s %8d %12zu %14.1f %14.1f %14.1f\n", sl_texture_format_name(fmts[f]),
               sl_texture_format_bytes(fmts[f]), sl_texture_bytes(tex[f]), ns[0], ns[1], ns[2]);
        sl_texture_destroy(tex[f]);
    }
    printf("(checksum %g)\n", (double)sink);
    return 0;
}
