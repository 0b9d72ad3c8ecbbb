/* sweep_report.c - what bench_speed_vs_error writes once every scene has run: the set means over
 * the scenes, the CSV, the plot data gnuplot reads (bench/gnuplot/speed-vs-error.gp), and the
 * report docs/accuracy.md, one function per section in the report's order. The measuring stays
 * in speed_vs_error.c; this file only reads its results (sweep_report.h), so the wording of the
 * report can change without touching the sweep, and the same results always give the same bytes. */
#include "sweep_report.h"

#include <errno.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static const char *const part_names[PART_COUNT] = {"total", "diffuse", "specular"};

/* ------------------------------------------------------------------ set means */

typedef struct {
    bool done;
    double frame_ms, lighting_ms, cpu_ms, anchor_ms;
    errors e[PART_COUNT];
} summary;

/* Mean over scenes first .. first + scenes - 1, all of which must have run (each scene weighs the
 * same); no scene: not summarized. */
static summary summarize(const result *r, int first, int scenes)
{
    summary s = {0};
    int n = 0, na = 0;
    for (int k = first; k < first + scenes; k++) {
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
    if (n != scenes || n == 0)
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

/* Everything the report's sections read: the sweep's results, their set means, and the variants
 * the text is built around (indices into vl, -1 when absent or not summarized). */
typedef struct {
    const config *c;
    const variant_list *vl;
    result (*res)[MAX_SCENES]; /* [variant][scene] */
    const scene_info *si;
    int scenes;         /* the Phong set: si[0 .. scenes - 1]; every section but the GGX one reads these */
    int ggx_scenes;     /* the GGX set: si[scenes .. scenes + ggx_scenes - 1] */
    double run_seconds, load0, load1;
    const summary *sum; /* per variant, the mean over the Phong scenes */
    const summary *sum_ggx; /* per variant, the mean over the GGX scenes */
    int base;           /* the recipe at N = 40: the baseline of the claim */
    int rec_fast;       /* the most accurate at the recipe's cost (+5%) */
    int rec_shader;     /* ... with the spec and consistent estimators alone */
} report;

/* Variants the claim and the Pareto front weigh: one frame, the baseline's G term (G = 1 is a
 * different BRDF, measured against its own ground truth), softlight's CPU renderer. */
static bool comparable(const variant *v)
{
    return v->kind != KIND_GL && v->accumulate <= 1 && v->opt.gterm != SL_GTERM_ONE;
}

static int find(const variant_list *vl, const char *name)
{
    for (int i = 0; i < vl->count; i++)
        if (!strcmp(vl->v[i].name, name))
            return i;
    return -1;
}

/* The comparable variant with the lowest total nRMSE in sum (a set's means) at no more than the
 * recipe's lighting CPU time (+5%), among the estimators up to up_to_estimator in options.h's
 * order (spec and consistent, then mf, then the split sum and the rest), leaving out env lights
 * when asked; the first in the variant list wins a tie. -1 without a summarized recipe. */
static int best_at_recipe_cost(const report *rp, const summary *sum, int up_to_estimator, bool without_env_lights)
{
    const variant_list *vl = rp->vl;
    if (rp->base < 0 || !sum[rp->base].done)
        return -1;
    int best = -1;
    for (int i = 0; i < vl->count; i++) {
        if (!sum[i].done || !comparable(&vl->v[i]) || sum[i].cpu_ms > 1.05 * sum[rp->base].cpu_ms)
            continue;
        if ((int)vl->v[i].opt.estimator > up_to_estimator || (without_env_lights && vl->v[i].opt.env_lights > 0))
            continue;
        if (best < 0 || sum[i].e[0].nrmse < sum[best].e[0].nrmse)
            best = i;
    }
    return best;
}

/* Pareto front on (lighting CPU ms, total nRMSE): no other variant is both faster and more accurate. */
static bool on_front(const variant_list *vl, const summary *s, int i, int count)
{
    for (int j = 0; j < count; j++)
        if (j != i && s[j].done && comparable(&vl->v[j]) && s[j].cpu_ms <= s[i].cpu_ms && s[j].e[0].nrmse <= s[i].e[0].nrmse &&
            (s[j].cpu_ms < s[i].cpu_ms || s[j].e[0].nrmse < s[i].e[0].nrmse))
            return false;
    return true;
}

/* ------------------------------------------------------------------ CSV and plot data */

/* A file the run writes; failing to create one ends the run, as every failure of the sweep does. */
static FILE *create_or_exit(const char *path)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "bench_speed_vs_error: %s: %s\n", path, strerror(errno));
        exit(2);
    }
    return f;
}

