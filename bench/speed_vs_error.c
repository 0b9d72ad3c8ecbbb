/* speed_vs_error.c - speed against error of the lighting stage's variants on the shipped scenes:
 * the variants, the ground truth, the renders and the timings; sweep_report.c turns the
 * results into the CSV, the plot data and docs/accuracy.md. bench/speed-vs-error.sh runs it and
 * then gnuplot (bench/gnuplot/) for the plots the report shows.
 *
 *   bench_speed_vs_error [--size WxH] [--frames F] [--anchor-frames F] [--out DIR] [--cache DIR]
 *                        [--doc FILE|none] [--gl PATH|none] [--scenes a,b,...] [--threads T]
 *                        [--truth DIR] [--truth-jobs]
 *
 * --truth DIR reads each scene's ground truth from DIR/NAME-WxH (`softlight truth --parts`, e.g.
 * merged from sharded runs: bench/speed-vs-error.sh --shards N, docs/sharding.md) instead of
 * integrating it; --truth-jobs prints what to run for that (NAME SCENE W H per line) and exits.
 *
 * Per scene: the G-buffer is rasterized once at the error size (default 192x108; a scene of
 * another aspect gets the same pixel count), its ground truth (src/shading/ground_truth_image.h:
 * every texel of the environment, double precision, both G terms) is read from the cache or
 * computed with progress on stderr, and every variant is
 *   - rendered specular-only and diffuse-only (the shader adds the two; total = their sum) and
 *     compared with the ground truth of the SAME G term, over the covered pixels;
 *   - timed as whole frames (raster + lighting + tone map, point lights off, as measured) at
 *     the error size: medians of --frames interleaved rounds (one frame of every variant per
 *     round, after a warm-up round), wall time and the lighting stage's CPU time; the speed
 *     axis is that CPU time, which the shared machine's load disturbs far less than wall time.
 *     Progressive variants (K accumulated rotated frames) cost K frames. The variants marked as
 *     anchors are also timed at the scene's own size (1280x720; top-down 1024x1024).
 * Errors: sl_compare_images (src/post/compare.h) in linear radiance (RMSE, mean and 99th
 * percentile relative error) and after the scene's tone map (share of pixels more than 1/255
 * and 8/255 off), plus nRMSE = RMSE / RMS of the ground truth, the headline figure: it puts
 * scenes of very different brightness (the city's sun) on one scale. Set figures are means over
 * the scenes, each scene weighing the same.
 *
 * Two sets of scenes: the five Phong scenes, whose means are the headline figures, and the GGX
 * scene (scenes/ggx.json, `"brdf": "ggx"`), run through the same variants and reported beside
 * them ("GGX beside Phong" in the report, "all-ggx" rows in the CSV); its ground truth costs
 * about three times a Phong pixel's (GGX's D and Smith visibility at every texel).
 *
 * The "mf" variants are the shader's microfacet estimator (options.estimator =
 * SL_ESTIMATOR_MICROFACET, `--estimator mf`: H drawn from D(H) (N.H), w = reflect(-V, H), weight
 * by the exact density p(w) = D (N.H) / (4 V.H); docs/lighting.md). The "pdf" mip rule
 * (SL_LOD_PDF, `--lod pdf`: GPU Gems 3's level without its +1) is swept beside "gems" to measure
 * what that +1 costs or buys. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "core/timer.h"
#include "ibl/env_lights.h"
#include "post/compare.h"
#include "render/renderer.h"
#include "shading/brdf.h"
#include "shading/ground_truth_image.h"
#include "sweep_report.h"

#define MAX_FRAMES 64

/* ------------------------------------------------------------------ variants */

typedef struct {
    const char *name, *path;
    bool ggx; /* the GGX set, reported beside the Phong set (sweep_report.h) */
} scene_entry;

/* The Phong scenes, then the GGX ones: the report takes the GGX scenes last. */
static const scene_entry all_scenes[] = {
    {"default", "scenes/default.json", false}, {"bunny", "scenes/bunny.json", false},
    {"city-sun", "scenes/city-sun.json", false}, {"grazing", "scenes/grazing.json", false},
    {"top-down", "scenes/top-down.json", false}, {"ggx", "scenes/ggx.json", true},
};

static const int sweep_n[] = {1, 2, 4, 8, 16, 20, 32, 40, 64, 128, 256};
#define SWEEP_COUNT ((int)(sizeof sweep_n / sizeof sweep_n[0]))

static void variant_name(variant *v)
{
    char acc[16] = "";
    if (v->accumulate > 1)
        snprintf(acc, sizeof acc, " x%d", v->accumulate);
    char el[16] = "";
    if (v->opt.env_lights > 0)
        snprintf(el, sizeof el, "+env%d", v->opt.env_lights);
    snprintf(v->name, sizeof v->name, "%s%s %s%s%s%s%s%s%s%s N%d%s", v->kind == KIND_GL ? "GL " : "", est_name(v),
             lod_name(v), v->opt.distortion ? "+dist" : "", el, v->opt.gterm == SL_GTERM_ONE ? " G=1" : "",
             v->irr != sl_irradiance_default() ? " " : "", v->irr != sl_irradiance_default() ? irr_name(v->irr) : "",
             v->opt.rotate ? " rot" : "", v->opt.plain ? " plain" : "", v->opt.samples, acc);
}

/* Every irradiance method the sweep measures; the diffuse images and the timing groups follow
 * this order. */
enum { IRRADIANCE_METHODS = 5 };
static const sl_irradiance_method methods[IRRADIANCE_METHODS] = {SL_IRRADIANCE_OCT, SL_IRRADIANCE_DP, SL_IRRADIANCE_SH9,
                                                                 SL_IRRADIANCE_BRUTE, SL_IRRADIANCE_MAP};

