/* shading.c - benchmark of the lighting pass (src/shading/lighting.c).
 *
 * bench_shading [frames] [env.hdr]
 *   frames   frames timed per configuration (default 5; the median is reported)
 *   env.hdr  environment (default scenes/envmaps/studio.hdr, run from the source root)
 *
 * A 1280x720 G-buffer of nine spheres filled analytically (synthetic.h: the raster is not
 * involved, so only the lighting pass is timed), materials from rough (alpha 1) to near-mirror
 * (alpha 5000), 26% of the pixels covered, the rest background. For N = 20, 40, 80:
 * the median ms/frame with 1 and 2 threads and the speed-up, plus ns per specular sample. */
#include <stdio.h>
#include <stdlib.h>

#include "core/timer.h"
#include "ibl/ibl.h"
#include "shading/lighting.h"
#include "shading/synthetic.h"

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median_ms(const sl_lighting_uniforms *u, const sl_gbuffer *gb, sl_image *out, int threads, int frames,
                        sl_lighting_stats *st)
{
    double t[64];
    sl_error err;
    for (int f = 0; f < frames; f++) {
        double t0 = sl_now_seconds();
        if (!sl_lighting_pass(u, st, gb, out, threads, &err)) {
            fprintf(stderr, "bench_shading: %s\n", err.msg);
            exit(1);
        }
        t[f] = (sl_now_seconds() - t0) * 1e3;
    }
    qsort(t, (size_t)frames, sizeof t[0], cmp_double);
    return t[frames / 2];
}

int main(int argc, char **argv)
{
    int frames = argc > 1 ? atoi(argv[1]) : 5;
    const char *path = argc > 2 ? argv[2] : "scenes/envmaps/studio.hdr";
    if (frames < 1 || frames > 64) {
        fprintf(stderr, "usage: bench_shading [frames 1..64] [env.hdr]\n");
        return 2;
    }
    sl_error err;
    sl_image img = {0};
    sl_env env = {0};
    sl_irradiance irr = {0};
    if (!sl_image_read_hdr(path, &img, NULL, &err) || !sl_env_build(&env, &img, &err) ||
        !sl_irradiance_sh9(&irr, &env, &err)) {
        fprintf(stderr, "bench_shading: %s\n", err.msg);
        return 1;
    }
    const int W = 1280, H = 720;
    sl_camera cam = {.eye = vec3(0, -9, 2), .target = vec3(0, 0, 0), .up = vec3(0, 0, 1), .fovy_deg = 40,
                     .znear = 0.1f, .zfar = 100};
    sl_synthetic_sphere s[9];
    const float alphas[9] = {1, 5, 20, 50, 100, 300, 1000, 3000, 5000};
    for (int i = 0; i < 9; i++)
        s[i] = (sl_synthetic_sphere){vec3(-3.2f + 3.2f * (float)(i % 3), 2.0f * (float)(i / 3), -1.5f + 1.5f * (float)(i / 3)),
                                     1.0f, vec3(0.5f, 0.4f, 0.3f), vec3s(i % 2 ? 0.9f : 0.04f), alphas[i]};
    sl_gbuffer gb = {0};
    mat4 inv;
    if (!sl_gbuffer_synthetic_spheres(&gb, W, H, &cam, s, 9, &inv, &err)) {
        fprintf(stderr, "bench_shading: %s\n", err.msg);
        return 1;
    }
    sl_lighting_uniforms *u = malloc(sizeof *u);
    sl_image out = {0};
    printf("lighting pass, %dx%d, env %s (%dx%d), median of %d frames\n", W, H, path, img.width, img.height, frames);
    printf("%5s %9s %12s %12s %9s %14s\n", "N", "covered", "1 thread ms", "2 threads ms", "speed-up", "ns/sample (1t)");
    const int ns[3] = {20, 40, 80};
    for (int i = 0; i < 3; i++) {
        sl_lighting_desc d = {.options = {.samples = ns[i]}, .env = &env, .irradiance = &irr, .eye = cam.eye,
                              .inv_view_proj = inv, .width = W, .height = H};
        if (!sl_lighting_uniforms_init(u, &d, &err)) {
            fprintf(stderr, "bench_shading: %s\n", err.msg);
            return 1;
        }
        sl_lighting_stats st;
        double t1 = median_ms(u, &gb, &out, 1, frames, &st);
        double t2 = median_ms(u, &gb, &out, 2, frames, &st);
        double covered = (double)(st.pixels - st.background) / (double)st.pixels;
        printf("%5d %8.1f%% %12.1f %12.1f %9.2f %14.1f\n", ns[i], 100.0 * covered, t1, t2, t1 / t2,
               t1 * 1e6 / (double)st.samples);
    }
    free(u);
    sl_image_free(&out);
    sl_image_free(&img);
    sl_gbuffer_free(&gb);
    sl_irradiance_free(&irr);
    sl_env_free(&env);
    return 0;
}