/* dir/name, created; its path in path (PATH_LEN bytes). */
static FILE *open_out(const char *dir, const char *name, char *path)
{
    snprintf(path, PATH_LEN, "%s/%s", dir, name);
    return create_or_exit(path);
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

/* speed-vs-error.csv: every variant x scene, then the sets ("all": Phong, "all-ggx"). */
static void write_csv(const report *rp)
{
    const config *c = rp->c;
    const variant_list *vl = rp->vl;
    result (*res)[MAX_SCENES] = rp->res;
    const scene_info *si = rp->si;
    const summary *sum = rp->sum, *sum_ggx = rp->sum_ggx;
    int scenes = rp->scenes + rp->ggx_scenes;
    char path[PATH_LEN];
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
        if (sum_ggx[i].done)
            csv_row(f, &vl->v[i], "all-ggx", c->width, c->height, sum_ggx[i].frame_ms, sum_ggx[i].lighting_ms,
                    sum_ggx[i].cpu_ms, sum_ggx[i].anchor_ms, sum_ggx[i].e);
    }
    fclose(f);
    fprintf(stderr, "wrote %s\n", path);
}

/* gnuplot data: series-K.dat, one file per N-sweep series; axes.dat, the single-point axes (GL's
 * wall times are not plotted); series.gp, how many series there are and where the progressive
 * ones begin. */
static void write_plot_data(const report *rp)
{
    const config *c = rp->c;
    const variant_list *vl = rp->vl;
    const summary *sum = rp->sum;
    char path[PATH_LEN];
    FILE *f;
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
}

/* ------------------------------------------------------------------ docs/accuracy.md */

/* A row of the tables of variants (set means): times, then the total's errors. */
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

/* The title and "How it was measured": the ground truth, the error size, the metrics, the timing
 * and the machine's load during this run. */
static void write_method(const report *rp, FILE *f)
{
    const config *c = rp->c;
    const scene_info *si = rp->si;
    int scenes = rp->scenes;
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
    bool all_cached = true, any_read = false;
    for (int k = 0; k < scenes; k++) {
        gt_total += si[k].gt_seconds;
        all_cached &= si[k].gt_cached;
        any_read |= si[k].gt_read;
    }
    if (any_read)
        fprintf(f, "this run read it from `%s/` (merged `softlight truth --parts --shard I/N` runs, checked\n"
                   "  against this run's coverage and by integrating 8 of its pixels again; docs/sharding.md).\n",
                c->truth_dir);
    else
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
            scenes, c->frames, c->threads > 0 ? c->threads : omp_get_max_threads(), c->anchor_frames, rp->load0,
            rp->load1, rp->run_seconds);
}

/* "Design of the sweep": which variants run and why (fixed text: build_variants in
 * speed_vs_error.c is what it describes). */