/* flags for add_variant */
enum { ROTATE = 1, PLAIN = 2 };

static int add_variant_ex(variant_list *l, variant_kind kind, sl_estimator est, sl_lod_rule lod, bool dist, sl_gterm g,
                          sl_irradiance_method irr, int n, const char *series, bool anchor, int flags, int accumulate,
                          int env_lights)
{
    variant v = {.kind = kind, .irr = irr, .anchor = anchor, .accumulate = accumulate};
    v.opt = (sl_lighting_options){.samples = n, .lod_rule = lod, .distortion = dist, .gterm = g, .estimator = est,
                                  .rotate = (flags & ROTATE) != 0, .plain = (flags & PLAIN) != 0,
                                  .env_lights = env_lights};
    snprintf(v.series, sizeof v.series, "%s", series ? series : "");
    variant_name(&v);
    for (int i = 0; i < l->count; i++)
        if (!strcmp(l->v[i].name, v.name)) {
            l->v[i].anchor |= anchor;
            if (series && !l->v[i].series[0])
                snprintf(l->v[i].series, sizeof l->v[i].series, "%s", series);
            return i;
        }
    if (l->count == MAX_VARIANTS) {
        fprintf(stderr, "bench_speed_vs_error: more than %d variants (raise MAX_VARIANTS)\n", MAX_VARIANTS);
        exit(2);
    }
    l->v[l->count] = v;
    return l->count++;
}

static int add_variant(variant_list *l, variant_kind kind, sl_estimator est, sl_lod_rule lod, bool dist, sl_gterm g,
                       sl_irradiance_method irr, int n, const char *series, bool anchor)
{
    return add_variant_ex(l, kind, est, lod, dist, g, irr, n, series, anchor, 0, 1, 0);
}

