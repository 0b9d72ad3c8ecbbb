/* lighting_pass.c - what runs the lighting shader (lighting.c) and is C only: options and
 * their names, the uniforms derived from a frame's description, per-thread tasks, the pass over
 * a G-buffer (OpenMP over tiles), accumulation of rotated frames, and the trace of one pixel. */

#include <omp.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "lighting_internal.h"

sl_lighting_options sl_lighting_options_resolve(const sl_lighting_options *opt)
{
    sl_lighting_options r = opt ? *opt : (sl_lighting_options){0};
    if (r.samples == 0)
        r.samples = SL_LIGHTING_DEFAULT_SAMPLES;
    if (r.lod_samples == 0)
        r.lod_samples = r.samples;
    if (r.lod_rule == SL_LOD_DEFAULT)
        r.lod_rule = SL_LOD_SPEC_D4;
    if (r.gterm == SL_GTERM_DEFAULT)
        r.gterm = SL_GTERM_INV_LH2;
    if (r.estimator == SL_ESTIMATOR_DEFAULT)
        r.estimator = SL_ESTIMATOR_SPEC;
    if (r.env_intensity == 0.0f)
        r.env_intensity = 1.0f;
    return r;
}

static const char *const lod_names[] = {"default", "none", "spec", "spec-d4", "gems", "pdf"};
static const char *const estimator_names[] = {"default", "spec", "consistent", "mf"};
static const char *const gterm_names[] = {"default", "inv-lh2", "one"};

const char *sl_lod_rule_name(sl_lod_rule rule)
{
    return (unsigned)rule <= SL_LOD_PDF ? lod_names[rule] : "?";
}
const char *sl_estimator_name(sl_estimator estimator)
{
    return (unsigned)estimator <= SL_ESTIMATOR_MICROFACET ? estimator_names[estimator] : "?";
}
const char *sl_gterm_name(sl_gterm gterm) { return (unsigned)gterm <= SL_GTERM_ONE ? gterm_names[gterm] : "?"; }

static int parse_name(const char *name, const char *const *names, int count)
{
    for (int i = 0; name && i < count; i++)
        if (!strcmp(name, names[i]))
            return i;
    return -1;
}
bool sl_lod_rule_parse(const char *name, sl_lod_rule *rule)
{
    int i = parse_name(name, lod_names, SL_LOD_PDF + 1);
    if (i < 0)
        return false;
    *rule = (sl_lod_rule)i;
    return true;
}
bool sl_estimator_parse(const char *name, sl_estimator *estimator)
{
    int i = parse_name(name, estimator_names, 4);
    if (i < 0)
        return false;
    *estimator = (sl_estimator)i;
    return true;
}
bool sl_gterm_parse(const char *name, sl_gterm *gterm)
{
    int i = parse_name(name, gterm_names, 3);
    if (i < 0)
        return false;
    *gterm = (sl_gterm)i;
    return true;
}

void sl_hammersley_pack_std140(const sl_hammersley *set, sl_hammersley_block *block)
{
    _Static_assert(sizeof(vec4) == 16, "vec4 must be 16 bytes for std140");
    _Static_assert(offsetof(sl_hammersley_block, hammersley) == 16, "std140: the vec4 array starts at 16");
    memset(block, 0, sizeof *block);
    block->N = (float)set->n;
    for (int k = 0; k < set->n; k++) {
        vec4 *h = &block->hammersley[k >> 1];
        if ((k & 1) == 0) {
            h->x = set->points[k].x;
            h->y = set->points[k].y;
        } else {
            h->z = set->points[k].x;
            h->w = set->points[k].y;
        }
    }
}

