/* shading.c - benchmark of the lighting pass (src/shading/lighting_pass.c).
 *
 * bench_shading [--frames F] [--env FILE.hdr] [--n 20,40,80] [--threads 1,2] [--plain] [--rotate]
 *               [--no-specular] [--no-background] [--ggx] [--estimator spec|consistent|mf|mis]
 *   --frames F        frames timed per configuration (default 5; the median is reported)
 *   --env FILE.hdr    environment (default scenes/envmaps/studio.hdr, run from the source root)
 *   --n LIST          sample counts N (default 20,40,80)
 *   --threads LIST    thread counts (default 1,2)
 *   --plain           the line-by-line port of the GLSL (options.plain) instead of the batched path
 *   --rotate          per-pixel rotation of the Hammersley set (options.rotate)
 *   --no-specular     diffuse and background only: the per-pixel cost without samples
 *   --no-background   every pixel covered (a sphere filling the frame): samples only
 *   --ggx             GGX against Phong at equal N: a twin G-buffer whose spheres are GGX of the
 *                     same peak (r from alpha = 2 / a^2 - 2, docs/lighting.md "Phong and GGX"),
 *                     the two timed alternately frame by frame in one run: both medians and the
 *                     median of the per-round ratios GGX / Phong
 *   --estimator E     the specular estimator (default spec, the specification's eq. (3))
 *
 * A 1280x720 G-buffer of nine spheres filled analytically (synthetic.h: the raster is not
 * involved, so only the lighting pass is timed), materials from rough (alpha 1) to near-mirror
 * (alpha 5000), 26% of the pixels covered, the rest background. Per N and thread count: the
 * median ms/frame and ns per specular sample (frame time x threads / samples: the thread time a
 * sample costs, per-pixel work included). docs/performance.md "Lighting" has the figures. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/options.h"
#include "core/timer.h"
#include "ibl/ibl.h"
#include "shading/lighting.h"
#include "shading/synthetic.h"

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
    return sl_median(t, frames);
}

/* Phong (gb[0]) and GGX (gb[1]) alternately, one frame each per round after a warm-up round:
 * medians of each and of the per-round ratio GGX / Phong (a change of load falls on both). */
static void alternate_ms(const sl_lighting_uniforms *u, const sl_gbuffer gb[2], sl_image *out, int threads, int frames,
                         double ms[2], double *ratio)
{
    double t[2][64], r[64];
    sl_error err;
    for (int f = -1; f < frames; f++) {
        for (int k = 0; k < 2; k++) {
            sl_lighting_stats st;
            double t0 = sl_now_seconds();
            if (!sl_lighting_pass(u, &st, &gb[k], out, threads, &err)) {
                fprintf(stderr, "bench_shading: %s\n", err.msg);
                exit(1);
            }
            if (f >= 0)
                t[k][f] = (sl_now_seconds() - t0) * 1e3;
        }
        if (f >= 0)
            r[f] = t[1][f] / t[0][f];
    }
    ms[0] = sl_median(t[0], frames);
    ms[1] = sl_median(t[1], frames);
    *ratio = sl_median(r, frames);
}

/* "20,40,80" -> {20, 40, 80}; returns the count (0 on a bad list). */
static int parse_list(const char *s, int *v, int max)
{
    int n = 0;
    while (*s && n < max) {
        char *end;
        long x = strtol(s, &end, 10);
        if (end == s || x < 1 || x > 1024)
            return 0;
        v[n++] = (int)x;
        s = *end == ',' ? end + 1 : end;
        if (*end && *end != ',')
            return 0;
    }
    return n;
}