/* The design: N swept for the main combinations, every other axis at N = 40 (docs/accuracy.md). */
static void build_variants(variant_list *l, bool with_gl)
{
    const sl_gterm G = SL_GTERM_INV_LH2;
    const sl_irradiance_method SH = sl_irradiance_default(); /* every variant but the irradiance rows */
    struct {
        variant_kind kind;
        sl_estimator est;
        sl_lod_rule lod;
        bool dist;
        const char *series;
        int env_lights;
    } sweeps[] = {
        {KIND_SHADER, SL_ESTIMATOR_SPEC, SL_LOD_SPEC_D4, false, "spec, spec-d4 (the recipe)", 0},
        {KIND_SHADER, SL_ESTIMATOR_CONSISTENT, SL_LOD_SPEC_D4, false, "consistent, spec-d4", 0},
        {KIND_SHADER, SL_ESTIMATOR_CONSISTENT, SL_LOD_SPEC_D4, true, "consistent, spec-d4+dist", 0},
        {KIND_SHADER, SL_ESTIMATOR_CONSISTENT, SL_LOD_GEMS, true, "consistent, gems+dist", 0},
        {KIND_SHADER, SL_ESTIMATOR_MICROFACET, SL_LOD_SPEC_D4, false, "mf, spec-d4 (--estimator mf)", 0},
        {KIND_SHADER, SL_ESTIMATOR_MICROFACET, SL_LOD_SPEC, true, "mf, spec+dist", 0},
        {KIND_SHADER, SL_ESTIMATOR_MICROFACET, SL_LOD_GEMS, true, "mf, gems+dist", 0},
        {KIND_SHADER, SL_ESTIMATOR_MICROFACET, SL_LOD_PDF, true, "mf, pdf+dist", 0},
        {KIND_SHADER, SL_ESTIMATOR_MICROFACET, SL_LOD_PDF, true, "mf, pdf+dist+env32 (env lights)", 32},
        {KIND_SHADER, SL_ESTIMATOR_CONSISTENT, SL_LOD_GEMS, true, "consistent, gems+dist+env32", 32},
        {KIND_SHADER, SL_ESTIMATOR_SPEC, SL_LOD_SPEC_D4, false, "spec, spec-d4+env32", 32},
        /* MIS reads level 0 unfiltered: the lod rule does not apply (docs/lighting.md "MIS") */
        {KIND_SHADER, SL_ESTIMATOR_MIS, SL_LOD_NONE, false, "mis (BRDF and environment sampling)", 0},
    };
    for (size_t s = 0; s < sizeof sweeps / sizeof sweeps[0]; s++)
        for (int i = 0; i < SWEEP_COUNT; i++)
            add_variant_ex(l, sweeps[s].kind, sweeps[s].est, sweeps[s].lod, sweeps[s].dist, G, SH, sweep_n[i],
                           sweeps[s].series,
                           sweep_n[i] == 40 || (sweeps[s].est == SL_ESTIMATOR_MICROFACET && sweep_n[i] == 16), 0, 1,
                           sweeps[s].env_lights);
    /* the number of env lights K, for the microfacet estimator at N = 16 and 32 */
    const int env_k[] = {4, 8, 16, 32, 64};
    for (int i = 0; i < 5; i++)
        for (int n = 16; n <= 32; n += 16)
            add_variant_ex(l, KIND_SHADER, SL_ESTIMATOR_MICROFACET, SL_LOD_PDF, true, G, SH, n, NULL, false, 0, 1,
                           env_k[i]);
    /* mip rule x distortion x estimator at N = 40 */
    for (int e = SL_ESTIMATOR_SPEC; e <= SL_ESTIMATOR_MICROFACET; e++)
        for (int lod = SL_LOD_NONE; lod <= SL_LOD_PDF; lod++)
            for (int d = 0; d < 2; d++)
                add_variant(l, KIND_SHADER, (sl_estimator)e, (sl_lod_rule)lod, d, G, SH, 40, NULL, false);
    /* G term (the ground truth uses the same G) */
    add_variant(l, KIND_SHADER, SL_ESTIMATOR_SPEC, SL_LOD_SPEC_D4, false, SL_GTERM_ONE, SH, 40, NULL, false);
    add_variant(l, KIND_SHADER, SL_ESTIMATOR_CONSISTENT, SL_LOD_SPEC_D4, true, SL_GTERM_ONE, SH, 40, NULL, false);
    add_variant(l, KIND_SHADER, SL_ESTIMATOR_MICROFACET, SL_LOD_GEMS, true, SL_GTERM_ONE, SH, 40, NULL, false);
    /* irradiance */
    add_variant(l, KIND_SHADER, SL_ESTIMATOR_SPEC, SL_LOD_SPEC_D4, false, G, SL_IRRADIANCE_DP, 40, NULL, false);
    add_variant(l, KIND_SHADER, SL_ESTIMATOR_SPEC, SL_LOD_SPEC_D4, false, G, SL_IRRADIANCE_SH9, 40, NULL, false);
    add_variant(l, KIND_SHADER, SL_ESTIMATOR_SPEC, SL_LOD_SPEC_D4, false, G, SL_IRRADIANCE_BRUTE, 40, NULL, false);
    add_variant(l, KIND_SHADER, SL_ESTIMATOR_SPEC, SL_LOD_SPEC_D4, false, G, SL_IRRADIANCE_MAP, 40, NULL, false);
    /* the split-sum method (--estimator splitsum): no samples, so N and the lod rule do not apply */
    add_variant(l, KIND_SHADER, SL_ESTIMATOR_SPLITSUM, SL_LOD_SPEC_D4, false, G, SH, 40, NULL, false);
    add_variant(l, KIND_SHADER, SL_ESTIMATOR_SPLITSUM, SL_LOD_SPEC_D4, false, SL_GTERM_ONE, SH, 40, NULL, false);
    /* the line-by-line port (options.plain) beside the default batched path (its fast log2/atan2) */
    add_variant_ex(l, KIND_SHADER, SL_ESTIMATOR_SPEC, SL_LOD_SPEC_D4, false, G, SH, 40, NULL, false, PLAIN, 1, 0);
    add_variant_ex(l, KIND_SHADER, SL_ESTIMATOR_CONSISTENT, SL_LOD_SPEC, true, G, SH, 40, NULL, false, PLAIN, 1, 0);
    add_variant_ex(l, KIND_SHADER, SL_ESTIMATOR_MICROFACET, SL_LOD_GEMS, true, G, SH, 40, NULL, false, PLAIN, 1, 0);
    /* per-pixel Cranley-Patterson rotation, one frame and accumulated over K frames */
    const int ks[] = {1, 2, 4, 8, 16, 32};
    for (int i = 0; i < 6; i++) {
        add_variant_ex(l, KIND_SHADER, SL_ESTIMATOR_SPEC, SL_LOD_SPEC_D4, false, G, SH, 40,
                       "spec, spec-d4, rotate, N40 x K frames", false, ROTATE, ks[i], 0);
        add_variant_ex(l, KIND_SHADER, SL_ESTIMATOR_CONSISTENT, SL_LOD_SPEC, true, G, SH, 40,
                       "consistent, spec+dist, rotate, N40 x K frames", false, ROTATE, ks[i], 0);
        add_variant_ex(l, KIND_SHADER, SL_ESTIMATOR_CONSISTENT, SL_LOD_SPEC, true, G, SH, 8,
                       "consistent, spec+dist, rotate, N8 x K frames", false, ROTATE, ks[i], 0);
        add_variant_ex(l, KIND_SHADER, SL_ESTIMATOR_MICROFACET, SL_LOD_GEMS, true, G, SH, 8,
                       "mf, gems+dist, rotate, N8 x K frames", false, ROTATE, ks[i], 0);
    }
    if (with_gl) {
        add_variant(l, KIND_GL, SL_ESTIMATOR_SPEC, SL_LOD_SPEC_D4, false, G, SH, 40, NULL, true);
        add_variant(l, KIND_GL, SL_ESTIMATOR_CONSISTENT, SL_LOD_GEMS, true, G, SH, 40, NULL, true);
        add_variant(l, KIND_GL, SL_ESTIMATOR_MICROFACET, SL_LOD_GEMS, true, G, SH, 40, NULL, true);
        add_variant(l, KIND_GL, SL_ESTIMATOR_MICROFACET, SL_LOD_PDF, true, G, SH, 40, NULL, true);
        add_variant_ex(l, KIND_GL, SL_ESTIMATOR_MICROFACET, SL_LOD_PDF, true, G, SH, 40, NULL, true, 0, 1, 32);
    }
}

/* ------------------------------------------------------------------ helpers */

static void die(const char *what, const sl_error *err)
{
    fprintf(stderr, "bench_speed_vs_error: %s: %s\n", what, err ? err->msg : strerror(errno));
    exit(2);
}

static void make_dir(const char *path)
{
    char tmp[PATH_LEN];
    snprintf(tmp, sizeof tmp, "%s", path);
    for (char *p = tmp + 1; *p; p++)
        if (*p == '/') {
            *p = '\0';
            mkdir(tmp, 0777);
            *p = '/';
        }
    if (mkdir(tmp, 0777) != 0 && errno != EEXIST)
        die(path, NULL);
}