bool sl_lighting_uniforms_init(sl_lighting_uniforms *u, const sl_lighting_desc *desc, sl_error *err)
{
    memset(u, 0, sizeof *u);
    sl_lighting_options o = sl_lighting_options_resolve(&desc->options);
    if (!desc->env || desc->env->level_count < 1)
        return sl_fail(err, SL_ERR_RANGE, "lighting: no environment map");
    if (o.samples < 1 || o.samples > SL_HAMMERSLEY_MAX)
        return sl_fail(err, SL_ERR_RANGE, "lighting: samples = %d, expected 1..%d", o.samples, SL_HAMMERSLEY_MAX);
    if (o.lod_samples < 1 || o.lod_samples > SL_HAMMERSLEY_MAX)
        return sl_fail(err, SL_ERR_RANGE, "lighting: lod samples = %d, expected 1..%d", o.lod_samples,
                       SL_HAMMERSLEY_MAX);
    if ((unsigned)o.lod_rule > SL_LOD_PDF || (unsigned)o.estimator > SL_ESTIMATOR_MICROFACET ||
        (unsigned)o.gterm > SL_GTERM_ONE)
        return sl_fail(err, SL_ERR_RANGE, "lighting: unknown lod rule, estimator or G term");
    if (desc->light_count < 0 || desc->light_count > SL_LIGHTING_MAX_LIGHTS)
        return sl_fail(err, SL_ERR_RANGE, "lighting: %d point lights, at most %d", desc->light_count,
                       SL_LIGHTING_MAX_LIGHTS);
    if (desc->light_count > 0 && !desc->lights)
        return sl_fail(err, SL_ERR_RANGE, "lighting: light_count %d with no lights", desc->light_count);
    if (!o.no_diffuse) {
        if (!desc->irradiance)
            return sl_fail(err, SL_ERR_RANGE, "lighting: diffuse is on but no irradiance was given");
        if (desc->irradiance->method != o.irradiance)
            return sl_fail(err, SL_ERR_RANGE, "lighting: options ask for irradiance method %d, the irradiance is %d",
                           (int)o.irradiance, (int)desc->irradiance->method);
    }
    if (!isfinite(o.env_intensity) || o.env_intensity < 0.0f || !isfinite(o.env_rotation_deg))
        return sl_fail(err, SL_ERR_RANGE, "lighting: environment intensity %g / rotation %g not usable",
                       (double)o.env_intensity, (double)o.env_rotation_deg);
    if (desc->width < 1 || desc->height < 1)
        return sl_fail(err, SL_ERR_RANGE, "lighting: viewport %dx%d", desc->width, desc->height);
    if (o.env_lights < 0 || o.env_lights > SL_ENV_LIGHTS_MAX)
        return sl_fail(err, SL_ERR_RANGE, "lighting: %d env lights, expected 0..%d", o.env_lights, SL_ENV_LIGHTS_MAX);
    const sl_env_lights *el = o.env_lights > 0 ? desc->env_lights : NULL;
    if (o.env_lights > 0) {
        const sl_env_level *a = &desc->env->levels[0];
        const sl_env_level *b = el ? &el->residual.levels[0] : NULL;
        if (!el || el->residual.level_count != desc->env->level_count || b->width != a->width ||
            b->height != a->height)
            return sl_fail(err, SL_ERR_RANGE, "lighting: %d env lights asked for, but none extracted from this environment",
                           o.env_lights);
    }

    sl_hammersley set;
    if (!sl_hammersley_build(&set, o.samples, err))
        return false;
    sl_hammersley_pack_std140(&set, &u->uHammersley);

    const sl_env_level *l0 = &desc->env->levels[0];
    u->uEnv = desc->env;
    u->uEnvResidual = el ? &el->residual : desc->env;
    _Static_assert(SL_ENV_LIGHTS_MAX % 16 == 0, "the batched path runs whole groups of 16 env lights");
    u->uEnvLightCount = el ? el->count : 0; /* the arrays stay zero past it (memset above) */
    for (int j = 0; j < u->uEnvLightCount; j++) {
        u->uEnvLightDir[j] = vec4(el->dir[j].x, el->dir[j].y, el->dir[j].z, 0.0f);
        u->uEnvLightRadiance[j] = vec4(el->radiance[j].x, el->radiance[j].y, el->radiance[j].z, 0.0f);
        u->envLightX[j] = el->dir[j].x;
        u->envLightY[j] = el->dir[j].y;
        u->envLightZ[j] = el->dir[j].z;
        u->envLightR[j] = el->radiance[j].x;
        u->envLightG[j] = el->radiance[j].y;
        u->envLightB[j] = el->radiance[j].z;
    }
    u->uEnvMaxLod = (float)(desc->env->level_count - 1);
    /* In float, as a shader computing it would; log2 of a product of ints <= 2^28 is exact enough. */
    u->uLodBase = 0.5f * log2f((float)l0->width * (float)l0->height / (float)o.lod_samples);
    u->uSinThetaMin = sinf(SL_PI / (2.0f * (float)l0->height));
    /* world -> environment: rotate by -rotation about +Z (column-major). */
    float phi = radians(o.env_rotation_deg);
    float c = cosf(phi), s = sinf(phi);
    u->uEnvRotation = (mat3){{{c, -s, 0.0f}, {s, c, 0.0f}, {0.0f, 0.0f, 1.0f}}};
    u->uEnvIntensity = o.env_intensity;
    u->uIrradianceMethod = desc->irradiance ? (int)desc->irradiance->method : 0;
    if (desc->irradiance && !o.no_diffuse) {
        u->uIrradiance = desc->irradiance;
        memcpy(u->uSH, desc->irradiance->sh, sizeof u->uSH);
    }
    u->uEye = desc->eye;
    u->uInvViewProj = desc->inv_view_proj;
    u->uViewport = vec2((float)desc->width, (float)desc->height);
    u->uLightCount = desc->light_count;
    for (int i = 0; i < desc->light_count; i++) {
        u->uLightPosition[i] = desc->lights[i].position;
        u->uLightColor[i] = desc->lights[i].color;
        u->uLightIntensity[i] = desc->lights[i].intensity;
    }
    u->uLodRule = (int)o.lod_rule;
    u->uDistortion = o.distortion ? 1 : 0;
    u->uGTerm = (int)o.gterm;
    u->uEstimator = (int)o.estimator;
    u->uDiffuse = o.no_diffuse ? 0 : 1;
    u->uSpecular = o.no_specular ? 0 : 1;
    u->uPointLights = (o.no_point_lights || desc->light_count == 0) ? 0 : 1;
    u->uRotate = o.rotate ? 1 : 0;
    u->uFrame = o.frame;
    u->options = o;
    size_t total = 0;
    for (int l = 0; l < desc->env->level_count; l++)
        total += (size_t)desc->env->levels[l].width * (size_t)desc->env->levels[l].height;
    /* vec3 indices (3 floats each) must fit an int */
    u->envGather = desc->env->block != NULL && u->uEnvResidual->block != NULL && total < (size_t)INT32_MAX / 3;
    size_t offset = 0;
    for (int l = 0; l < SL_ENV_MAX_LEVELS; l++) {
        /* without a block every level is described as level 0 at offset 0: the vectorized loop
         * then reads valid texels (of the wrong level), and the texel-by-texel fetch replaces
         * what it computed */
        const sl_env_level *lv = &desc->env->levels[u->envGather && l < desc->env->level_count ? l : 0];
        u->envOffset[l] = (int)offset;
        u->envWidth[l] = lv->width;
        u->envHeight[l] = lv->height;
        if (u->envGather)
            offset += (size_t)lv->width * (size_t)lv->height;
    }
    return true;
}

