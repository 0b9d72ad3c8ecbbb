/* speed_vs_error.c - speed against error of the lighting stage's variants on the shipped scenes
 * (issue 7): the data, the CSV and docs/accuracy.md. bench/speed-vs-error.sh runs it and then
 * gnuplot (bench/gnuplot/) for the plots the report shows.
 *
 *   bench_speed_vs_error [--size WxH] [--frames F] [--anchor-frames F] [--out DIR] [--cache DIR]
 *                        [--doc FILE|none] [--gl PATH|none] [--scenes a,b,...] [--threads T]
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
 * The "mf" variants are the shader's microfacet estimator (options.estimator =
 * SL_ESTIMATOR_MICROFACET, `--estimator mf`: H drawn from D(H) (N.H), w = reflect(-V, H), weight
 * by the exact density p(w) = D (N.H) / (4 V.H); docs/lighting.md). The "pdf" mip rule
 * (SL_LOD_PDF, `--lod pdf`: GPU Gems 3's level without its +1) is swept beside "gems" to measure
 * what that +1 costs or buys. */
#include <errno.h>
#include <math.h>
#include <omp.h>
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

#define MAX_VARIANTS 200
#define MAX_SCENES 8
#define MAX_FRAMES 64
#define PATH_LEN 1024

/* ------------------------------------------------------------------ variants */

typedef enum { KIND_SHADER, KIND_GL } variant_kind;
enum { PART_TOTAL, PART_DIFFUSE, PART_SPECULAR, PART_COUNT };
static const char *const part_names[PART_COUNT] = {"total", "diffuse", "specular"};

typedef struct {
    char name[64];
    char series[48];  /* the N-sweep line it belongs to; "" for the single-point axes */
    variant_kind kind;
    sl_lighting_options opt; /* samples, lod_rule, distortion, gterm, estimator */
    sl_irradiance_method irr;
    int accumulate;   /* > 1: frames 0 .. accumulate - 1 with rotation on, averaged (progressive) */
    bool anchor;      /* also timed at the scene's own size */
} variant;

typedef struct {
    double nrmse, rmse, mean_rel, p99_rel, over1, over8;
} errors;

typedef struct {
    bool done;
    double frame_ms, lighting_ms, cpu_ms; /* medians: whole frame, lighting (wall), lighting CPU time */
    double anchor_ms, anchor_lighting_ms;
    errors e[PART_COUNT];
} result;

typedef struct {
    const char *name, *path;
} scene_entry;

static const scene_entry all_scenes[] = {
    {"default", "scenes/default.json"}, {"bunny", "scenes/bunny.json"}, {"city-sun", "scenes/city-sun.json"},
    {"grazing", "scenes/grazing.json"}, {"top-down", "scenes/top-down.json"},
};

static const int sweep_n[] = {1, 2, 4, 8, 16, 20, 32, 40, 64, 128, 256};
#define SWEEP_COUNT ((int)(sizeof sweep_n / sizeof sweep_n[0]))

typedef struct {
    variant v[MAX_VARIANTS];
    int count;
} variant_list;

static const char *irr_name(sl_irradiance_method m)
{
    return m == SL_IRRADIANCE_BRUTE ? "brute" : m == SL_IRRADIANCE_MAP ? "map" : "sh9";
}

static const char *est_name(const variant *v) { return sl_estimator_name(v->opt.estimator); }
static const char *lod_name(const variant *v) { return sl_lod_rule_name(v->opt.lod_rule); }

static void variant_name(variant *v)
{
    char acc[16] = "";
    if (v->accumulate > 1)
        snprintf(acc, sizeof acc, " x%d", v->accumulate);
    char el[16] = "";
    if (v->opt.env_lights > 0)
        snprintf(el, sizeof el, "+env%d", v->opt.env_lights);
    snprintf(v->name, sizeof v->name, "%s%s %s%s%s%s%s%s%s N%d%s", v->kind == KIND_GL ? "GL " : "", est_name(v),
             lod_name(v), v->opt.distortion ? "+dist" : "", el, v->opt.gterm == SL_GTERM_ONE ? " G=1" : "",
             v->irr != SL_IRRADIANCE_SH9 ? (v->irr == SL_IRRADIANCE_BRUTE ? " brute" : " map") : "",
             v->opt.rotate ? " rot" : "", v->opt.plain ? " plain" : "", v->opt.samples, acc);
}

/* Variants the claim and the Pareto front weigh: one frame, the baseline's G term (G = 1 is a
 * different BRDF, measured against its own ground truth), softlight's CPU renderer. */
static bool comparable(const variant *v)
{
    return v->kind != KIND_GL && v->accumulate <= 1 && v->opt.gterm != SL_GTERM_ONE;
}

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
    const sl_irradiance_method SH = SL_IRRADIANCE_SH9;
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
    add_variant(l, KIND_SHADER, SL_ESTIMATOR_SPEC, SL_LOD_SPEC_D4, false, G, SL_IRRADIANCE_BRUTE, 40, NULL, false);
    add_variant(l, KIND_SHADER, SL_ESTIMATOR_SPEC, SL_LOD_SPEC_D4, false, G, SL_IRRADIANCE_MAP, 40, NULL, false);
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

typedef struct {
    int width, height;  /* error size for 16:9; others keep the pixel count */
    int frames, anchor_frames, threads;
    const char *out_dir, *cache_dir, *doc, *gl;
    char scenes[256];
} config;

