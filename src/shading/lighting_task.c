/* lighting_task.c - per-thread scratch of the lighting pass: counters, and the batched path's
 * tables of what does not depend on the pixel (docs/lighting.md "Two paths").
 *
 * skewed_sample and sample_pdf (microfacet_sample and microfacet_D) depend on the material's
 * alpha and the sample index only, yet cost an acos, a pow, two sincos and a second pow per
 * sample. A task keeps the tables of the last SLOTS distinct alphas it met, built by the port's
 * own functions (so the values are the port's bits), and a pixel pays a lookup. With rotation
 * on, every pixel has its own pairs; what stays fixed is each pair's azimuth, kept as cos/sin
 * (azimuth_table) for the batched path to rotate. The MIS estimator's environment samples
 * (env_sample_table) depend on neither pixel nor material with rotation off: one table. Tables are valid for the uniforms they were
 * built from (task->owner); a task met with other uniforms starts over. */
#include <stdlib.h>

#include "lighting_internal.h"

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
    task->env_samples.n = 0;
}

void sl_lighting_task_use_planes(sl_lighting_task *task, const sl_lighting_planes *planes)
{
    task->sky_plane = planes ? planes->sky : NULL;
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

/* Tables built for other uniforms are dropped. */
static void own(sl_lighting_task *task, const sl_lighting_uniforms *u)
{
    if (task->owner != u) {
        sl_lighting_task_reset(task);
        task->owner = u;
    }
}

void sl_shade_lobe_fill(const sl_lighting_uniforms *u, float alpha, bool microfacet, int k0, int m, float *xi1, float *xi2,
                     float *Lx, float *Ly, float *Lz, float *pdf)
{
    for (int i = 0; i < m; i++) {
        vec2 xi = sl_shade_hammersley_point(u, k0 + i);
        vec3 L = microfacet ? sl_shade_microfacet_sample(xi, alpha) : sl_shade_skewed_sample(xi, alpha);
        xi1[i] = xi.x;
        xi2[i] = xi.y;
        Lx[i] = L.x;
        Ly[i] = L.y;
        Lz[i] = L.z;
        pdf[i] = microfacet ? sl_shade_microfacet_D(xi, alpha) : sl_shade_sample_pdf(xi, alpha);
    }
}

void sl_shade_pad_samples(float *const *columns, int count, int m, int padded)
{
    for (int c = 0; c < count; c++)
        for (int i = m; i < padded; i++)
            columns[c][i] = columns[c][m - 1];
}

const lobe_table *sl_shade_lobe_for(const sl_lighting_uniforms *u, sl_lighting_task *task, float alpha, bool microfacet)
{
    int n = (int)u->uHammersley.N;
    own(task, u);
    for (int s = 0; s < SLOTS; s++) {
        const lobe_table *t = &task->slots[s];
        if (t->valid && t->alpha == alpha && t->n == n && t->microfacet == microfacet)
            return t;
    }
    lobe_table *t = &task->slots[task->next];
    task->next = (task->next + 1) % SLOTS;
    sl_shade_lobe_fill(u, alpha, microfacet, 0, n, t->xi1, t->xi2, t->Lx, t->Ly, t->Lz, t->pdf);
    float *columns[] = {t->xi1, t->xi2, t->Lx, t->Ly, t->Lz, t->pdf};
    sl_shade_pad_samples(columns, 6, n, sl_samples_padded(n));
    t->microfacet = microfacet;
    t->alpha = alpha;
    t->n = n;
    t->valid = true;
    return t;
}

/* phi as sl_uv_to_dir computes it from u = xi1 */
const azimuth_table *sl_shade_azimuth_for(const sl_lighting_uniforms *u, sl_lighting_task *task, azimuth_table *local)
{
    int n = (int)u->uHammersley.N;
    azimuth_table *t = local;
    if (task) {
        own(task, u);
        t = &task->azimuth;
        if (t->n == n)
            return t;
    }
    for (int k = 0; k < n; k++) {
        vec2 xi = sl_shade_hammersley_point(u, k);
        float phi = 2.0f * SL_PI * (0.5f - xi.x);
        t->xi1[k] = xi.x;
        t->xi2[k] = xi.y;
        t->cphi[k] = cosf(phi);
        t->sphi[k] = sinf(phi);
    }
    float *columns[] = {t->xi1, t->xi2, t->cphi, t->sphi};
    sl_shade_pad_samples(columns, 4, n, sl_samples_padded(n));
    t->n = n;
    return t;
}

const env_sample_table *sl_shade_env_samples_for(const sl_lighting_uniforms *u, sl_lighting_task *task,
                                                 env_sample_table *local)
{
    env_sample_table *t = local;
    if (task) {
        own(task, u);
        t = &task->env_samples;
        if (t->n > 0)
            return t;
    }
    const int n = (int)u->uHammersley.N;
    const float half_ = 0.5f / (float)(n > 1 ? n : 1); /* specular_mis's shift of xi.x */
    for (int k = 0; k < n; k++) {
        vec2 xi = sl_shade_hammersley_point(u, k);
        vec2 xe = vec2(fract(xi.x + half_), xi.y);
        ivec2 te;
        vec4 e = sl_shade_env_dist_sample(u, xe, &te);
        vec3 L = scale(sl_shade_env_texel_fetch(u, te), u->uEnvIntensity);
        t->wx[k] = e.x;
        t->wy[k] = e.y;
        t->wz[k] = e.z;
        t->pe[k] = e.w;
        t->lr[k] = L.x;
        t->lg[k] = L.y;
        t->lb[k] = L.z;
        t->xe1[k] = xe.x;
        t->xe2[k] = xe.y;
    }
    /* to the next multiple of 16: entries the batched loops read past n, adding 0 */
    for (int k = n; k < ((n + 15) & ~15) && k < SL_HAMMERSLEY_MAX; k++) {
        t->wx[k] = t->wy[k] = 0.0f;
        t->wz[k] = 1.0f;
        t->pe[k] = 1.0f;
        t->lr[k] = t->lg[k] = t->lb[k] = 0.0f;
        t->xe1[k] = t->xe2[k] = 0.0f;
    }
    t->n = n;
    return t;
}