sl_lighting_task *sl_lighting_task_create(sl_error *err)
{
    sl_lighting_task *task = calloc(1, sizeof *task);
    if (!task)
        sl_fail(err, SL_ERR_MEMORY, "lighting: no memory for a task (%zu bytes)", sizeof *task);
    return task;
}

void sl_lighting_task_reset(sl_lighting_task *task)
{
    task->owner = NULL;
    task->next = 0;
    for (int s = 0; s < SLOTS; s++)
        task->slots[s].valid = false;
    task->azimuth.n = 0;
}

void sl_lighting_task_stats(const sl_lighting_task *task, sl_lighting_stats *stats)
{
    stats->pixels += task->stats.pixels;
    stats->background += task->stats.background;
    stats->samples += task->stats.samples;
    stats->below_horizon += task->stats.below_horizon;
    stats->bent_normals += task->stats.bent_normals;
    stats->pole_frames += task->stats.pole_frames;
    stats->nonfinite += task->stats.nonfinite;
}

void sl_lighting_task_destroy(sl_lighting_task *task) { free(task); }

enum { TILE = SPAN }; /* a tile row is one span of the batched path (lighting.c) */

bool sl_lighting_pass(const sl_lighting_uniforms *u, sl_lighting_stats *stats, const sl_gbuffer *gb,
                      sl_image *out, int threads, sl_error *err)
{
    if (!gb || !gb->texels || gb->width < 1 || gb->height < 1)
        return sl_fail(err, SL_ERR_RANGE, "lighting pass: empty G-buffer");
    if ((int)u->uViewport.x != gb->width || (int)u->uViewport.y != gb->height)
        return sl_fail(err, SL_ERR_RANGE, "lighting pass: uniforms are for %dx%d, the G-buffer is %dx%d",
                       (int)u->uViewport.x, (int)u->uViewport.y, gb->width, gb->height);
    if (out->data) {
        if (out->width != gb->width || out->height != gb->height || out->channels != 3)
            return sl_fail(err, SL_ERR_RANGE, "lighting pass: output is %dx%dx%d, expected %dx%dx3", out->width,
                           out->height, out->channels, gb->width, gb->height);
    } else if (!sl_image_alloc(out, gb->width, gb->height, 3, err)) {
        return false;
    }
    int nthreads = threads > 0 ? threads : omp_get_max_threads();
    sl_lighting_task **tasks = calloc((size_t)nthreads, sizeof *tasks);
    if (!tasks)
        return sl_fail(err, SL_ERR_MEMORY, "lighting pass: no memory");
    for (int i = 0; i < nthreads; i++) {
        tasks[i] = sl_lighting_task_create(err);
        if (!tasks[i]) {
            for (int j = 0; j < i; j++)
                sl_lighting_task_destroy(tasks[j]);
            free(tasks);
            return false;
        }
    }
    const int tiles_x = (gb->width + TILE - 1) / TILE;
    const int tiles_y = (gb->height + TILE - 1) / TILE;
    const int tile_count = tiles_x * tiles_y;
    /* Each tile writes only its own pixels; each pixel's value depends on nothing but its
     * texel and the read-only uniforms, so the image does not depend on the thread count. */
#pragma omp parallel num_threads(nthreads)
    {
        sl_lighting_task *task = tasks[omp_get_thread_num()];
#pragma omp for schedule(dynamic)
        for (int tile = 0; tile < tile_count; tile++) {
            int x0 = (tile % tiles_x) * TILE, y0 = (tile / tiles_x) * TILE;
            int x1 = x0 + TILE < gb->width ? x0 + TILE : gb->width;
            int y1 = y0 + TILE < gb->height ? y0 + TILE : gb->height;
            for (int y = y0; y < y1; y++) {
                float *row = sl_image_pixel(out, 0, gb->height - 1 - y); /* row 0 = top */
                vec3 c[TILE];
                sl_lighting_shade_row(u, gb, x0, y, x1 - x0, task, c);
                for (int x = x0; x < x1; x++) {
                    row[3 * x + 0] = c[x - x0].x;
                    row[3 * x + 1] = c[x - x0].y;
                    row[3 * x + 2] = c[x - x0].z;
                }
            }
            task->stats.pixels += (int64_t)(x1 - x0) * (y1 - y0);
        }
    }
    if (stats)
        memset(stats, 0, sizeof *stats);
    for (int i = 0; i < nthreads; i++) {
        if (stats)
            sl_lighting_task_stats(tasks[i], stats);
        sl_lighting_task_destroy(tasks[i]);
    }
    free(tasks);
    return true;
}