typedef struct {
    const char *name;
    int w, h, anchor_w, anchor_h;
    long covered;
    double gt_seconds;
    bool gt_cached;
    double env_lights_ms;  /* extracting 32 env lights and the residual's mips (median of 3) */
    int env_lights_count;
    double env_lights_share; /* their share of the map's luminous power */
    float exposure;
} scene_info;

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
    const sl_irradiance_method methods[3] = {SL_IRRADIANCE_SH9, SL_IRRADIANCE_BRUTE, SL_IRRADIANCE_MAP};
    for (int m = 0; m < 3; m++) {
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
    if (!sl_image_read_pfm(pfm[0], diffuse, NULL, &err) || !sl_image_read_pfm(pfm[1], specular, NULL, &err))
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

static void run_scene(const config *c, const scene_entry *s, scene_info *si, const variant_list *vl,
                      result res[MAX_VARIANTS])
{
    sl_error err;
    sl_scene scene;
    if (!sl_scene_load(s->path, &scene, &err))
        die(s->path, &err);
    si->name = s->name;
    si->anchor_w = scene.settings.width;
    si->anchor_h = scene.settings.height;
    double aspect = (double)si->anchor_w / si->anchor_h, px = (double)c->width * c->height;
    si->w = (int)lround(sqrt(px * aspect));
    si->h = (int)lround(si->w / aspect);
    if (fabs(aspect - (double)c->width / c->height) < 1e-3) {
        si->w = c->width;
        si->h = c->height;
    }
    sl_render_desc desc = {.width = si->w, .height = si->h, .threads = c->threads, .irradiance_set = true};
    desc.lighting = (sl_lighting_options){.irradiance = SL_IRRADIANCE_SH9, .no_point_lights = true};
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
        if (!sl_env_lights_extract(&el, &r.env, 32, &err))
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
    if (!sl_gt_image_compute(&gt, &gd, &err))
        die("ground truth", &err);
    si->covered = gt.covered;
    si->gt_seconds = gt.from_cache ? cached_seconds(cache) : gt.seconds;
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
    sl_image diffuse[3] = {{0}, {0}, {0}}, spec = {0}, total = {0};
    const sl_irradiance_method methods[3] = {SL_IRRADIANCE_SH9, SL_IRRADIANCE_BRUTE, SL_IRRADIANCE_MAP};
    for (int m = 0; m < 3; m++) {
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
        int m = v->irr == SL_IRRADIANCE_BRUTE ? 1 : v->irr == SL_IRRADIANCE_MAP ? 2 : 0;
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
    for (int m = 0; m < 3; m++)
        sl_image_free(&diffuse[m]);
    sl_image_free(&spec);
    sl_image_free(&total);
    sl_image_free(&gt_total[0]);
    sl_image_free(&gt_total[1]);
    sl_gt_image_free(&gt);
    sl_renderer_free(&r);
    sl_scene_free(&scene);
}

/* ------------------------------------------------------------------ aggregation and output */

typedef struct {
    bool done;
    double frame_ms, lighting_ms, cpu_ms, anchor_ms;
    errors e[PART_COUNT];
} summary;

/* Mean over the scenes that ran (each scene weighs the same). */
static summary summarize(const result *r, int scenes)
{
    summary s = {0};
    int n = 0, na = 0;
    for (int k = 0; k < scenes; k++) {
        if (!r[k].done)
            continue;
        n++;
        s.frame_ms += r[k].frame_ms;
        s.lighting_ms += r[k].lighting_ms;
        s.cpu_ms += r[k].cpu_ms;
        if (r[k].anchor_ms > 0) {
            s.anchor_ms += r[k].anchor_ms;
            na++;
        }
        for (int p = 0; p < PART_COUNT; p++) {
            s.e[p].nrmse += r[k].e[p].nrmse;
            s.e[p].rmse += r[k].e[p].rmse;
            s.e[p].mean_rel += r[k].e[p].mean_rel;
            s.e[p].p99_rel += r[k].e[p].p99_rel;
            s.e[p].over1 += r[k].e[p].over1;
            s.e[p].over8 += r[k].e[p].over8;
        }
    }
    if (n != scenes)
        return s; /* incomplete: not summarized */
    s.done = true;
    s.frame_ms /= n;
    s.lighting_ms /= n;
    s.cpu_ms /= n;
    s.anchor_ms = na == n ? s.anchor_ms / n : 0.0;
    for (int p = 0; p < PART_COUNT; p++) {
        s.e[p].nrmse /= n;
        s.e[p].rmse /= n;
        s.e[p].mean_rel /= n;
        s.e[p].p99_rel /= n;
        s.e[p].over1 /= n;
        s.e[p].over8 /= n;
    }
    return s;
}

static void csv_row(FILE *f, const variant *v, const char *scene, int w, int h, double frame_ms, double lighting_ms,
                    double cpu_ms, double anchor_ms, const errors *e)
{
    fprintf(f, "%s,\"%s\",%s,%d,%s,%d,%s,%s,%s,%d,%d,%d,%d,\"%s\",%dx%d,%.4f,%.4f,%.4f,%.2f",
            v->kind == KIND_GL ? "gl" : "softlight", v->name, scene, v->opt.samples, lod_name(v), v->opt.distortion,
            sl_gterm_name(v->opt.gterm), est_name(v), irr_name(v->irr), v->opt.rotate, v->accumulate > 1 ? v->accumulate : 1,
            v->opt.plain, v->opt.env_lights, v->series, w, h, frame_ms, lighting_ms, cpu_ms, anchor_ms);
    for (int p = 0; p < PART_COUNT; p++)
        fprintf(f, ",%.5g,%.5g,%.5g,%.5g,%.5g,%.5g", e[p].nrmse, e[p].rmse, e[p].mean_rel, e[p].p99_rel, e[p].over1,
                e[p].over8);
    fputc('\n', f);
}

static FILE *open_out(const char *dir, const char *name, char *path)
{
    snprintf(path, PATH_LEN, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    if (!f)
        die(path, NULL);
    return f;
}

/* Pareto front on (frame ms, total nRMSE): no other variant is both faster and more accurate. */
static bool on_front(const variant_list *vl, const summary *s, int i, int count)
{
    for (int j = 0; j < count; j++)
        if (j != i && s[j].done && comparable(&vl->v[j]) && s[j].cpu_ms <= s[i].cpu_ms && s[j].e[0].nrmse <= s[i].e[0].nrmse &&
            (s[j].cpu_ms < s[i].cpu_ms || s[j].e[0].nrmse < s[i].e[0].nrmse))
            return false;
    return true;
}

static int find(const variant_list *vl, const char *name)
{
    for (int i = 0; i < vl->count; i++)
        if (!strcmp(vl->v[i].name, name))
            return i;
    return -1;
}

static void md_row(FILE *f, const variant *v, const summary *s, bool front)
{
    char full[32] = "-";
    if (s->anchor_ms > 0)
        snprintf(full, sizeof full, "%.1f", s->anchor_ms);
    fprintf(f, "| %s%s%s | %.2f | %.2f | %.2f | %s | %.4f | %.4f | %.3f | %.3f | %.1f%% | %.1f%% |\n",
            front ? "**" : "", v->name, front ? "**" : "", s->cpu_ms, s->lighting_ms, s->frame_ms, full, s->e[0].nrmse, s->e[2].nrmse,
            s->e[0].mean_rel, s->e[0].p99_rel, 100 * s->e[0].over1, 100 * s->e[0].over8);
}

static const char *TABLE_HEAD =
    "| variant | lighting CPU ms | lighting ms | frame ms | frame ms, full size | nRMSE total | nRMSE specular "
    "| mean rel | p99 rel | >1/255 | >8/255 |\n"
    "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";

static void write_outputs(const config *c, const variant_list *vl, result res[][MAX_SCENES], const scene_info *si,
                          int scenes, double run_seconds, double load0, double load1)
{
    char path[PATH_LEN];
    static summary sum[MAX_VARIANTS];
    for (int i = 0; i < vl->count; i++)
        sum[i] = summarize(res[i], scenes);

    /* CSV: every variant x scene, then the set ("all") */
    FILE *f = open_out(c->out_dir, "speed-vs-error.csv", path);
    fprintf(f, "renderer,variant,scene,N,lod,distortion,g,estimator,irradiance,rotate,frames,plain,env_lights,series,size,"
               "frame_ms,lighting_ms,lighting_cpu_ms,"
               "anchor_frame_ms");
    for (int p = 0; p < PART_COUNT; p++)
        fprintf(f, ",%s_nrmse,%s_rmse,%s_mean_rel,%s_p99_rel,%s_over1,%s_over8", part_names[p], part_names[p],
                part_names[p], part_names[p], part_names[p], part_names[p]);
    fputc('\n', f);
    for (int i = 0; i < vl->count; i++) {
        for (int k = 0; k < scenes; k++)
            if (res[i][k].done)
                csv_row(f, &vl->v[i], si[k].name, si[k].w, si[k].h, res[i][k].frame_ms, res[i][k].lighting_ms, res[i][k].cpu_ms,
                        res[i][k].anchor_ms, res[i][k].e);
        if (sum[i].done)
            csv_row(f, &vl->v[i], "all", c->width, c->height, sum[i].frame_ms, sum[i].lighting_ms, sum[i].cpu_ms, sum[i].anchor_ms,
                    sum[i].e);
    }
    fclose(f);
    fprintf(stderr, "wrote %s\n", path);

    /* gnuplot data: one file per N-sweep series, and the axes (GL's wall times are not plotted) */
    char series[16][48];
    int nseries = 0;
    for (int i = 0; i < vl->count; i++) {
        const char *s = vl->v[i].series;
        bool seen = !s[0];
        for (int j = 0; j < nseries && !seen; j++)
            seen = !strcmp(series[j], s);
        if (!seen && nseries < 16)
            snprintf(series[nseries++], sizeof series[0], "%s", s);
    }
    for (int j = 0; j < nseries; j++) {
        char name[64];
        snprintf(name, sizeof name, "series-%d.dat", j + 1);
        f = open_out(c->out_dir, name, path);
        fprintf(f, "\"N\" \"%s\" nrmse_total nrmse_specular mean_rel over8 p99_rel\n", series[j]);
        for (int i = 0; i < vl->count; i++)
            if (!strcmp(vl->v[i].series, series[j]) && sum[i].done)
                fprintf(f, "%d %.5f %.6g %.6g %.6g %.6g %.6g\n",
                        vl->v[i].opt.rotate ? vl->v[i].accumulate : vl->v[i].opt.samples, sum[i].cpu_ms,
                        sum[i].e[0].nrmse, sum[i].e[2].nrmse, sum[i].e[0].mean_rel, sum[i].e[0].over8,
                        sum[i].e[0].p99_rel);
        fclose(f);
    }
    f = open_out(c->out_dir, "axes.dat", path);
    fprintf(f, "# label ms nrmse_total nrmse_specular mean_rel over8 p99_rel (N = 40 axis variants)\n");
    for (int i = 0; i < vl->count; i++)
        if (!vl->v[i].series[0] && vl->v[i].kind != KIND_GL && sum[i].done)
            fprintf(f, "\"%s\" %.5f %.6g %.6g %.6g %.6g %.6g\n", vl->v[i].name, sum[i].cpu_ms, sum[i].e[0].nrmse,
                    sum[i].e[2].nrmse, sum[i].e[0].mean_rel, sum[i].e[0].over8, sum[i].e[0].p99_rel);
    fclose(f);
    f = open_out(c->out_dir, "series.gp", path);
    int first_progressive = nseries + 1;
    for (int j = nseries - 1; j >= 0; j--)
        if (strstr(series[j], "x K frames"))
            first_progressive = j + 1;
    fprintf(f, "nseries = %d\nfirst_progressive = %d\n", nseries, first_progressive);
    fclose(f);

    if (!c->doc || !strcmp(c->doc, "none"))
        return;
    /* ---------------- docs/accuracy.md ---------------- */
    f = fopen(c->doc, "w");
    if (!f)
        die(c->doc, NULL);
    int base = find(vl, "spec spec-d4 N40");
    time_t now = time(NULL);
    char date[32];
    strftime(date, sizeof date, "%Y-%m-%d", gmtime(&now));
    fprintf(f, "# Accuracy: speed against error\n\n"
               "Generated by `bench/speed-vs-error.sh` (bench/speed_vs_error.c) on %s; do not edit by hand,\n"
               "rerun it. Every figure per scene and variant: `accuracy/speed-vs-error.csv` (written to\n"
               "`%s/` and copied here by the script).\n\n",
            date, c->out_dir);
    fprintf(f, "## How it was measured\n\n"
               "* **Ground truth**: eq. (1) with the BRDF of eq. (2), integrated over every texel of the\n"
               "  environment's level 0 in double precision (`src/ibl/ground_truth.h`), per covered pixel of the\n"
               "  same G-buffer the variants shade, with the same N (bent towards the eye as the shader bends it),\n"
               "  V and alpha, and the **same G term as the variant**; image-based light only (point lights off in\n"
               "  both). Cached in `%s/` (`src/shading/ground_truth_image.h`); ",
            c->cache_dir);
    double gt_total = 0;
    bool all_cached = true;
    for (int k = 0; k < scenes; k++) {
        gt_total += si[k].gt_seconds;
        all_cached &= si[k].gt_cached;
    }
    fprintf(f, "computing it took %.0f s for the %d scenes (%s).\n", gt_total, scenes,
            all_cached ? "when the cache was made; this run read it" : "in this run");
    fprintf(f, "* **Error size**: %dx%d for the 16:9 scenes and the same pixel count for the others (", c->width,
            c->height);
    for (int k = 0; k < scenes; k++)
        fprintf(f, "%s%s %dx%d, %ld covered", k ? "; " : "", si[k].name, si[k].w, si[k].h, si[k].covered);
    fprintf(f, "). The ground truth costs about 5.6 ms per covered pixel and core, which is what bounds the\n"
               "  size: the whole first run fits in about a quarter of an hour on the 2-core build machine.\n"
               "* **Error**: over the covered pixels, in linear radiance: nRMSE (RMSE divided by the RMS of the\n"
               "  ground truth, the headline figure: it puts the city's sun and the studio on one scale), mean\n"
               "  and 99th-percentile per-pixel relative error (`src/post/compare.h`, floor 1e-3); after each\n"
               "  scene's tone map: the share of pixels more than 1/255 and 8/255 off. Diffuse and specular are\n"
               "  measured separately (the renderer runs diffuse-only and specular-only); total = their sum.\n"
               "  Set figures are means over the %d scenes, each scene weighing the same.\n"
               "* **Time**: whole frames (raster + lighting + tone map, point lights off) at the error size,\n"
               "  median of %d frames after a warm-up round, %d threads, `OMP_WAIT_POLICY=passive`, the variants\n"
               "  interleaved (one frame of each per round) so that a change of load falls on all alike.\n"
               "  **The speed axis is the lighting stage's CPU time per frame, summed over threads**\n"
               "  (`lighting CPU ms`): the lighting stage is the only one the variants change (at this size\n"
               "  the raster's geometry work would otherwise swamp them), and CPU time is what the work costs\n"
               "  whoever else is using the cores: wall times on this shared machine moved by 2-4x between runs\n"
               "  minutes apart (on an idle machine, wall time is about CPU time / 2). Wall times are in the\n"
               "  tables too (`lighting ms`, `frame ms`). Lighting cost is linear in pixels; the anchor variants\n"
               "  are also timed as whole frames at each scene's own size (1280x720, top-down 1024x1024, wall,\n"
               "  median of %d): the \"frame ms, full size\" column. The machine is a shared 2-core VM: load average %.1f at the\n"
               "  start and %.1f at the end of the run, so absolute times can be off by up to 2x between runs\n"
               "  (docs/performance.md); compare rows of one run. The whole run took %.0f s.\n\n",
            scenes, c->frames, c->threads > 0 ? c->threads : omp_get_max_threads(), c->anchor_frames, load0, load1,
            run_seconds);
    fprintf(f, "## Design of the sweep\n\n"
               "Not the full cross product. N = 1, 2, 4, 8, 16, 20, 32, 40, 64, 128, 256 for eight lines:\n\n"
               "1. `spec spec-d4` - the specification's recipe: eq. (3), the mip level with its note's D/4\n"
               "   (softlight's default); **N = 40 is the baseline** of the claim below;\n"
               "2. `consistent spec-d4` - the estimator weighted by D/p(w) (docs/lighting.md);\n"
               "3. `consistent spec-d4+dist` - plus the lat-long distortion factor in the mip level;\n"
               "4. `consistent gems+dist` - GPU Gems 3's filtered-importance-sampling level with the distortion;\n"
               "5. `mf spec-d4` - the microfacet estimator (`--estimator mf`, docs/lighting.md): H drawn from\n"
               "   D(H)(N.H), w = reflect(-V, H), weighted by the exact density p(w) = D (N.H) / (4 V.H), with\n"
               "   softlight's default mip rule (what `--estimator mf` alone gives);\n"
               "6. `mf spec+dist` - with the specification's formula on D(H): for this estimator D = 4 p(w) at\n"
               "   normal incidence, where it is 0.17 of a level finer than Gems'; away from it, it does not\n"
               "   follow p(w) (docs/lighting.md \"Mip level\");\n"
               "7. `mf gems+dist` - with GPU Gems 3's level for p(w);\n"
               "8. `mf pdf+dist` - the same level without Gems' +1 (`--lod pdf`): the footprint of p(w) itself,\n"
               "   one level finer;\n"
               "9. `mf pdf+dist+env32` - plus env lights (`--env-lights 32`, src/ibl/env_lights.h): the\n"
               "   environment's 32 brightest texels are summed exactly at their ground-truth nodes and the\n"
               "   samples read the rest, whose brightest texel is then the 33rd;\n"
               "10. `consistent gems+dist+env32` and 11. `spec spec-d4+env32` - the same split under the other\n"
               "   two estimators.\n\n"
               "The number of env lights K = 4, 8, 16, 32, 64 for `mf pdf+dist` at N = 16 and 32. Their\n"
               "extraction is per environment (like the irradiance), so no frame time includes it; its cost\n"
               "is in the \"Env lights\" section.\n\n"
               "At N = 40: every mip rule (none, spec, spec-d4, gems, pdf) with and without the distortion, for all three\n"
               "estimators; G = 1 (against a G = 1 ground truth); irradiance sh9 / brute (64x32 map from the\n"
               "quadrature) / map (that map written as .hdr and loaded back, so RGBE-rounded). softlight-gl\n"
               "(llvmpipe) runs the recipe, `consistent gems+dist`, `mf gems+dist`, `mf pdf+dist` and\n"
               "`mf pdf+dist+env32` at N = 40: error on\n"
               "softlight's G-buffer (`--gbuffer`), time of its own whole frames. The shader's only fast\n"
               "approximation is its default batched path (lighting_math.h's log2 and atan2 instead of libm's;\n"
               "docs/lighting.md): `plain` rows run the line-by-line port instead, for the recipe, `consistent\n"
               "spec+dist` and `mf gems+dist`. Per-pixel Cranley-Patterson rotation (`rot`, `options.rotate`):\n"
               "one frame, and progressive accumulation of K = 1..32 frames (`xK`, frame = 0..K-1,\n"
               "`sl_lighting_accumulate`) for the recipe at N = 40, `consistent spec+dist` at N = 40 and N = 8,\n"
               "and `mf gems+dist` at N = 8; their time is K frames.\n\n"
               "The claim, the Pareto front and the recommendations weigh only single frames with the baseline's\n"
               "G term (`1/(L.H)^2`): G = 1 is a different BRDF (measured against its own ground truth, it is\n"
               "an easier integrand, not a better estimate), and K accumulated frames cost K frames.\n\n");

    fprintf(f, "## Plots\n\n![total error against time](accuracy/speed-vs-error.png)\n\n"
               "![specular error against time](accuracy/specular-vs-time.png)\n\n"
               "![share of pixels off by more than 8/255](accuracy/over8-vs-time.png)\n\n");

    /* the claim */
    if (base >= 0 && sum[base].done) {
        const summary *b = &sum[base];
        int best = -1;
        for (int i = 0; i < vl->count; i++)
            if (sum[i].done && comparable(&vl->v[i]) && sum[i].cpu_ms <= 1.05 * b->cpu_ms &&
                (best < 0 || sum[i].e[0].nrmse < sum[best].e[0].nrmse))
                best = i;
        int best_old = -1, best_mf = -1; /* the shader before mf; before env lights */
        for (int i = 0; i < vl->count; i++) {
            if (!sum[i].done || !comparable(&vl->v[i]) || sum[i].cpu_ms > 1.05 * b->cpu_ms ||
                vl->v[i].opt.env_lights > 0)
                continue;
            if (vl->v[i].opt.estimator != SL_ESTIMATOR_MICROFACET &&
                (best_old < 0 || sum[i].e[0].nrmse < sum[best_old].e[0].nrmse))
                best_old = i;
            if (best_mf < 0 || sum[i].e[0].nrmse < sum[best_mf].e[0].nrmse)
                best_mf = i;
        }
        fprintf(f, "## The claim: 5 times lower error at the same cost\n\n"
                   "Baseline, the recipe at N = 40: lighting %.2f CPU ms/frame, nRMSE %.4f (specular %.4f), mean relative "
                   "error %.3f, %.1f%% of pixels more than 8/255 off.\n\n",
                b->cpu_ms, b->e[0].nrmse, b->e[2].nrmse, b->e[0].mean_rel, 100 * b->e[0].over8);
        const int cand[3] = {best_old, best_mf, best};
        const char *what[3] = {"with the spec and consistent estimators, no env lights (any mip rule, distortion, N)",
                               "with the mf estimator too, no env lights",
                               "with every option, env lights included"};
        for (int k = 0; k < 3; k++) {
            int i = cand[k];
            if (i < 0)
                continue;
            const summary *s = &sum[i];
            double ratio = s->e[0].nrmse > 0 ? b->e[0].nrmse / s->e[0].nrmse : INFINITY;
            fprintf(f, "* Best at no more than the baseline's lighting CPU time (+5%%) %s: **`%s`**, %.2f ms, nRMSE %.4f: "
                       "**%.2fx lower** (mean relative %.2fx, p99 relative %.2fx, >8/255 share %.2fx lower). "
                       "The claim (>= 5x) %s.\n",
                    what[k], vl->v[i].name, s->cpu_ms, s->e[0].nrmse, ratio,
                    s->e[0].mean_rel > 0 ? b->e[0].mean_rel / s->e[0].mean_rel : INFINITY,
                    s->e[0].p99_rel > 0 ? b->e[0].p99_rel / s->e[0].p99_rel : INFINITY,
                    s->e[0].over8 > 0 ? b->e[0].over8 / s->e[0].over8 : INFINITY,
                    ratio >= 5.0 ? "**holds** on this metric" : "**does not hold**");
            fprintf(f, "  Per scene (nRMSE, baseline -> this):");
            for (int q = 0; q < scenes; q++)
                fprintf(f, "%s %s %.4f -> %.4f (%.1fx)", q ? ";" : "", si[q].name, res[base][q].e[0].nrmse,
                        res[i][q].e[0].nrmse, res[base][q].e[0].nrmse / fmax(res[i][q].e[0].nrmse, 1e-12));
            fprintf(f, ".\n");
        }
        /* what more samples buy the recipe: its error floor */
        int b256 = find(vl, "spec spec-d4 N256"), c256 = find(vl, "consistent spec-d4+dist N256");
        const char *mf_lines[4] = {"mf spec-d4", "mf spec+dist", "mf gems+dist", "mf pdf+dist"};
        int m256 = -1;
        for (int k = 0; k < 4; k++) {
            char name[64];
            snprintf(name, sizeof name, "%s N256", mf_lines[k]);
            int i = find(vl, name);
            if (i >= 0 && sum[i].done && (m256 < 0 || sum[i].e[0].nrmse < sum[m256].e[0].nrmse))
                m256 = i;
        }
        fprintf(f, "\nWhy (figures from this run):\n\n");
        if (b256 >= 0 && sum[b256].done)
            fprintf(f, "* The recipe's estimator is biased (ERRATA): at N = 256 its nRMSE is still %.4f (%.4f at N = 40),\n"
                       "  specular %.4f. Sampling more does not remove the bias, so no N of the recipe gets close.\n",
                    sum[b256].e[0].nrmse, b->e[0].nrmse, sum[b256].e[2].nrmse);
        if (c256 >= 0 && sum[c256].done)
            fprintf(f, "* The consistent estimator removes most of the bias but converges slowly: `%s` reaches\n"
                       "  nRMSE %.4f at N = 256 (%.1fx the recipe's cost). Its weight D/p is unbounded (the sampled lobe\n"
                       "  is narrower than D seen from w) and it never draws the wedge w.R < 0 < w.N, which at low alpha\n"
                       "  is a fixed deficit (docs/lighting.md).\n",
                    vl->v[c256].name, sum[c256].e[0].nrmse, sum[c256].cpu_ms / b->cpu_ms);
        int mnone = find(vl, "mf none N40");
        if (m256 >= 0 && mnone >= 0 && sum[mnone].done)
            fprintf(f, "* The microfacet estimator draws H from D and weights by the exact density: its weight\n"
                       "  G' F (w.N)(V.H)/(N.H) is at most 2/(N.V) and every w above the horizon can be drawn, so it\n"
                       "  converges (tests/unit/test_shading.c, 48 cases, lod 0: RMS relative error 5e-3 at N = 256\n"
                       "  and 8e-4 at N = 1024, where the consistent estimator is at 9e-2 at N = 256). On the scenes\n"
                       "  `%s` reaches nRMSE %.4f at N = 256 (%.1fx the recipe's cost). What is left is set by the\n"
                       "  mip level: without filtering (`mf none N40`) the sun aliases (nRMSE %.4f, though mean\n"
                       "  relative %.3f), with it each sample reads a blur sized for N samples.\n",
                    vl->v[m256].name, sum[m256].e[0].nrmse, sum[m256].cpu_ms / b->cpu_ms, sum[mnone].e[0].nrmse,
                    sum[mnone].e[0].mean_rel);
        fprintf(f, "* Without env lights, nRMSE (which squares the error) is carried by the few pixels that\n"
                   "  reflect a sun or a lamp (radiance in the thousands against a sky near 1): in `top-down` two\n"
                   "  pixels of the mirror sphere, in `grazing` the sun's glint on the floor. Filtered importance\n"
                   "  sampling reads them through a blur sized for N samples, so the peak comes out low or smeared,\n"
                   "  and it steps up and down along N with whether a sample lands on it.\n");
        int e0 = find(vl, "mf pdf+dist N32"), e32 = find(vl, "mf pdf+dist+env32 N32");
        if (e0 >= 0 && e32 >= 0 && sum[e0].done && sum[e32].done) {
            fprintf(f, "* Env lights take exactly those texels out of the sampled map and sum them at the ground\n"
                       "  truth's own nodes, so that part is exact for any alpha, and the samples read a residual whose\n"
                       "  brightest texel is the 33rd: `mf pdf+dist N32` -> `+env32`: nRMSE %.4f -> %.4f, specular\n"
                       "  %.4f -> %.4f, mean relative %.3f -> %.3f, >8/255 %.1f%% -> %.1f%%, lighting %.2f -> %.2f CPU ms\n"
                       "  (32 BRDF evaluations per pixel, vectorized over the lights). Per scene (nRMSE):",
                    sum[e0].e[0].nrmse, sum[e32].e[0].nrmse, sum[e0].e[2].nrmse, sum[e32].e[2].nrmse,
                    sum[e0].e[0].mean_rel, sum[e32].e[0].mean_rel, 100 * sum[e0].e[0].over8, 100 * sum[e32].e[0].over8,
                    sum[e0].cpu_ms, sum[e32].cpu_ms);
            for (int q = 0; q < scenes; q++)
                fprintf(f, "%s %s %.4f -> %.4f", q ? ";" : "", si[q].name, res[e0][q].e[0].nrmse, res[e32][q].e[0].nrmse);
            fprintf(f, ".\n");
        }
        int irr_b = find(vl, "spec spec-d4 brute N40");
        fprintf(f, "* The diffuse term is the same in all of these (SH9, nRMSE %.4f alone): a floor under every\n"
                   "  total figure; the brute-force map is better (%.4f, see the irradiance rows).\n",
                b->e[1].nrmse, irr_b >= 0 && sum[irr_b].done ? sum[irr_b].e[1].nrmse : NAN);
        /* what the microfacet estimator costs: batched against the port, and against the recipe */
        int mp = find(vl, "mf gems+dist plain N40"), mb = find(vl, "mf gems+dist N40");
        int cp = find(vl, "consistent spec+dist plain N40"), cb = find(vl, "consistent spec+dist N40");
        if (mp >= 0 && mb >= 0 && cp >= 0 && cb >= 0 && sum[mp].done && sum[mb].done && sum[cp].done && sum[cb].done)
            fprintf(f, "* Cost: `mf gems+dist` at N = 40 takes %.2f lighting CPU ms batched and %.2f ms as the\n"
                       "  line-by-line port (%.2fx), against %.2f ms for the recipe and %.2f ms for `consistent\n"
                       "  spec+dist` (%.2f ms plain). The microfacet estimator needs no pow per sample (its D(H) comes\n"
                       "  with H from the per-alpha table) where the consistent one evaluates D(H) per sample.\n",
                    sum[mb].cpu_ms, sum[mp].cpu_ms, sum[mp].cpu_ms / sum[mb].cpu_ms, b->cpu_ms, sum[cb].cpu_ms,
                    sum[cp].cpu_ms);
        /* Gems' +1 measured: pdf against gems, same estimator and N (the rule costs the same) */
        static const int plus_n[] = {4, 16, 32, 40, 256};
        bool plus_any = false;
        for (int k = 0; k < 5; k++) {
            char ng[64], np[64];
            snprintf(ng, sizeof ng, "mf gems+dist N%d", plus_n[k]);
            snprintf(np, sizeof np, "mf pdf+dist N%d", plus_n[k]);
            int g = find(vl, ng), p = find(vl, np);
            if (g < 0 || p < 0 || !sum[g].done || !sum[p].done)
                continue;
            if (!plus_any)
                fprintf(f, "* The mip level is the other lever: GPU Gems 3 adds 1 to the level of the sample's footprint\n"
                           "  `1/2 log2(Omega_s/Omega_p)`, a deliberate over-blur (one level, 2x the filter radius) that\n"
                           "  hides the aliasing of a fixed sample set; `pdf` is the same level without it. `mf` with the\n"
                           "  distortion, nRMSE / mean relative / >8/255 share, gems -> pdf:");
            fprintf(f, "%s N = %d: %.4f -> %.4f, %.3f -> %.3f, %.1f%% -> %.1f%%", plus_any ? ";" : "", plus_n[k],
                    sum[g].e[0].nrmse, sum[p].e[0].nrmse, sum[g].e[0].mean_rel, sum[p].e[0].mean_rel,
                    100 * sum[g].e[0].over8, 100 * sum[p].e[0].over8);
            plus_any = true;
        }
        if (plus_any)
            fprintf(f, ".\n");
        const sl_estimator plus_est[2] = {SL_ESTIMATOR_SPEC, SL_ESTIMATOR_CONSISTENT};
        for (int k = 0; k < 2; k++) {
            char ng[64], np[64];
            snprintf(ng, sizeof ng, "%s gems+dist N40", sl_estimator_name(plus_est[k]));
            snprintf(np, sizeof np, "%s pdf+dist N40", sl_estimator_name(plus_est[k]));
            int g = find(vl, ng), p = find(vl, np);
            if (g >= 0 && p >= 0 && sum[g].done && sum[p].done)
                fprintf(f, "  With the %s estimator at N = 40 (p = the density of its drawn directions): nRMSE %.4f -> %.4f,\n"
                           "  mean relative %.3f -> %.3f.\n",
                        sl_estimator_name(plus_est[k]), sum[g].e[0].nrmse, sum[p].e[0].nrmse, sum[g].e[0].mean_rel,
                        sum[p].e[0].mean_rel);
        }
        fputc('\n', f);
    }

    /* Pareto front and recommended defaults */
    fprintf(f, "## Pareto front (set means: lighting CPU ms against total nRMSE)\n\n%s", TABLE_HEAD);
    int order[MAX_VARIANTS], n = 0;
    for (int i = 0; i < vl->count; i++)
        if (sum[i].done && comparable(&vl->v[i]) && on_front(vl, sum, i, vl->count))
            order[n++] = i;
    for (int a = 0; a < n; a++)
        for (int b2 = a + 1; b2 < n; b2++)
            if (sum[order[b2]].cpu_ms < sum[order[a]].cpu_ms) {
                int t = order[a];
                order[a] = order[b2];
                order[b2] = t;
            }
    for (int a = 0; a < n; a++)
        md_row(f, &vl->v[order[a]], &sum[order[a]], false);
    /* at the recipe's cost (+5%): the best of all (rec_fast) and without the mf estimator (rec_shader) */
    int rec_fast = -1, rec_shader = -1;
    if (base >= 0 && sum[base].done)
        for (int i = 0; i < vl->count; i++) {
            if (!sum[i].done || !comparable(&vl->v[i]) || sum[i].cpu_ms > 1.05 * sum[base].cpu_ms)
                continue;
            if (rec_fast < 0 || sum[i].e[0].nrmse < sum[rec_fast].e[0].nrmse)
                rec_fast = i;
            if (vl->v[i].opt.estimator != SL_ESTIMATOR_MICROFACET &&
                (rec_shader < 0 || sum[i].e[0].nrmse < sum[rec_shader].e[0].nrmse))
                rec_shader = i;
        }
    fprintf(f, "\n## Recommended defaults\n\n");
    char env_flag[32] = "";
    if (rec_fast >= 0 && vl->v[rec_fast].opt.env_lights > 0)
        snprintf(env_flag, sizeof env_flag, " --env-lights %d", vl->v[rec_fast].opt.env_lights);
    if (rec_fast >= 0)
        fprintf(f, "* For accuracy, at the recipe's cost: **`%s`** (`--estimator %s --lod %s%s%s -n %d`), nRMSE %.4f\n"
                   "  against the recipe's %.4f, %.2f against %.2f lighting CPU ms. The recipe (`--estimator spec`)\n"
                   "  stays the default because it is what the specification's GLSL computes; this is the setting\n"
                   "  to use when the picture should be right.\n",
                vl->v[rec_fast].name, sl_estimator_name(vl->v[rec_fast].opt.estimator),
                sl_lod_rule_name(vl->v[rec_fast].opt.lod_rule), vl->v[rec_fast].opt.distortion ? " --distortion" : "",
                env_flag, vl->v[rec_fast].opt.samples, sum[rec_fast].e[0].nrmse, sum[base].e[0].nrmse, sum[rec_fast].cpu_ms,
                sum[base].cpu_ms);
    if (rec_shader >= 0 && rec_shader != rec_fast)
        fprintf(f, "* Without the microfacet estimator, the best at that cost is `%s` (nRMSE %.4f).\n",
                vl->v[rec_shader].name, sum[rec_shader].e[0].nrmse);
    fprintf(f, "* Irradiance: the brute-force map (`--irradiance brute`) where its one-off cost is paid once per\n"
               "  environment (rows below); G: the same G term as whatever the image is compared with.\n");
    /* progressive accumulation against one frame with as many samples */
    int acc = find(vl, "consistent spec+dist rot N8 x32"), one = find(vl, "consistent spec-d4+dist N256");
    int one40 = find(vl, "consistent spec+dist N40"), acc40 = find(vl, "consistent spec+dist rot N40 x32");
    if (acc >= 0 && one >= 0 && one40 >= 0 && acc40 >= 0 && sum[acc].done && sum[one].done && sum[one40].done &&
        sum[acc40].done)
        fprintf(f, "* Rotation and accumulation (`rot`, `xK`) do not pay on these scenes: 32 accumulated frames of\n"
                   "  N = 8 (256 samples per pixel, %.0f CPU ms) reach nRMSE %.4f, mean relative %.3f, where one frame\n"
                   "  of N = 256 (`consistent spec-d4+dist N256`, %.0f ms) reaches %.4f / %.3f; and 32 frames of N = 40\n"
                   "  (%.0f ms) end at %.4f / %.3f against %.4f / %.3f for the single unrotated frame. Each frame keeps\n"
                   "  the mip level chosen for its own N (a blur sized for N samples), so averaging frames removes\n"
                   "  noise but not that bias, and a rotated frame loses the per-alpha tables (it costs more).\n"
                   "  What rotation changes is the look (noise instead of a fixed pattern), which these figures\n"
                   "  do not score.\n",
                sum[acc].cpu_ms, sum[acc].e[0].nrmse, sum[acc].e[0].mean_rel, sum[one].cpu_ms, sum[one].e[0].nrmse,
                sum[one].e[0].mean_rel, sum[acc40].cpu_ms, sum[acc40].e[0].nrmse, sum[acc40].e[0].mean_rel,
                sum[one40].e[0].nrmse, sum[one40].e[0].mean_rel);
    int macc = find(vl, "mf gems+dist rot N8 x32"), mone = find(vl, "mf gems+dist N256");
    int mrot = find(vl, "mf gems+dist rot N8"), mfix = find(vl, "mf gems+dist N8");
    if (macc >= 0 && mone >= 0 && mrot >= 0 && mfix >= 0 && sum[macc].done && sum[mone].done && sum[mrot].done &&
        sum[mfix].done)
        fprintf(f, "* With the microfacet estimator, 32 accumulated rotated frames of N = 8 (%.0f CPU ms) reach nRMSE\n"
                   "  %.4f, mean relative %.3f, against %.4f / %.3f for one frame of N = 256 (`%s`, %.0f ms): %s.\n"
                   "  One rotated frame of N = 8: %.4f / %.3f (unrotated %.4f / %.3f).\n",
                sum[macc].cpu_ms, sum[macc].e[0].nrmse, sum[macc].e[0].mean_rel, sum[mone].e[0].nrmse,
                sum[mone].e[0].mean_rel, vl->v[mone].name, sum[mone].cpu_ms,
                sum[macc].e[0].nrmse < sum[mone].e[0].nrmse && sum[macc].cpu_ms <= sum[mone].cpu_ms
                    ? "accumulation pays here"
                    : "one frame with all the samples is still the better use of the time",
                sum[mrot].e[0].nrmse, sum[mrot].e[0].mean_rel, sum[mfix].e[0].nrmse, sum[mfix].e[0].mean_rel);
    fputc('\n', f);

    /* env lights: K and their one-off cost */
    fprintf(f, "## Env lights\n\n"
               "Extraction (`sl_env_lights_extract`, K = 32, median of 3, one thread: node table of level 0,\n"
               "selection, residual mip chain), once per environment:");
    for (int q = 0; q < scenes; q++)
        fprintf(f, "%s %s %.0f ms (%d lights, %.1f%% of the map's luminous power)", q ? ";" : "", si[q].name,
                si[q].env_lights_ms, si[q].env_lights_count, 100 * si[q].env_lights_share);
    fprintf(f, ".\n\nK against error, `mf pdf+dist` (set means):\n\n"
               "| K | N | lighting CPU ms | nRMSE total | nRMSE specular | mean rel | >8/255 |\n"
               "|---:|---:|---:|---:|---:|---:|---:|\n");
    const int ks_env[] = {0, 4, 8, 16, 32, 64};
    for (int nn = 16; nn <= 32; nn += 16)
        for (int k = 0; k < 6; k++) {
            char name[64];
            if (ks_env[k] > 0)
                snprintf(name, sizeof name, "mf pdf+dist+env%d N%d", ks_env[k], nn);
            else
                snprintf(name, sizeof name, "mf pdf+dist N%d", nn);
            int i = find(vl, name);
            if (i >= 0 && sum[i].done)
                fprintf(f, "| %d | %d | %.2f | %.4f | %.4f | %.3f | %.1f%% |\n", ks_env[k], nn, sum[i].cpu_ms,
                        sum[i].e[0].nrmse, sum[i].e[2].nrmse, sum[i].e[0].mean_rel, 100 * sum[i].e[0].over8);
        }
    fputc('\n', f);

    /* full tables */
    fprintf(f, "## Every variant (set means; bold = on the Pareto front)\n\n%s", TABLE_HEAD);
    for (int i = 0; i < vl->count; i++)
        if (sum[i].done && vl->v[i].kind != KIND_GL)
            md_row(f, &vl->v[i], &sum[i], comparable(&vl->v[i]) && on_front(vl, sum, i, vl->count));
    fprintf(f, "\n## Diffuse (irradiance method; set means)\n\n"
               "| irradiance | nRMSE diffuse | mean rel | p99 rel | >1/255 | >8/255 |\n|---|---:|---:|---:|---:|---:|\n");
    const char *irrv[3] = {"spec spec-d4 N40", "spec spec-d4 brute N40", "spec spec-d4 map N40"};
    for (int k = 0; k < 3; k++) {
        int i = find(vl, irrv[k]);
        if (i >= 0 && sum[i].done)
            fprintf(f, "| %s | %.4f | %.4f | %.4f | %.2f%% | %.2f%% |\n", irr_name(vl->v[i].irr), sum[i].e[1].nrmse,
                    sum[i].e[1].mean_rel, sum[i].e[1].p99_rel, 100 * sum[i].e[1].over1, 100 * sum[i].e[1].over8);
    }
    /* GL beside the CPU */
    fprintf(f, "\n## softlight and softlight-gl side by side (N = 40)\n\n"
               "softlight-gl on llvmpipe (Mesa's CPU rasterizer, the same 2 cores); its time is G-buffer + lighting\n"
               "passes (glFinish), without tone map and read-back; softlight's is raster + lighting + tone map.\n"
               "Every time in this table is wall time (softlight-gl's CPU time is not separable from its\n"
               "process), so it moves with the machine's load; both renderers were timed minutes apart.\n\n"
               "| variant | renderer | lighting ms | frame ms | frame ms, full size | nRMSE total | nRMSE specular "
               "| >8/255 |\n|---|---|---:|---:|---:|---:|---:|---:|\n");
    const char *pairs[5][2] = {{"spec spec-d4 N40", "GL spec spec-d4 N40"},
                               {"consistent gems+dist N40", "GL consistent gems+dist N40"},
                               {"mf gems+dist N40", "GL mf gems+dist N40"},
                               {"mf pdf+dist N40", "GL mf pdf+dist N40"},
                               {"mf pdf+dist+env32 N40", "GL mf pdf+dist+env32 N40"}};
    for (int k = 0; k < 5; k++)
        for (int j = 0; j < 2; j++) {
            int i = find(vl, pairs[k][j]);
            if (i >= 0 && sum[i].done)
                fprintf(f, "| %s | %s | %.2f | %.2f | %.1f | %.4f | %.4f | %.1f%% |\n", pairs[k][0],
                        j ? "softlight-gl" : "softlight", sum[i].lighting_ms, sum[i].frame_ms, sum[i].anchor_ms, sum[i].e[0].nrmse, sum[i].e[2].nrmse, 100 * sum[i].e[0].over8);
        }
    /* per scene, the baseline and the recommendations */
    fprintf(f, "\n## Per scene\n\n| scene | variant | lighting CPU ms | nRMSE total | nRMSE diffuse | nRMSE specular | mean rel "
               "| p99 rel | >1/255 | >8/255 |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    int show[3] = {base, rec_shader, rec_fast};
    for (int q = 0; q < scenes; q++)
        for (int k = 0; k < 3; k++) {
            int i = show[k];
            if (i < 0 || (k == 2 && rec_fast == rec_shader) || !res[i][q].done)
                continue;
            const result *r = &res[i][q];
            fprintf(f, "| %s | %s | %.2f | %.4f | %.4f | %.4f | %.3f | %.3f | %.1f%% | %.1f%% |\n", si[q].name,
                    vl->v[i].name, r->cpu_ms, r->e[0].nrmse, r->e[1].nrmse, r->e[2].nrmse, r->e[0].mean_rel,
                    r->e[0].p99_rel, 100 * r->e[0].over1, 100 * r->e[0].over8);
        }
    fclose(f);
    fprintf(stderr, "wrote %s\n", c->doc);
}

/* ------------------------------------------------------------------ main */

static bool parse_size(const char *s, int *w, int *h) { return sscanf(s, "%dx%d", w, h) == 2 && *w > 0 && *h > 0; }

int main(int argc, char **argv)
{
    config c = {.width = 192, .height = 108, .frames = 5, .anchor_frames = 3, .out_dir = "out/speed-vs-error",
                .cache_dir = "out/ground-truth", .doc = "docs/accuracy.md", .gl = NULL};
    snprintf(c.scenes, sizeof c.scenes, "default,bunny,city-sun,grazing,top-down");
    static char gl_default[PATH_LEN];
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
        else {
            fprintf(stderr,
                    "usage: bench_speed_vs_error [--size WxH] [--frames F] [--anchor-frames F] [--threads T]\n"
                    "       [--out DIR] [--cache DIR] [--doc FILE|none] [--gl PATH|none] [--scenes a,b,...]\n"
                    "(run from the source root; bench/speed-vs-error.sh runs it and makes the plots)\n");
            return 2;
        }
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
        /* --scenes is a comma list of names */
        const char *p = strstr(c.scenes, all_scenes[k].name);
        size_t len = strlen(all_scenes[k].name);
        if (!p || (p != c.scenes && p[-1] != ',') || (p[len] && p[len] != ','))
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
    write_outputs(&c, &vl, res, si, scenes, sl_now_seconds() - t0, load0, loadavg());
    return 0;
}