static double loadavg(void)
{
    double l = -1.0;
    FILE *f = fopen("/proc/loadavg", "r");
    if (f) {
        if (fscanf(f, "%lf", &l) != 1)
            l = -1.0;
        fclose(f);
    }
    return l;
}

typedef struct {
    const char *scene;
    double t0, last;
} progress_state;

/* Percentage and ETA on stderr, at most twice a second. */
static void on_progress(void *user, long done, long total)
{
    progress_state *p = user;
    double now = sl_now_seconds();
    if (done < total && now - p->last < 0.5)
        return;
    p->last = now;
    double el = now - p->t0, eta = done > 0 ? el * (double)(total - done) / (double)done : 0.0;
    fprintf(stderr, "\r  ground truth %-9s %5.1f%% (%ld/%ld px)  elapsed %3.0fs  ETA %3.0fs ", p->scene,
            total ? 100.0 * (double)done / (double)total : 100.0, done, total, el, eta);
    if (done == total)
        fputc('\n', stderr);
}

static void image_copy(sl_image *dst, const sl_image *src)
{
    sl_error err;
    if (!dst->data && !sl_image_alloc(dst, src->width, src->height, src->channels, &err))
        die("image", &err);
    memcpy(dst->data, src->data, (size_t)src->width * src->height * src->channels * sizeof(float));
}

static void image_sum(sl_image *dst, const sl_image *a, const sl_image *b)
{
    sl_error err;
    if (!dst->data && !sl_image_alloc(dst, a->width, a->height, 3, &err))
        die("image", &err);
    size_t n = (size_t)a->width * a->height * 3;
    for (size_t i = 0; i < n; i++)
        dst->data[i] = a->data[i] + b->data[i];
}

static errors measure(const sl_image *img, const sl_image *truth, const sl_image *mask, const sl_tonemap_options *tm)
{
    sl_compare_stats s;
    sl_error err;
    sl_compare_desc d = {.exposure = tm->exposure, .contrast = tm->contrast, .mask = mask};
    if (!sl_compare_images(img, truth, &d, &s, &err))
        die("compare", &err);
    return (errors){.nrmse = s.nrmse, .rmse = s.rmse, .mean_rel = s.mean_rel,
                    .p99_rel = s.p99_rel, .over1 = s.share_over_1, .over8 = s.share_over_8};
}

/* ------------------------------------------------------------------ one scene */

static void set_options(sl_renderer *r, const variant *v, bool diffuse, bool specular)
{
    sl_lighting_options o = v->opt;
    o.irradiance = r->desc.lighting.irradiance;
    o.no_point_lights = true;
    o.no_diffuse = !diffuse;
    o.no_specular = !specular;
    o.env_intensity = r->desc.lighting.env_intensity;
    o.env_rotation_deg = r->desc.lighting.env_rotation_deg;
    r->desc.lighting = o;
}

static void use_irradiance(sl_renderer *r, sl_irradiance_method m)
{
    sl_error err;
    if (r->have_irradiance && r->desc.lighting.irradiance == m)
        return;
    if (!sl_renderer_set_irradiance(r, m, &err))
        die("irradiance", &err);
}

/* Lighting only (the G-buffer stays), into r->radiance. */
static void shade(sl_renderer *r, const variant *v, bool diffuse, bool specular)
{
    sl_error err;
    set_options(r, v, diffuse, specular);
    if (!sl_renderer_shade(r, NULL, &err))
        die("shade", &err);
}

/* CPU time of the whole process (all threads): what a pass costs, whoever else shares the cores. */
static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* One whole frame: raster + lighting + tone map. Milliseconds of the frame (wall), of the
 * lighting stage (wall) and of the lighting stage's CPU time summed over threads. */
static void time_frame(sl_renderer *r, const variant *v, double *frame, double *lighting, double *cpu)
{
    sl_error err;
    set_options(r, v, true, true);
    /* the env lights' extraction is per environment (like the irradiance), not per frame */
    if (!sl_renderer_prepare_lighting(r, NULL, &err))
        die("env lights", &err);
    double t0 = sl_now_seconds();
    if (!sl_renderer_raster(r, NULL, &err))
        die("raster", &err);
    double t1 = sl_now_seconds(), c1 = cpu_seconds();
    if (!sl_renderer_shade(r, NULL, &err))
        die("shade", &err);
    double t2 = sl_now_seconds(), c2 = cpu_seconds();
    if (!sl_renderer_tonemap(r, &err))
        die("tonemap", &err);
    double t3 = sl_now_seconds();
    *frame = (t3 - t0) * 1e3;
    *lighting = (t2 - t1) * 1e3;
    *cpu = (c2 - c1) * 1e3;
}

/* Time the selected variants in interleaved rounds (one frame of each per round, a warm-up
 * round first), so that a change in the machine's load falls on all of them alike; medians.
 * Variants are grouped by irradiance method so the irradiance is built once per group. */