bool sl_lighting_accumulate(sl_image *mean, const sl_image *frame, int index, sl_error *err)
{
    if (!frame || !frame->data || index < 0)
        return sl_fail(err, SL_ERR_RANGE, "accumulate: no frame, or frame index %d < 0", index);
    if (index == 0 && !mean->data && !sl_image_alloc(mean, frame->width, frame->height, frame->channels, err))
        return false;
    if (!mean->data || mean->width != frame->width || mean->height != frame->height ||
        mean->channels != frame->channels)
        return sl_fail(err, SL_ERR_RANGE, "accumulate: frame %d is %dx%dx%d, the mean %dx%dx%d", index, frame->width,
                       frame->height, frame->channels, mean->width, mean->height, mean->channels);
    size_t count = (size_t)frame->width * (size_t)frame->height * (size_t)frame->channels;
    float *m = mean->data;
    const float *f = frame->data;
    if (index == 0) {
        memcpy(m, f, count * sizeof *m);
        return true;
    }
    /* The running mean: after frame k it is the mean of frames 0..k to float rounding, and it
     * never needs more than one image of memory. */
    float w = 1.0f / (float)(index + 1);
    for (size_t i = 0; i < count; i++)
        m[i] += (f[i] - m[i]) * w;
    return true;
}

bool sl_lighting_trace_pixel(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x, int y,
                             sl_lighting_trace *trace, sl_error *err)
{
    if (!gb || !gb->texels || x < 0 || y < 0 || x >= gb->width || y >= gb->height)
        return sl_fail(err, SL_ERR_RANGE, "trace: pixel %d,%d outside the %dx%d image", x, y, gb ? gb->width : 0,
                       gb ? gb->height : 0);
    memset(trace, 0, sizeof *trace);
    trace->x = x;
    trace->y = y;
    sl_lighting_shade(u, gb, x, gb->height - 1 - y, NULL, trace);
    return true;
}

static void print3(FILE *f, const char *name, vec3 v)
{
    fprintf(f, "  %-12s (%.6g, %.6g, %.6g)\n", name, (double)v.x, (double)v.y, (double)v.z);
}

