/* cmd_compare.c - `softlight compare A B`: how far apart two renderings (.pfm, .hdr, .exr or a layer
 * FILE.exr:LAYER of a multi-layer .exr) are.
 *
 * Prints the figures of sl_compare_images (src/post/compare.h) and the worst pixels, optionally
 * writes a false-colour difference PNG, and turns a tolerance into an exit status so scripts and
 * CTest can use it: 0 within tolerance, 1 outside it (or any NaN/Inf in either image), 2 on errors.
 * The image readers repair NaN, Inf and negative texels on load; their counts are reported here
 * and a NaN or Inf in a file fails the check, since no stage may ever emit one. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "app/args.h"
#include "app/commands.h"
#include "core/exr.h"
#include "core/image.h"
#include "post/compare.h"

static bool has_suffix(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n >= k && !strcmp(s + n - k, suffix);
}

/* FILE.pfm, FILE.hdr, FILE.exr (its R, G, B), or FILE.exr:LAYER (a layer of a multi-layer
 * .exr, as render --exr writes: signed values kept, as the AOV it equals; a PFM compared with
 * such a layer is read signed too, so normal.pfm compares with FILE.exr:normal). */
static bool is_exr_layer(const char *path) { return strstr(path, ".exr:") || strstr(path, ".EXR:"); }

static bool load_float_image(const char *path, sl_image *img, sl_image_repairs *repairs, sl_error *err)
{
    memset(repairs, 0, sizeof *repairs);
    const char *colon = strstr(path, ".exr:");
    if (!colon)
        colon = strstr(path, ".EXR:");
    if (colon) {
        char file[4096];
        size_t n = (size_t)(colon - path) + 4;
        if (n >= sizeof file)
            return sl_fail(err, SL_ERR_RANGE, "%s: path too long", path);
        memcpy(file, path, n);
        file[n] = '\0';
        return sl_exr_read_layer(file, path + n + 1, NULL, 0, img, err);
    }
    if (has_suffix(path, ".exr") || has_suffix(path, ".EXR"))
        return sl_image_read_exr(path, 0, img, repairs, err);
    if (has_suffix(path, ".pfm") || has_suffix(path, ".PFM"))
        return sl_image_read_pfm(path, 0, img, repairs, err);
    if (has_suffix(path, ".hdr") || has_suffix(path, ".HDR"))
        return sl_image_read_hdr(path, 0, img, repairs, err);
    return sl_fail(err, SL_ERR_UNSUPPORTED, "%s: expected a .pfm, .hdr or .exr image (or FILE.exr:LAYER)", path);
}

/* A or B: a PFM beside an .exr layer is read signed (positions, normals), as the layer is. */
static bool load_compared(const char *path, bool beside_layer, sl_image *img, sl_image_repairs *repairs, sl_error *err)
{
    if (beside_layer && (has_suffix(path, ".pfm") || has_suffix(path, ".PFM"))) {
        memset(repairs, 0, sizeof *repairs);
        return sl_image_read_pfm_signed(path, 0, img, err);
    }
    return load_float_image(path, img, repairs, err);
}

/* --edges DA,DB: sl_compare_edge_mask of the two depth images, and-ed into `mask` when one was given. */
static bool edge_mask(const char *pair, int band, float depth_tol, const sl_image *given, sl_image *mask,
                      sl_error *err)
{
    const char *comma = strchr(pair, ',');
    char first[1024];
    if (!comma || (size_t)(comma - pair) >= sizeof first)
        return sl_fail(err, SL_ERR_RANGE, "--edges: expected DEPTH_A.pfm,DEPTH_B.pfm, got '%s'", pair);
    memcpy(first, pair, (size_t)(comma - pair));
    first[comma - pair] = '\0';
    sl_image da = {0}, db = {0}, edges = {0};
    sl_image_repairs r;
    long kept = 0;
    bool ok = load_float_image(first, &da, &r, err) && load_float_image(comma + 1, &db, &r, err) &&
              sl_compare_edge_mask(&da, &db, band, depth_tol, &edges, &kept, err);
    if (ok && given) {
        if (given->width != edges.width || given->height != edges.height) {
            ok = sl_fail(err, SL_ERR_RANGE, "--mask is %dx%d, the depth images %dx%d", given->width, given->height,
                         edges.width, edges.height);
        } else {
            for (int y = 0; y < edges.height; y++)
                for (int x = 0; x < edges.width; x++)
                    if (!(sl_image_pixel(given, x, y)[0] > 0.5f))
                        sl_image_pixel(&edges, x, y)[0] = 0.0f;
        }
    }
    if (ok) {
        printf("edges           %ld of %ld pixels kept (band %d, depth tolerance %g)\n", kept,
               (long)edges.width * edges.height, band, (double)depth_tol);
        sl_image_free(mask);
        *mask = edges;
    } else {
        sl_image_free(&edges);
    }
    sl_image_free(&da);
    sl_image_free(&db);
    return ok;
}

static void print_repairs(const char *label, const char *path, const sl_image_repairs *r)
{
    if (r->nan_count || r->inf_count || r->negative_count)
        printf("%s %s: %ld NaN, %ld Inf, %ld negative values in the file (read as 0)\n", label, path, r->nan_count,
               r->inf_count, r->negative_count);
}