static void time_variants(sl_renderer *r, const variant_list *vl, const bool *selected, int frames, result *res,
                          bool anchor)
{
    static double tf[MAX_VARIANTS][MAX_FRAMES], tl[MAX_VARIANTS][MAX_FRAMES], tc[MAX_VARIANTS][MAX_FRAMES];
    for (int m = 0; m < IRRADIANCE_METHODS; m++) {
        bool any = false;
        for (int i = 0; i < vl->count; i++)
            any |= selected[i] && vl->v[i].irr == methods[m];
        if (!any)
            continue;
        use_irradiance(r, methods[m]);
        for (int f = -1; f < frames; f++)
            for (int i = 0; i < vl->count; i++) {
                if (!selected[i] || vl->v[i].irr != methods[m])
                    continue;
                double a, b, c;
                time_frame(r, &vl->v[i], &a, &b, &c);
                if (f >= 0) {
                    tf[i][f] = a;
                    tl[i][f] = b;
                    tc[i][f] = c;
                }
            }
        for (int i = 0; i < vl->count; i++) {
            if (!selected[i] || vl->v[i].irr != methods[m])
                continue;
            double k = vl->v[i].accumulate > 1 ? vl->v[i].accumulate : 1; /* K frames to get there */
            if (anchor) {
                res[i].anchor_ms = sl_median(tf[i], frames);
                res[i].anchor_lighting_ms = sl_median(tl[i], frames);
            } else {
                res[i].frame_ms = k * sl_median(tf[i], frames);
                res[i].lighting_ms = k * sl_median(tl[i], frames);
                res[i].cpu_ms = k * sl_median(tc[i], frames);
            }
        }
    }
}

static void gl_options(const variant *v, char *buf, size_t n)
{
    snprintf(buf, n, "-n %d --lod %s%s --g %s --estimator %s --env-lights %d", v->opt.samples,
             sl_lod_rule_name(v->opt.lod_rule), v->opt.distortion ? " --distortion" : "", sl_gterm_name(v->opt.gterm),
             sl_estimator_name(v->opt.estimator), v->opt.env_lights);
}

/* softlight-gl: lighting of our G-buffer (AOV files) for the error, whole frames for the time. */
static bool run_gl(const config *c, const scene_entry *s, const scene_info *si, const variant *v, const char *aov_dir,
                   sl_image *diffuse, sl_image *specular, result *res)
{
    char opts[256], cmd[4 * PATH_LEN], pfm[2][PATH_LEN];
    gl_options(v, opts, sizeof opts);
    for (int part = 0; part < 2; part++) {
        snprintf(pfm[part], sizeof pfm[part], "%s/gl-%s-%s.pfm", c->out_dir, s->name, part ? "specular" : "diffuse");
        snprintf(cmd, sizeof cmd, "'%s' render '%s' --gbuffer '%s' --size %dx%d %s %s --pfm '%s' >/dev/null", c->gl,
                 s->path, aov_dir, si->w, si->h, opts, part ? "--specular-only" : "--diffuse-only", pfm[part]);
        if (system(cmd) != 0) {
            fprintf(stderr, "  softlight-gl failed: %s\n", cmd);
            return false;
        }
    }
    sl_error err;
    sl_image_free(diffuse);
    sl_image_free(specular);
    if (!sl_image_read_pfm(pfm[0], 0, diffuse, NULL, &err) || !sl_image_read_pfm(pfm[1], 0, specular, NULL, &err))
        die("GL output", &err);
    for (int a = 0; a < (c->anchor_frames > 0 ? 2 : 1); a++) {
        int w = a ? si->anchor_w : si->w, h = a ? si->anchor_h : si->h, runs = a ? c->anchor_frames : c->frames;
        snprintf(cmd, sizeof cmd, "'%s' render '%s' --size %dx%d %s --no-lights --time %d", c->gl, s->path, w, h, opts,
                 runs);
        FILE *p = popen(cmd, "r");
        char line[512];
        double g = -1, l = -1;
        while (p && fgets(line, sizeof line, p)) {
            const char *t = strstr(line, "gbuffer ");
            const char *q = strstr(line, "lighting ");
            if (!strncmp(line, "time:", 5) && t && q) {
                g = atof(t + 8);
                l = atof(q + 9);
            }
        }
        if (!p || pclose(p) != 0 || g < 0) {
            fprintf(stderr, "  softlight-gl --time failed: %s\n", cmd);
            return false;
        }
        if (a) {
            res->anchor_ms = g + l;
            res->anchor_lighting_ms = l;
        } else {
            res->frame_ms = g + l;
            res->lighting_ms = l;
        }
    }
    return true;
}

/* The brute-force irradiance map as a Radiance file, for the `map` method (RGBE-rounded). */
static void write_irradiance_map(const sl_renderer *r, const char *path)
{
    const sl_env_level *l = &r->irradiance.map.levels[0];
    sl_image img;
    sl_error err;
    if (!sl_image_alloc(&img, l->width, l->height, 3, &err))
        die("map", &err);
    for (int i = 0; i < l->width * l->height; i++) {
        img.data[3 * i + 0] = l->texels[i].x;
        img.data[3 * i + 1] = l->texels[i].y;
        img.data[3 * i + 2] = l->texels[i].z;
    }
    if (!sl_image_write_hdr(path, &img, &err))
        die(path, &err);
    sl_image_free(&img);
}

/* The integration time recorded in a cache file's header ("seconds S"), or 0. */
static double cached_seconds(const char *path)
{
    double t = 0.0;
    char line[512];
    FILE *f = fopen(path, "rb");
    while (f && fgets(line, sizeof line, f) && strcmp(line, "data\n"))
        if (sscanf(line, "seconds %lf", &t) == 1)
            break;
    if (f)
        fclose(f);
    return t;
}

/* The error size of a scene: c's size for its aspect, else the same pixel count at the scene's. */
static void error_size(const config *c, const sl_scene *scene, int *w, int *h)
{
    double aspect = (double)scene->options.size[0] / scene->options.size[1], px = (double)c->width * c->height;
    *w = (int)lround(sqrt(px * aspect));
    *h = (int)lround(*w / aspect);
    if (fabs(aspect - (double)c->width / c->height) < 1e-3) {
        *w = c->width;
        *h = c->height;
    }
}