static void write_design(FILE *f)
{
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
               "   environment's 32 brightest texels are summed as lights, each at its texel's centroid (the\n"
               "   ground truth's node; near a narrow lobe's peak over cells of the texel, as the truth:\n"
               "   docs/ibl.md \"Narrow lobes\"), and the samples read the rest, whose brightest texel is then\n"
               "   the 33rd;\n"
               "10. `consistent gems+dist+env32` and 11. `spec spec-d4+env32` - the same split under the other\n"
               "   two estimators.\n\n"
               "The number of env lights K = 4, 8, 16, 32, 64 for `mf pdf+dist` at N = 16 and 32. Their\n"
               "extraction is per environment (like the irradiance), so no frame time includes it; its cost\n"
               "is in the \"Env lights\" section.\n\n"
               "At N = 40: every mip rule (none, spec, spec-d4, gems, pdf) with and without the distortion, for all three\n"
               "estimators; G = 1 (against a G = 1 ground truth); irradiance oct (the default: every other row\n"
               "uses it) / dp / sh9 / brute (64x32 map from the quadrature) / map (that map written as .hdr\n"
               "and loaded back, so RGBE-rounded). softlight-gl\n"
               "(llvmpipe) runs the recipe, `consistent gems+dist`, `mf gems+dist`, `mf pdf+dist` and\n"
               "`mf pdf+dist+env32` at N = 40: error on\n"
               "softlight's G-buffer (`--gbuffer`), time of its own whole frames. The shader's only fast\n"
               "approximation is its default batched path (core/fast_math.h's log2 and atan2 instead of libm's;\n"
               "docs/lighting.md): `plain` rows run the line-by-line port instead, for the recipe, `consistent\n"
               "spec+dist` and `mf gems+dist`. Per-pixel Cranley-Patterson rotation (`rot`, `options.rotate`):\n"
               "one frame, and progressive accumulation of K = 1..32 frames (`xK`, frame = 0..K-1,\n"
               "`sl_lighting_accumulate`) for the recipe at N = 40, `consistent spec+dist` at N = 40 and N = 8,\n"
               "and `mf gems+dist` at N = 8; their time is K frames.\n\n"
               "The claim, the Pareto front and the recommendations weigh only single frames with the baseline's\n"
               "G term (`1/(L.H)^2`): G = 1 is a different BRDF (measured against its own ground truth, it is\n"
               "an easier integrand, not a better estimate), and K accumulated frames cost K frames.\n\n");
}

/* The three plots bench/speed-vs-error.sh draws from the plot data into docs/accuracy/. */
static void write_plots(FILE *f)
{
    fprintf(f, "## Plots\n\n![total error against time](accuracy/speed-vs-error.png)\n\n"
               "![specular error against time](accuracy/specular-vs-time.png)\n\n"
               "![share of pixels off by more than 8/255](accuracy/over8-vs-time.png)\n\n");
}

/* The claim: the best variants at the baseline's cost, each against the baseline, per scene. */
static void write_claim(const report *rp, FILE *f)
{
    const variant_list *vl = rp->vl;
    result (*res)[MAX_SCENES] = rp->res;
    const scene_info *si = rp->si;
    const summary *sum = rp->sum;
    int scenes = rp->scenes, base = rp->base;
    const summary *b = &sum[base];
    /* the estimators in options.h's order: spec and consistent, then mf, then the rest */
    int best = best_at_recipe_cost(rp, sum, SL_ESTIMATOR_CV_MIS, false);
    int best_old = best_at_recipe_cost(rp, sum, SL_ESTIMATOR_CONSISTENT, true);
    int best_mf = best_at_recipe_cost(rp, sum, SL_ESTIMATOR_MICROFACET, true);
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
}