int cmd_compare(int argc, char **argv)
{
    const char *mask_path = NULL, *diff_path = NULL, *edges = NULL;
    float tolerance = -1.0f, exposure = 1.0f, contrast = 1.0f, rel_floor = 1e-3f, depth_tol = 1e-6f;
    int metric = SL_METRIC_RMSE, edge_band = 1;
    unsigned given = 0;
    const sl_arg_mark tolerance_mark = {&given, 1u};
    const sl_arg table[] = {
        {"--mask", NULL, SL_ARG_STRING, &mask_path, 0, 0, NULL, "M", "compare only where M (.pfm/.hdr) is > 0.5", NULL},
        {"--edges", NULL, SL_ARG_STRING, &edges, 0, 0, NULL, "DA,DB",
         "leave out pixels near silhouettes or where depth images DA, DB (depth.pfm) disagree", NULL},
        {"--edge-band", NULL, SL_ARG_INT, &edge_band, 0, 16, NULL, "N", "pixels around each such pixel (default 1)",
         NULL},
        {"--depth-tol", NULL, SL_ARG_FLOAT, &depth_tol, 0, 1, NULL, "T", "depths further apart disagree (default 1e-6)",
         NULL},
        {"--tolerance", NULL, SL_ARG_FLOAT, &tolerance, 0, 1e30, NULL, "T", "exit 1 unless the metric is <= T",
         &tolerance_mark},
        {"--metric", NULL, SL_ARG_CHOICE, &metric, 0, 0, "rmse|max|p99rel", NULL,
         "what --tolerance bounds (default rmse)", NULL},
        {"--diff", NULL, SL_ARG_STRING, &diff_path, 0, 0, NULL, "OUT.png", "write a false-colour difference image",
         NULL},
        {"--exposure", NULL, SL_ARG_FLOAT, &exposure, 1e-6, 1e6, NULL, "E", "tone-map exposure (default 1)", NULL},
        {"--contrast", NULL, SL_ARG_FLOAT, &contrast, 1e-3, 100, NULL, "C", "tone-map contrast (default 1)", NULL},
        {"--rel-floor", NULL, SL_ARG_FLOAT, &rel_floor, 1e-12, 1e30, NULL, "F",
         "smallest denominator of the relative error (default 1e-3)", NULL},
    };
    const int count = (int)(sizeof table / sizeof table[0]);
    const char *usage = "softlight compare A B [options]   (A, B: .pfm, .hdr, .exr or FILE.exr:LAYER)";
    const char *paths[2];
    int npos = 0;
    bool help = false;
    sl_error err = {0};
    if (!sl_args_parse(argc, argv, 2, table, count, paths, 2, &npos, &help, &err)) {
        fprintf(stderr, "softlight compare: %s\n", err.msg);
        return 2;
    }
    if (help) {
        sl_args_print_help(stdout, usage, table, count);
        printf("\nexit status: 0 within tolerance (or no --tolerance), 1 outside it or NaN/Inf present, 2 errors\n");
        return 0;
    }
    if (npos != 2) {
        fprintf(stderr, "softlight compare: expected two images, A and B (see --help)\n");
        return 2;
    }

    int status = 2;
    sl_image a = {0}, b = {0}, mask = {0}, diff = {0};
    sl_image_repairs ra, rb, rm;
    bool layers = is_exr_layer(paths[0]) || is_exr_layer(paths[1]);
    if (!load_compared(paths[0], layers, &a, &ra, &err) || !load_compared(paths[1], layers, &b, &rb, &err) ||
        (mask_path && !load_float_image(mask_path, &mask, &rm, &err)))
        goto done;
    if (edges && !edge_mask(edges, edge_band, depth_tol, mask_path ? &mask : NULL, &mask, &err))
        goto done;
    sl_compare_desc desc = {.exposure = exposure, .contrast = contrast, .rel_floor = rel_floor,
                            .mask = mask_path || edges ? &mask : NULL};
    sl_compare_stats stats;
    if (!sl_compare_images(&a, &b, &desc, &stats, &err))
        goto done;
    printf("A %s\nB %s\n", paths[0], paths[1]);
    print_repairs("A", paths[0], &ra);
    print_repairs("B", paths[1], &rb);
    sl_compare_print(stdout, &stats, exposure, "A", "B");
    if (diff_path) {
        if (!sl_compare_diff_image(&a, &b, &desc, &diff, &err) || !sl_image_write_png(diff_path, &diff, &err))
            goto done;
        printf("diff image      %s\n", diff_path);
    }
    bool file_nonfinite = ra.nan_count || ra.inf_count || rb.nan_count || rb.inf_count;
    bool ok = !file_nonfinite && sl_compare_within(&stats, SL_METRIC_RMSE, INFINITY);
    static const char *metric_names[] = {"rmse", "max", "p99rel"};
    if (given) { /* --tolerance */
        double value = sl_compare_metric_value(&stats, (sl_compare_metric)metric);
        ok = ok && sl_compare_within(&stats, (sl_compare_metric)metric, (double)tolerance);
        printf("%s %s = %.6g, tolerance %.6g\n", ok ? "PASS" : "FAIL", metric_names[metric], value,
               (double)tolerance);
    } else if (!ok) {
        printf("FAIL NaN or Inf present\n");
    }
    status = ok ? 0 : 1;
done:
    if (status == 2)
        fprintf(stderr, "softlight compare: %s\n", err.msg);
    sl_image_free(&a);
    sl_image_free(&b);
    sl_image_free(&mask);
    sl_image_free(&diff);
    return status;
}