/* The ground truth of this run's G-buffer from DIR, written by `softlight truth SCENE --size WxH
 * --parts DIR` (or merged from its --shard runs): diffuse, both specular G terms and the mask as
 * PFMs (row 0 = top). Trusted only after two checks: the mask is this run's coverage, and 8
 * covered pixels spread over the image, integrated here again, equal the files' values bit for bit
 * (the truth of a pixel depends only on its texel and the frame's inputs: any difference in
 * environment, rotation, intensity, eye or G-buffer shows). */
static void read_truth_dir(const char *dir, const sl_gt_image_desc *gd, sl_gt_image *gt)
{
    sl_error err;
    static const char *const files[4] = {"diffuse", "specular-inv-lh2", "specular-one", "mask"};
    sl_image *planes[4] = {&gt->diffuse, &gt->specular[SL_GT_G_INV_LH2], &gt->specular[SL_GT_G_ONE], &gt->mask};
    const sl_gbuffer *gb = gd->gbuffer;
    *gt = (sl_gt_image){.width = gb->width, .height = gb->height, .from_cache = true};
    for (int i = 0; i < 4; i++) {
        char path[PATH_LEN + 32];
        snprintf(path, sizeof path, "%s/%s.pfm", dir, files[i]);
        if (!sl_image_read_pfm(path, 0, planes[i], NULL, &err))
            die("--truth", &err);
        if (planes[i]->width != gb->width || planes[i]->height != gb->height) {
            fprintf(stderr, "bench_speed_vs_error: %s is %dx%d, this run's G-buffer %dx%d\n", path, planes[i]->width,
                    planes[i]->height, gb->width, gb->height);
            exit(2);
        }
    }
    long covered = 0;
    for (int y = 0; y < gb->height; y++)
        for (int x = 0; x < gb->width; x++) {
            bool mine = sl_gbuffer_covered(sl_gbuffer_at(gb, x, gb->height - 1 - y));
            if (mine != (sl_image_pixel(&gt->mask, x, y)[0] > 0.5f)) {
                fprintf(stderr, "bench_speed_vs_error: %s/mask.pfm differs from this run's coverage at (%d, %d) "
                                "(row 0 = top): another scene, size or camera?\n", dir, x, y);
                exit(2);
            }
            covered += mine;
        }
    gt->covered = covered;
    /* the spot check: a G-buffer with only 8 of the covered texels, integrated without a cache */
    sl_gbuffer probe = {0};
    if (!sl_gbuffer_resize(&probe, gb->width, gb->height, &err))
        die("--truth", &err);
    sl_gbuffer_clear(&probe, 0);
    long step = covered / 8 > 0 ? covered / 8 : 1, k = 0;
    for (size_t i = 0; i < (size_t)gb->width * (size_t)gb->height; i++)
        if (sl_gbuffer_covered(&gb->texels[i]) && k++ % step == step / 2)
            probe.texels[i] = gb->texels[i];
    sl_gt_image_desc pd = *gd;
    pd.gbuffer = &probe;
    pd.cache_path = NULL;
    pd.progress = NULL;
    sl_gt_image again;
    if (!sl_gt_image_compute(&again, &pd, &err))
        die("--truth", &err);
    for (int y = 0; y < gb->height; y++)
        for (int x = 0; x < gb->width; x++) {
            if (!sl_gbuffer_covered(sl_gbuffer_at(&probe, x, gb->height - 1 - y)))
                continue;
            for (int i = 0; i < 3; i++) {
                const sl_image *mine = i == 0 ? &again.diffuse : &again.specular[i - 1];
                if (memcmp(sl_image_pixel(mine, x, y), sl_image_pixel(planes[i], x, y), 3 * sizeof(float)) != 0) {
                    fprintf(stderr, "bench_speed_vs_error: %s/%s.pfm at (%d, %d) is not this run's ground truth "
                                    "(integrated again here): another environment, rotation, intensity or eye?\n",
                            dir, files[i], x, y);
                    exit(2);
                }
            }
        }
    sl_gt_image_free(&again);
    sl_gbuffer_free(&probe);
}

