/* sweep_report.h - the results of the speed-against-error sweep as its report reads them:
 * variants, per-scene results, scene facts, the run's configuration, and the one call that
 * writes the CSV, the plot data and docs/accuracy.md (sweep_report.c). speed_vs_error.c fills
 * these; the report only reads them. */
#ifndef SWEEP_REPORT_H
#define SWEEP_REPORT_H

#include <stdbool.h>

#include "ibl/ibl.h"
#include "shading/lighting.h"

#define MAX_VARIANTS 224
#define MAX_SCENES 8
#define PATH_LEN 1024

typedef enum { KIND_SHADER, KIND_GL } variant_kind;
enum { PART_TOTAL, PART_DIFFUSE, PART_SPECULAR, PART_COUNT };

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
    variant v[MAX_VARIANTS];
    int count;
} variant_list;

typedef struct {
    double nrmse, rmse, mean_rel, p99_rel, over1, over8;
} errors;

/* One variant on one scene. */
typedef struct {
    bool done;
    double frame_ms, lighting_ms, cpu_ms; /* medians: whole frame, lighting (wall), lighting CPU time */
    double anchor_ms, anchor_lighting_ms;
    errors e[PART_COUNT];
} result;

typedef struct {
    int width, height;  /* error size for 16:9; others keep the pixel count */
    int frames, anchor_frames, threads;
    const char *out_dir, *cache_dir, *doc, *gl;
    const char *truth_dir; /* NULL: compute (or read the cache); else DIR/NAME-WxH from `softlight truth --parts` */
    char scenes[256];
} config;

typedef struct {
    const char *name;
    bool ggx;           /* a GGX scene: its own set, beside the Phong set (the set means) */
    int w, h, anchor_w, anchor_h;
    long covered;
    double gt_seconds;
    bool gt_cached;
    bool gt_read;       /* read from c->truth_dir (sharded truth runs: their time is not this run's) */
    double env_lights_ms;  /* extracting 32 env lights and the residual's mips (median of 3) */
    int env_lights_count;
    double env_lights_share; /* their share of the map's luminous power */
    float exposure;
} scene_info;

/* Names as the variant names, the CSV and the report spell them. */
static inline const char *irr_name(sl_irradiance_method m) { return sl_irradiance_name(m); }
static inline const char *est_name(const variant *v) { return sl_estimator_name(v->opt.estimator); }
static inline const char *lod_name(const variant *v) { return sl_lod_rule_name(v->opt.lod_rule); }

/* Write c->out_dir/speed-vs-error.csv, the plot data beside it, and c->doc unless it is NULL or
 * "none", from res[variant][scene] of `scenes` scenes, the Phong scenes first and the GGX scenes
 * (si[k].ggx) after them: the set means, the claim and the plots are the Phong set's; the GGX
 * scenes are a set of their own ("all-ggx" in the CSV, a section of the report) beside it.
 * run_seconds and the load averages at the start and the end go into the report's method. Exits (status 2) when a file cannot be written. */
void sweep_write_report(const config *c, const variant_list *vl, result res[][MAX_SCENES], const scene_info *si,
                        int scenes, double run_seconds, double load0, double load1);

#endif