int main(int argc, char **argv)
{
    int frames = 5, ns[16] = {20, 40, 80}, nn = 3, threads[8] = {1, 2}, nt = 2;
    const char *path = "scenes/envmaps/studio.hdr";
    sl_lighting_options base = {0};
    bool no_background = false, ggx = false;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--frames") && v) {
            frames = atoi(v);
            i++;
        } else if (!strcmp(a, "--env") && v) {
            path = v;
            i++;
        } else if (!strcmp(a, "--n") && v) {
            nn = parse_list(v, ns, 16);
            i++;
        } else if (!strcmp(a, "--threads") && v) {
            nt = parse_list(v, threads, 8);
            i++;
        } else if (!strcmp(a, "--plain")) {
            base.plain = true;
        } else if (!strcmp(a, "--rotate")) {
            base.rotate = true;
        } else if (!strcmp(a, "--no-specular")) {
            base.no_specular = true;
        } else if (!strcmp(a, "--no-background")) {
            no_background = true;
        } else if (!strcmp(a, "--ggx")) {
            ggx = true;
        } else if (!strcmp(a, "--estimator") && v) {
            if (!sl_estimator_parse(v, &base.estimator)) {
                nn = 0;
                break;
            }
            i++;
        } else {
            nn = 0;
            break;
        }
    }
    if (frames < 1 || frames > 64 || nn == 0 || nt == 0) {
        fprintf(stderr, "usage: bench_shading [--frames 1..64] [--env FILE.hdr] [--n 20,40,80] [--threads 1,2] "
                        "[--plain] [--rotate] [--no-specular] [--no-background] [--ggx]\n"
                        "       [--estimator spec|consistent|mf|mis]\n");
        return 2;
    }
    sl_error err;
    sl_image img = {0};
    sl_env env = {0};
    sl_irradiance irr = {0};
    if (!sl_image_read_hdr(path, 0, &img, NULL, &err) || !sl_env_build(&env, &img, 0, &err) ||
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
    if (no_background) /* one big glossy sphere the camera sits in front of, filling the frame */
        s[0] = (sl_synthetic_sphere){vec3(0, 0, 0), 7.0f, vec3(0.5f, 0.4f, 0.3f), vec3s(0.5f), 50.0f};
    sl_gbuffer gb = {0};
    mat4 inv;
    if (!sl_gbuffer_synthetic_spheres(&gb, W, H, &cam, s, no_background ? 1 : 9, &inv, 0, &err)) {
        fprintf(stderr, "bench_shading: %s\n", err.msg);
        return 1;
    }
    /* the GGX twin: each sphere's Phong exponent becomes the roughness of equal peak D,
     * a^2 = 2 / (alpha + 2), r = sqrt(a) */
    sl_gbuffer gbs[2] = {gb, {0}};
    if (ggx) {
        for (int i = 0; i < 9; i++)
            s[i].alpha = sl_gbuffer_ggx_alpha(sqrtf(sqrtf(2.0f / (s[i].alpha + 2.0f))));
        if (!sl_gbuffer_synthetic_spheres(&gbs[1], W, H, &cam, s, no_background ? 1 : 9, NULL, 0, &err)) {
            fprintf(stderr, "bench_shading: %s\n", err.msg);
            return 1;
        }
    }
    sl_env_dist dist = {0}; /* --estimator mis: the environment's distribution, built once */
    if (base.estimator == SL_ESTIMATOR_MIS && !sl_env_dist_build(&dist, &env, &err)) {
        fprintf(stderr, "bench_shading: %s\n", err.msg);
        return 1;
    }
    sl_lighting_uniforms *u = malloc(sizeof *u);
    sl_image out = {0};
    printf("lighting pass, %dx%d, env %s (%dx%d), %s path, estimator %s%s%s, median of %d frames%s\n", W, H, path,
           img.width, img.height, base.plain ? "plain" : "batched", sl_estimator_name(base.estimator),
           base.rotate ? ", rotation on" : "", base.no_specular ? ", no specular" : "", frames,
           ggx ? ", Phong and its GGX twin alternating" : "");
    if (ggx)
        printf("%5s %8s %10s %10s %12s\n", "N", "threads", "Phong ms", "GGX ms", "GGX/Phong");
    else
        printf("%5s %8s %8s %10s %14s\n", "N", "covered", "threads", "ms", "ns/sample");
    for (int i = 0; i < nn; i++) {
        sl_lighting_options o = base;
        o.samples = ns[i];
        sl_lighting_desc d = {.options = o, .env = &env, .irradiance = &irr, .eye = cam.eye, .inv_view_proj = inv,
                              .width = W, .height = H, .env_dist = &dist};
        if (!sl_lighting_uniforms_init(u, &d, &err)) {
            fprintf(stderr, "bench_shading: %s\n", err.msg);
            return 1;
        }
        for (int t = 0; t < nt && ggx; t++) {
            double ms[2], ratio;
            alternate_ms(u, gbs, &out, threads[t], frames, ms, &ratio);
            printf("%5d %8d %10.1f %10.1f %12.3f\n", ns[i], threads[t], ms[0], ms[1], ratio);
        }
        for (int t = 0; t < nt && !ggx; t++) {
            sl_lighting_stats st;
            double ms = median_ms(u, &gb, &out, threads[t], frames, &st);
            double covered = (double)(st.pixels - st.background) / (double)st.pixels;
            printf("%5d %7.1f%% %8d %10.1f", ns[i], 100.0 * covered, threads[t], ms);
            if (st.samples > 0)
                printf(" %14.2f", ms * 1e6 * threads[t] / (double)st.samples);
            printf("\n");
        }
    }
    free(u);
    sl_image_free(&out);
    sl_image_free(&img);
    sl_gbuffer_free(&gb);
    sl_gbuffer_free(&gbs[1]);
    sl_irradiance_free(&irr);
    sl_env_dist_free(&dist);
    sl_env_free(&env);
    return 0;
}