static void run_scene(const config *c, const scene_entry *s, scene_info *si, const variant_list *vl,
                      result res[MAX_VARIANTS])
{
    sl_error err;
    sl_scene scene;
    if (!sl_scene_load(s->path, &scene, &err))
        die(s->path, &err);
    si->name = s->name;
    si->ggx = s->ggx;
    si->anchor_w = scene.options.size[0];
    si->anchor_h = scene.options.size[1];
    error_size(c, &scene, &si->w, &si->h);
    sl_render_desc desc = {0};
    sl_option_set_size(&desc.options, si->w, si->h);
    sl_option_set_threads(&desc.options, c->threads);
    sl_option_set_irradiance(&desc.options, sl_irradiance_default());
    sl_option_set_no_lights(&desc.options, true);
    sl_renderer r;
    if (!sl_renderer_init(&r, &scene, &desc, &err))
        die(s->path, &err);
    si->exposure = r.desc.tonemap.exposure;
    if (!sl_renderer_raster(&r, NULL, &err))
        die("raster", &err);
    /* the env lights' one-off cost per environment (not in any frame's time) */
    double te[3];
    for (int k = 0; k < 3; k++) {
        sl_env_lights el;
        double t0 = sl_now_seconds();
        if (!sl_env_lights_extract(&el, &r.env, 32, 0, &err))
            die("env lights", &err);
        te[k] = (sl_now_seconds() - t0) * 1e3;
        si->env_lights_count = el.count;
        si->env_lights_share = el.share;
        sl_env_lights_free(&el);
    }
    si->env_lights_ms = sl_median(te, 3);

    /* ground truth */
    char cache[PATH_LEN];
    snprintf(cache, sizeof cache, "%s/%s-%dx%d.gt", c->cache_dir, s->name, si->w, si->h);
    progress_state ps = {.scene = s->name, .t0 = sl_now_seconds()};
    sl_gt_image gt;
    sl_gt_image_desc gd = {.env = &r.env, .gbuffer = &r.gbuffer, .eye = scene.camera.eye,
                           .env_rotation_deg = r.desc.lighting.env_rotation_deg,
                           .env_intensity = r.desc.lighting.env_intensity, .threads = c->threads,
                           .cache_path = cache, .label = s->path, .progress = on_progress, .progress_user = &ps};
    if (c->truth_dir) {
        char dir[PATH_LEN];
        snprintf(dir, sizeof dir, "%s/%s-%dx%d", c->truth_dir, s->name, si->w, si->h);
        read_truth_dir(dir, &gd, &gt);
        si->gt_read = true;
    } else if (!sl_gt_image_compute(&gt, &gd, &err)) {
        die("ground truth", &err);
    }
    si->covered = gt.covered;
    si->gt_seconds = si->gt_read ? 0.0 : gt.from_cache ? cached_seconds(cache) : gt.seconds;
    si->gt_cached = gt.from_cache;
    sl_image gt_total[2] = {{0}, {0}};
    for (int g = 0; g < 2; g++)
        if (!sl_gt_image_total(&gt, (sl_gt_geometry)g, &gt_total[g], &err))
            die("ground truth", &err);

    /* diffuse once per irradiance method */
    char map_path[PATH_LEN];
    snprintf(map_path, sizeof map_path, "%s/irradiance-%s.hdr", c->out_dir, s->name);
    use_irradiance(&r, SL_IRRADIANCE_BRUTE);
    write_irradiance_map(&r, map_path);
    snprintf(scene.environment.irradiance_path, sizeof scene.environment.irradiance_path, "%s", map_path);
    sl_image diffuse[IRRADIANCE_METHODS] = {{0}}, spec = {0}, total = {0};
    for (int m = 0; m < IRRADIANCE_METHODS; m++) {
        use_irradiance(&r, methods[m]);
        variant dv = {.opt = {.samples = 1}};
        shade(&r, &dv, true, false);
        image_copy(&diffuse[m], &r.radiance);
    }
    const sl_tonemap_options *tm = &r.desc.tonemap;

    char aov_dir[PATH_LEN];
    snprintf(aov_dir, sizeof aov_dir, "%s/aov-%s", c->out_dir, s->name);
    bool aov_written = false;
    for (int i = 0; i < vl->count; i++) {
        const variant *v = &vl->v[i];
        result *rs = &res[i];
        int g = v->opt.gterm == SL_GTERM_ONE ? SL_GT_G_ONE : SL_GT_G_INV_LH2;
        int m = 0;
        while (m < IRRADIANCE_METHODS - 1 && methods[m] != v->irr)
            m++;
        const sl_image *dif = &diffuse[m];
        sl_image gl_dif = {0};
        if (v->kind == KIND_GL) {
            if (!aov_written) {
                make_dir(aov_dir);
                if (!sl_gbuffer_write_aovs(&r.gbuffer, scene.camera.eye, aov_dir, &err))
                    die("aov", &err);
                aov_written = true;
            }
            if (!run_gl(c, s, si, v, aov_dir, &gl_dif, &spec, rs))
                continue;
            dif = &gl_dif;
        } else {
            use_irradiance(&r, v->irr);
            if (v->accumulate > 1) { /* progressive: the mean of frames 0 .. K-1, rotation on */
                for (int k = 0; k < v->accumulate; k++) {
                    variant vk = *v;
                    vk.opt.frame = (uint32_t)k;
                    shade(&r, &vk, false, true);
                    if (!sl_lighting_accumulate(&spec, &r.radiance, k, &err))
                        die("accumulate", &err);
                }
            } else {
                shade(&r, v, false, true);
                image_copy(&spec, &r.radiance);
            }
        }
        image_sum(&total, dif, &spec);
        rs->e[PART_TOTAL] = measure(&total, &gt_total[g], &gt.mask, tm);
        rs->e[PART_DIFFUSE] = measure(dif, &gt.diffuse, &gt.mask, tm);
        rs->e[PART_SPECULAR] = measure(&spec, &gt.specular[g], &gt.mask, tm);
        rs->done = true;
        sl_image_free(&gl_dif);
    }
    /* timing at the error size, then the anchors at the scene's own size (the G-buffer changes) */
    bool selected[MAX_VARIANTS];
    for (int i = 0; i < vl->count; i++)
        selected[i] = vl->v[i].kind != KIND_GL && res[i].done;
    time_variants(&r, vl, selected, c->frames, res, false);
    if (c->anchor_frames > 0) {
        if (!sl_renderer_resize(&r, si->anchor_w, si->anchor_h, &err))
            die("resize", &err);
        for (int i = 0; i < vl->count; i++)
            selected[i] = selected[i] && vl->v[i].anchor;
        time_variants(&r, vl, selected, c->anchor_frames, res, true);
    }
    for (int m = 0; m < IRRADIANCE_METHODS; m++)
        sl_image_free(&diffuse[m]);
    sl_image_free(&spec);
    sl_image_free(&total);
    sl_image_free(&gt_total[0]);
    sl_image_free(&gt_total[1]);
    sl_gt_image_free(&gt);
    sl_renderer_free(&r);
    sl_scene_free(&scene);
}

/* ------------------------------------------------------------------ main */