void sl_lighting_trace_print(FILE *f, const sl_lighting_trace *t)
{
    fprintf(f, "pixel %d,%d (row 0 = top); gl_FragCoord (%.1f, %.1f)\n", t->x, t->y, (double)t->frag_coord.x,
            (double)t->frag_coord.y);
    if (!t->covered) {
        fprintf(f, "  no geometry (depth %.6g): environment at lod 0\n", (double)t->texel.depth);
        print3(f, "background", t->background);
        print3(f, "total", t->total);
        return;
    }
    fprintf(f, "G-buffer texel\n");
    print3(f, "position", t->texel.position);
    print3(f, "normal", t->texel.normal);
    print3(f, "kd", t->texel.kd);
    print3(f, "ks", t->texel.ks);
    fprintf(f, "  %-12s %.6g (used %.6g)\n  %-12s %.9g\n", "alpha", (double)t->texel.alpha, (double)t->alpha, "depth",
            (double)t->texel.depth);
    fprintf(f, "frame (world)\n");
    print3(f, "V", t->V);
    print3(f, "N", t->N);
    fprintf(f, "  %-12s %s\n", "bent normal", t->bent ? "yes (N.V < 0.01)" : "no");
    fprintf(f, "frame (environment)\n");
    print3(f, "N", t->Nenv);
    print3(f, "V", t->Venv);
    fprintf(f, "  %-12s %.6g\n", "N.V", (double)t->NdotV);
    fprintf(f, "  %-12s (%.8f, %.8f)%s\n", "xi rotation", (double)t->rotation.x, (double)t->rotation.y,
            t->rotation.x == 0.0f && t->rotation.y == 0.0f ? " (off)" : "");
    print3(f, "R", t->R);
    print3(f, "A", t->A);
    print3(f, "B", t->B);
    const char *axis = t->microfacet ? "N" : "R";
    fprintf(f, "  %-12s %s (frame about %s)\n", "A axis", t->pole_frame ? "X (axis near a pole)" : "Z", axis);
    fprintf(f, "specular samples (N = %d; %s; %s)\n", t->sample_count,
            t->microfacet ? "microfacet estimator: H drawn about N, w = reflect(-V, H), L.H = V.H"
                          : "directions drawn about R",
            t->plain ? "plain port" : "batched path: lod and uv by lighting_math.h, 4 partial sums");
    fprintf(f, "  %4s %-17s %-26s %-9s %-26s %-8s %-26s %-8s %-10s %-8s %-26s %-8s %-26s %-26s\n", "k", "xi",
            t->microfacet ? "H (about +Z)" : "L (skewed)", "p(w)", "w", "w.N", "H", t->microfacet ? "V.H" : "L.H", "D",
            "G", "F", "lod", "Li", "contribution");
    for (int k = 0; k < t->sample_count; k++) {
        const sl_lighting_trace_sample *s = &t->samples[k];
        fprintf(f, "  %4d (%.5f,%.5f) (%+.5f,%+.5f,%+.5f) %-9.4g (%+.5f,%+.5f,%+.5f) %+-8.4f", k, (double)s->xi.x,
                (double)s->xi.y, (double)s->L.x, (double)s->L.y, (double)s->L.z, (double)s->pdf, (double)s->w.x,
                (double)s->w.y, (double)s->w.z, (double)s->wN);
        if (t->microfacet && s->LdotH <= 0.0f) {
            fprintf(f, " V.H %+.5f <= 0 (facet faces away): 0\n", (double)s->LdotH);
            continue;
        }
        if (s->wN <= 0.0f) {
            fprintf(f, " below the horizon: 0\n");
            continue;
        }
        fprintf(f,
                " (%+.5f,%+.5f,%+.5f) %-8.5f %-10.4g %-8.4g (%.4f,%.4f,%.4f) %-8.4f (%.4g,%.4g,%.4g) (%.4g,%.4g,%.4g)"
                " sum (%.5g,%.5g,%.5g)\n",
                (double)s->H.x, (double)s->H.y, (double)s->H.z, (double)s->LdotH, (double)s->D, (double)s->G,
                (double)s->F.x, (double)s->F.y, (double)s->F.z, (double)s->lod, (double)s->Li.x, (double)s->Li.y,
                (double)s->Li.z, (double)s->c.x, (double)s->c.y, (double)s->c.z, (double)s->sum.x,
                (double)s->sum.y, (double)s->sum.z);
    }
    fprintf(f, "result\n");
    print3(f, "irradiance", t->irradiance);
    print3(f, "diffuse", t->diffuse);
    print3(f, "specular", t->specular);
    if (t->env_light_count > 0)
        fprintf(f, "  %-12s (%.6g, %.6g, %.6g): the exact part from %d env lights (in specular; the samples read the residual)\n",
                "env lights", (double)t->env_lights.x, (double)t->env_lights.y, (double)t->env_lights.z,
                t->env_light_count);
    print3(f, "lights", t->lights);
    print3(f, "total", t->total);
    if (t->repaired)
        fprintf(f, "  a NaN/Inf was replaced by 0\n");
}