/* "Why": what more samples buy each estimator (its error floor), and the mip level's part in it. */
static void write_why_estimators(const report *rp, FILE *f)
{
    const variant_list *vl = rp->vl;
    const summary *sum = rp->sum;
    const summary *b = &sum[rp->base];
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
    if (b256 >= 0 && sum[b256].done)
        fprintf(f, "* The recipe's estimator is biased (docs/conventions.md, erratum 7): at N = 256 its nRMSE is still %.4f (%.4f at N = 40),\n"
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
}

/* "Why": the bright texels that carry nRMSE, and what env lights do to them. */
static void write_why_env_lights(const report *rp, FILE *f)
{
    const variant_list *vl = rp->vl;
    result (*res)[MAX_SCENES] = rp->res;
    const scene_info *si = rp->si;
    const summary *sum = rp->sum;
    int scenes = rp->scenes;
    fprintf(f, "* Without env lights, nRMSE (which squares the error) is carried by the few pixels that\n"
               "  reflect a sun or a lamp (radiance in the thousands against a sky near 1): in `top-down` two\n"
               "  pixels of the mirror sphere, in `grazing` the sun's glint on the floor. Filtered importance\n"
               "  sampling reads them through a blur sized for N samples, so the peak comes out low or smeared,\n"
               "  and it steps up and down along N with whether a sample lands on it.\n");
    int e0 = find(vl, "mf pdf+dist N32"), e32 = find(vl, "mf pdf+dist+env32 N32");
    if (e0 >= 0 && e32 >= 0 && sum[e0].done && sum[e32].done) {
        fprintf(f, "* Env lights take exactly those texels out of the sampled map and sum them as the ground\n"
                   "  truth does, each at its texel's centroid or, near the peak of a lobe narrower than a few\n"
                   "  texels, over cells of the texel (docs/ibl.md \"Narrow lobes\"), and the samples read a\n"
                   "  residual whose brightest texel is the 33rd: `mf pdf+dist N32` -> `+env32`: nRMSE %.4f -> %.4f,\n"
                   "  specular %.4f -> %.4f, mean relative %.3f -> %.3f, >8/255 %.1f%% -> %.1f%%, lighting %.2f ->\n"
                   "  %.2f CPU ms"
                   " (32 BRDF evaluations per pixel, vectorized over the lights, and more for the few lights a narrow"
                   " lobe splits). Per scene (nRMSE):",
                sum[e0].e[0].nrmse, sum[e32].e[0].nrmse, sum[e0].e[2].nrmse, sum[e32].e[2].nrmse,
                sum[e0].e[0].mean_rel, sum[e32].e[0].mean_rel, 100 * sum[e0].e[0].over8, 100 * sum[e32].e[0].over8,
                sum[e0].cpu_ms, sum[e32].cpu_ms);
        for (int q = 0; q < scenes; q++)
            fprintf(f, "%s %s %.4f -> %.4f", q ? ";" : "", si[q].name, res[e0][q].e[0].nrmse, res[e32][q].e[0].nrmse);
        fprintf(f, ".\n");
    }
}

/* "Why": the diffuse floor under every total, and what the microfacet estimator costs (batched
 * against the port, and against the recipe). */
static void write_why_diffuse_and_cost(const report *rp, FILE *f)
{
    const variant_list *vl = rp->vl;
    const summary *sum = rp->sum;
    const summary *b = &sum[rp->base];
    int irr_sh9 = find(vl, "spec spec-d4 sh9 N40");
    fprintf(f, "* The diffuse term is the same in all of these (the octahedral map, nRMSE %.4f alone): a floor\n"
               "  under every total figure; SH9 is %.4f (see the irradiance rows).\n",
            b->e[1].nrmse, irr_sh9 >= 0 && sum[irr_sh9].done ? sum[irr_sh9].e[1].nrmse : NAN);
    int mp = find(vl, "mf gems+dist plain N40"), mb = find(vl, "mf gems+dist N40");
    int cp = find(vl, "consistent spec+dist plain N40"), cb = find(vl, "consistent spec+dist N40");
    if (mp >= 0 && mb >= 0 && cp >= 0 && cb >= 0 && sum[mp].done && sum[mb].done && sum[cp].done && sum[cb].done)
        fprintf(f, "* Cost: `mf gems+dist` at N = 40 takes %.2f lighting CPU ms batched and %.2f ms as the\n"
                   "  line-by-line port (%.2fx), against %.2f ms for the recipe and %.2f ms for `consistent\n"
                   "  spec+dist` (%.2f ms plain). The microfacet estimator needs no pow per sample (its D(H) comes\n"
                   "  with H from the per-alpha table) where the consistent one evaluates D(H) per sample.\n",
                sum[mb].cpu_ms, sum[mp].cpu_ms, sum[mp].cpu_ms / sum[mb].cpu_ms, b->cpu_ms, sum[cb].cpu_ms,
                sum[cp].cpu_ms);
}

/* "Why": GPU Gems 3's +1 on the mip level measured, pdf against gems (same estimator and N; the
 * rule costs the same). */
static void write_why_mip_level(const report *rp, FILE *f)
{
    const variant_list *vl = rp->vl;
    const summary *sum = rp->sum;
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
}

/* The Pareto front on (lighting CPU ms, total nRMSE), fastest first. */
static void write_pareto_front(const report *rp, FILE *f)
{
    const variant_list *vl = rp->vl;
    const summary *sum = rp->sum;
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
}

/* Recommended defaults: the best at the recipe's cost, with every estimator and with the spec and
 * consistent ones alone (the specification's sampling, whatever the mip rule or env lights). */
static void write_recommendations(const report *rp, FILE *f)
{
    const variant_list *vl = rp->vl;
    const summary *sum = rp->sum;
    int base = rp->base, rec_fast = rp->rec_fast, rec_shader = rp->rec_shader;
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
        fprintf(f, "* With the spec and consistent estimators alone, the best at that cost is `%s` (nRMSE %.4f).\n",
                vl->v[rec_shader].name, sum[rec_shader].e[0].nrmse);
    fprintf(f, "* Irradiance: the default octahedral map (`--irradiance oct`), built once per environment\n"
               "  (rows below); G: the same G term as whatever the image is compared with.\n");
}

/* Progressive accumulation against one frame with as many samples (part of the recommendations). */
static void write_accumulation(const report *rp, FILE *f)
{
    const variant_list *vl = rp->vl;
    const summary *sum = rp->sum;
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
}

/* Env lights: their one-off extraction cost per scene, and K against error. */
static void write_env_lights(const report *rp, FILE *f)
{
    const variant_list *vl = rp->vl;
    const scene_info *si = rp->si;
    const summary *sum = rp->sum;
    int scenes = rp->scenes;
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
}

/* Every softlight variant's set means, the Pareto front in bold. */
static void write_every_variant(const report *rp, FILE *f)
{
    const variant_list *vl = rp->vl;
    const summary *sum = rp->sum;
    fprintf(f, "## Every variant (set means; bold = on the Pareto front)\n\n%s", TABLE_HEAD);
    for (int i = 0; i < vl->count; i++)
        if (sum[i].done && vl->v[i].kind != KIND_GL)
            md_row(f, &vl->v[i], &sum[i], comparable(&vl->v[i]) && on_front(vl, sum, i, vl->count));
}

/* The diffuse term under each irradiance method. */
static void write_diffuse(const report *rp, FILE *f)
{
    const variant_list *vl = rp->vl;
    const summary *sum = rp->sum;
    fprintf(f, "\n## Diffuse (irradiance method; set means)\n\n"
               "| irradiance | nRMSE diffuse | mean rel | p99 rel | >1/255 | >8/255 |\n|---|---:|---:|---:|---:|---:|\n");
    const char *irrv[5] = {"spec spec-d4 N40", "spec spec-d4 dp N40", "spec spec-d4 sh9 N40", "spec spec-d4 brute N40",
                           "spec spec-d4 map N40"};
    for (int k = 0; k < 5; k++) {
        int i = find(vl, irrv[k]);
        if (i >= 0 && sum[i].done)
            fprintf(f, "| %s | %.4f | %.4f | %.4f | %.2f%% | %.2f%% |\n", irr_name(vl->v[i].irr), sum[i].e[1].nrmse,
                    sum[i].e[1].mean_rel, sum[i].e[1].p99_rel, 100 * sum[i].e[1].over1, 100 * sum[i].e[1].over8);
    }
}

/* softlight and softlight-gl on the same variants (wall times). */
static void write_gl_side_by_side(const report *rp, FILE *f)
{
    const variant_list *vl = rp->vl;
    const summary *sum = rp->sum;
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
}

/* Per scene: the baseline and the recommendations. */
static void write_per_scene(const report *rp, FILE *f)
{
    const variant_list *vl = rp->vl;
    result (*res)[MAX_SCENES] = rp->res;
    const scene_info *si = rp->si;
    int scenes = rp->scenes, base = rp->base, rec_fast = rp->rec_fast, rec_shader = rp->rec_shader;
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
}

/* "GGX beside Phong": the GGX set's total nRMSE per N for every N-sweep series, each beside the
 * Phong set's; the estimator x mip rule axis at N = 40 with the cost; the best GGX variant at
 * the recipe's cost. The two sets are different scenes: what compares is how each estimator and
 * mip rule converges on each BRDF, not pixel for pixel. */
static void write_ggx(const report *rp, FILE *f)
{
    const config *c = rp->c;
    const variant_list *vl = rp->vl;
    const scene_info *si = rp->si;
    const summary *sum = rp->sum, *gs = rp->sum_ggx;
    int threads = c->threads > 0 ? c->threads : omp_get_max_threads();
    fprintf(f, "\n## GGX beside Phong\n\n"
               "This run: `bench/speed-vs-error.sh build -- --size %dx%d --frames %d --anchor-frames %d --scenes %s`.\n"
               "The GGX set (`\"brdf\": \"ggx\"`, docs/lighting.md \"Phong and GGX\"): ",
            c->width, c->height, c->frames, c->anchor_frames, c->scenes);
    for (int q = rp->scenes; q < rp->scenes + rp->ggx_scenes; q++)
        fprintf(f, "%s%s, %dx%d, %ld covered pixels, ground truth %.0f s (%.1f ms per covered pixel and core%s)",
                q > rp->scenes ? "; " : "", si[q].name, si[q].w, si[q].h, si[q].covered, si[q].gt_seconds,
                si[q].covered ? 1e3 * si[q].gt_seconds * threads / (double)si[q].covered : 0.0,
                si[q].gt_read ? ", by the sharded runs" : si[q].gt_cached ? ", when the cache was made" : "");
    fprintf(f, ". The same variants as the Phong set, on the same G-buffer path, against the ground truth\n"
               "with GGX's D and height-correlated Smith visibility (GGX has one G: the `G=1` rows equal the\n"
               "others on it). `spec` on a GGX material is eq. (3)'s structure with GGX's lobe (samples drawn\n"
               "about R with GGX's shape, weighted G (w.N) / 4): it keeps eq. (3)'s bias, which is why it\n"
               "stays high at any N below; `consistent` divides by the density of the same draws and misses\n"
               "GGX's tail past R; `mf` draws H from D(H) (N.H) and converges. The Phong column is the Phong\n"
               "set's mean over its %d scenes: different scenes, so compare the shape of each line, not the\n"
               "values pixel for pixel.\n\n",
            rp->scenes);
    /* table 1: rows series x set, columns N */
    char series[16][48];
    int nseries = 0;
    for (int i = 0; i < vl->count; i++) {
        const char *s = vl->v[i].series;
        bool seen = !s[0] || strstr(s, "x K frames") != NULL;
        for (int j = 0; j < nseries && !seen; j++)
            seen = !strcmp(series[j], s);
        if (!seen && nseries < 16)
            snprintf(series[nseries++], sizeof series[0], "%s", s);
    }
    int ns[32], nn = 0;
    for (int i = 0; i < vl->count && nseries > 0; i++)
        if (!strcmp(vl->v[i].series, series[0]) && nn < 32)
            ns[nn++] = vl->v[i].opt.samples;
    fprintf(f, "Total nRMSE per N (GGX set, then the Phong set's mean):\n\n| series | set |");
    for (int k = 0; k < nn; k++)
        fprintf(f, " N %d |", ns[k]);
    fprintf(f, "\n|---|---|");
    for (int k = 0; k < nn; k++)
        fprintf(f, "---:|");
    fputc('\n', f);
    for (int j = 0; j < nseries; j++)
        for (int set = 0; set < 2; set++) {
            const summary *s = set ? sum : gs;
            fprintf(f, "| %s | %s |", set ? "" : series[j], set ? "Phong" : "GGX");
            for (int k = 0; k < nn; k++) {
                int hit = -1;
                for (int i = 0; i < vl->count && hit < 0; i++)
                    if (!strcmp(vl->v[i].series, series[j]) && vl->v[i].opt.samples == ns[k])
                        hit = i;
                if (hit >= 0 && s[hit].done)
                    fprintf(f, " %.4f |", s[hit].e[0].nrmse);
                else
                    fprintf(f, " - |");
            }
            fputc('\n', f);
        }
    /* table 2: every single-frame N = 40 variant of the default irradiance and G term */
    fprintf(f, "\nN = 40, every estimator, mip rule and distortion (set means; lighting CPU ms per frame):\n\n"
               "| variant | GGX CPU ms | GGX nRMSE total | GGX nRMSE specular | GGX >8/255 | Phong CPU ms "
               "| Phong nRMSE total | Phong nRMSE specular |\n|---|---:|---:|---:|---:|---:|---:|---:|\n");
    for (int i = 0; i < vl->count; i++) {
        const variant *v = &vl->v[i];
        if (!comparable(v) || v->opt.samples != 40 || v->opt.plain || v->opt.rotate ||
            v->irr != sl_irradiance_default() || !gs[i].done)
            continue;
        fprintf(f, "| %s | %.2f | %.4f | %.4f | %.1f%% |", v->name, gs[i].cpu_ms, gs[i].e[0].nrmse, gs[i].e[2].nrmse,
                100 * gs[i].e[0].over8);
        if (sum[i].done)
            fprintf(f, " %.2f | %.4f | %.4f |\n", sum[i].cpu_ms, sum[i].e[0].nrmse, sum[i].e[2].nrmse);
        else
            fprintf(f, " - | - | - |\n");
    }
    int base = rp->base, best = best_at_recipe_cost(rp, gs, SL_ESTIMATOR_CV_MIS, false);
    if (base >= 0 && gs[base].done && best >= 0)
        fprintf(f, "\nOn the GGX set the recipe (`%s`, %.2f CPU ms) has total nRMSE %.4f; the most accurate variant\n"
                   "at its cost (+5%%) is `%s`: %.4f (%.2f ms).\n",
                vl->v[base].name, gs[base].cpu_ms, gs[base].e[0].nrmse, vl->v[best].name, gs[best].e[0].nrmse,
                gs[best].cpu_ms);
}

/* docs/accuracy.md, section by section; the claim and its reasons need the recipe's set means. */
static void write_doc(const report *rp)
{
    const char *path = rp->c->doc;
    FILE *f = create_or_exit(path);
    write_method(rp, f);
    write_design(f);
    write_plots(f);
    if (rp->base >= 0 && rp->sum[rp->base].done) {
        write_claim(rp, f);
        fprintf(f, "\nWhy (figures from this run):\n\n");
        write_why_estimators(rp, f);
        write_why_env_lights(rp, f);
        write_why_diffuse_and_cost(rp, f);
        write_why_mip_level(rp, f);
        fputc('\n', f);
    }
    write_pareto_front(rp, f);
    write_recommendations(rp, f);
    write_accumulation(rp, f);
    fputc('\n', f);
    write_env_lights(rp, f);
    write_every_variant(rp, f);
    write_diffuse(rp, f);
    write_gl_side_by_side(rp, f);
    write_per_scene(rp, f);
    if (rp->ggx_scenes > 0)
        write_ggx(rp, f);
    fclose(f);
    fprintf(stderr, "wrote %s\n", path);
}

void sweep_write_report(const config *c, const variant_list *vl, result res[][MAX_SCENES], const scene_info *si,
                        int scenes, double run_seconds, double load0, double load1)
{
    static summary sum[MAX_VARIANTS], sum_ggx[MAX_VARIANTS];
    int phong = 0;
    while (phong < scenes && !si[phong].ggx)
        phong++;
    for (int k = phong; k < scenes; k++)
        if (!si[k].ggx) {
            fprintf(stderr, "bench_speed_vs_error: scene %s after a GGX scene (the GGX scenes come last)\n", si[k].name);
            exit(2);
        }
    for (int i = 0; i < vl->count; i++) {
        sum[i] = summarize(res[i], 0, phong);
        sum_ggx[i] = summarize(res[i], phong, scenes - phong);
    }
    report rp = {.c = c, .vl = vl, .res = res, .si = si, .scenes = phong, .ggx_scenes = scenes - phong,
                 .run_seconds = run_seconds, .load0 = load0, .load1 = load1, .sum = sum, .sum_ggx = sum_ggx,
                 .base = find(vl, "spec spec-d4 N40")};
    rp.rec_fast = best_at_recipe_cost(&rp, sum, SL_ESTIMATOR_CV_MIS, false);
    rp.rec_shader = best_at_recipe_cost(&rp, sum, SL_ESTIMATOR_CONSISTENT, false);
    write_csv(&rp);
    write_plot_data(&rp);
    if (c->doc && strcmp(c->doc, "none"))
        write_doc(&rp);
}