/* --scenes is a comma list of names */
static bool scene_selected(const char *list, const char *name)
{
    size_t len = strlen(name);
    for (const char *p = strstr(list, name); p; p = strstr(p + 1, name))
        if ((p == list || p[-1] == ',') && (!p[len] || p[len] == ','))
            return true;
    return false;
}

static bool parse_size(const char *s, int *w, int *h) { return sscanf(s, "%dx%d", w, h) == 2 && *w > 0 && *h > 0; }

int main(int argc, char **argv)
{
    config c = {.width = 192, .height = 108, .frames = 5, .anchor_frames = 3, .out_dir = "out/speed-vs-error",
                .cache_dir = "out/ground-truth", .doc = "docs/accuracy.md", .gl = NULL};
    snprintf(c.scenes, sizeof c.scenes, "default,bunny,city-sun,grazing,top-down,ggx");
    static char gl_default[PATH_LEN];
    bool truth_jobs = false;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--size") && v && parse_size(v, &c.width, &c.height))
            i++;
        else if (!strcmp(a, "--frames") && v && (c.frames = atoi(v)) >= 1 && c.frames <= MAX_FRAMES)
            i++;
        else if (!strcmp(a, "--anchor-frames") && v && (c.anchor_frames = atoi(v)) >= 0 && c.anchor_frames <= MAX_FRAMES)
            i++;
        else if (!strcmp(a, "--threads") && v && (c.threads = atoi(v)) >= 1)
            i++;
        else if (!strcmp(a, "--out") && v)
            c.out_dir = argv[++i];
        else if (!strcmp(a, "--cache") && v)
            c.cache_dir = argv[++i];
        else if (!strcmp(a, "--doc") && v)
            c.doc = argv[++i];
        else if (!strcmp(a, "--gl") && v)
            c.gl = argv[++i];
        else if (!strcmp(a, "--scenes") && v)
            snprintf(c.scenes, sizeof c.scenes, "%s", argv[++i]);
        else if (!strcmp(a, "--truth") && v)
            c.truth_dir = argv[++i];
        else if (!strcmp(a, "--truth-jobs"))
            truth_jobs = true;
        else {
            fprintf(stderr,
                    "usage: bench_speed_vs_error [--size WxH] [--frames F] [--anchor-frames F] [--threads T]\n"
                    "       [--out DIR] [--cache DIR] [--doc FILE|none] [--gl PATH|none] [--scenes a,b,...]\n"
                    "       [--truth DIR] [--truth-jobs]\n"
                    "(run from the source root; bench/speed-vs-error.sh runs it and makes the plots)\n");
            return 2;
        }
    }
    if (truth_jobs) { /* what bench/speed-vs-error.sh --shards runs: one line per scene, NAME PATH W H */
        for (size_t k = 0; k < sizeof all_scenes / sizeof all_scenes[0]; k++) {
            if (!scene_selected(c.scenes, all_scenes[k].name))
                continue;
            sl_error err;
            sl_scene scene;
            if (!sl_scene_load(all_scenes[k].path, &scene, &err))
                die(all_scenes[k].path, &err);
            int w, h;
            error_size(&c, &scene, &w, &h);
            printf("%s %s %d %d\n", all_scenes[k].name, all_scenes[k].path, w, h);
            sl_scene_free(&scene);
        }
        return 0;
    }
    if (!c.gl) { /* softlight-gl beside this program, if it was built */
        snprintf(gl_default, sizeof gl_default, "%s", argv[0]);
        char *slash = strrchr(gl_default, '/');
        snprintf(slash ? slash + 1 : gl_default, sizeof gl_default - (size_t)(slash ? slash + 1 - gl_default : 0),
                 "softlight-gl");
        struct stat st;
        c.gl = stat(gl_default, &st) == 0 ? gl_default : "none";
    }
    bool with_gl = strcmp(c.gl, "none") != 0;
    if (with_gl) {
        char cmd[PATH_LEN + 32];
        snprintf(cmd, sizeof cmd, "'%s' info >/dev/null 2>&1", c.gl);
        if (system(cmd) != 0) {
            fprintf(stderr, "bench_speed_vs_error: %s info failed: no GL here, the GL rows are left out\n", c.gl);
            with_gl = false;
        }
    }
    make_dir(c.out_dir);
    make_dir(c.cache_dir);

    static variant_list vl;
    build_variants(&vl, with_gl);
    static result res[MAX_VARIANTS][MAX_SCENES];
    scene_info si[MAX_SCENES] = {{0}};
    int scenes = 0;
    double t0 = sl_now_seconds(), load0 = loadavg();
    fprintf(stderr, "speed vs error: %d variants, error size %dx%d, %d frames per timing, GL %s\n", vl.count, c.width,
            c.height, c.frames, with_gl ? c.gl : "off");
    for (size_t k = 0; k < sizeof all_scenes / sizeof all_scenes[0]; k++) {
        if (!scene_selected(c.scenes, all_scenes[k].name))
            continue;
        double ts = sl_now_seconds();
        fprintf(stderr, "scene %s\n", all_scenes[k].name);
        static result scene_res[MAX_VARIANTS];
        memset(scene_res, 0, sizeof scene_res);
        run_scene(&c, &all_scenes[k], &si[scenes], &vl, scene_res);
        for (int i = 0; i < vl.count; i++)
            res[i][scenes] = scene_res[i];
        fprintf(stderr, "  done in %.0f s\n", sl_now_seconds() - ts);
        scenes++;
    }
    if (!scenes) {
        fprintf(stderr, "bench_speed_vs_error: no scene matches --scenes %s\n", c.scenes);
        return 2;
    }
    sweep_write_report(&c, &vl, res, si, scenes, sl_now_seconds() - t0, load0, loadavg());
    return 0;
}
