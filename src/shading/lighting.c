/* lighting.c - the lighting shader: a line-by-line C port of shaders/lighting.frag, and the
 * pass that runs it over a G-buffer.
 *
 * Every function below tagged "GLSL: name" is the GLSL function of that name, in the same
 * order, with the same variable names; a uniform uX is u->uX. Two deliberate differences,
 * both exact (the same float operations, so the same bits):
 *   - specular_ibl takes its per-sample (xi, L, pdf) from a per-alpha table when a task is
 *     given (hoisting, below); the GLSL recomputes them per pixel.
 *   - the trace: `if (trace)` blocks record intermediate values; they change nothing.
 * Everything else that is C-only (tasks, the pass, the trace printer) is after the port.
 *
 * Hoisting: skewed_sample and sample_pdf depend on the material's alpha and the sample index
 * only, yet cost an acos, a pow, two sincos and a second pow per sample. A task keeps the
 * tables of the last SLOTS distinct alphas it met (scenes have few materials), so a pixel
 * pays a table lookup; 1/2 log2(W H / N) is uLodBase, computed once per frame. */
#include "lighting.h"

#include <math.h>
#include <stddef.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

/* GLSL constants, same names and values. */
static const int LOD_NONE = SL_LOD_NONE;
static const int LOD_SPEC = SL_LOD_SPEC;
static const int LOD_SPEC_D4 = SL_LOD_SPEC_D4;
static const int ESTIMATOR_CONSISTENT = SL_ESTIMATOR_CONSISTENT;
static const float MIN_NDOTV = 0.01f;
static const float POLE_EPS = 1e-6f;
static const float TINY = SL_BRDF_TINY;
static const float MAX_ALPHA = 1e7f;
static const float MIN_LIGHT_D2 = 1e-8f;
#define PI SL_PI

/* ---- per-thread scratch ---- */

enum { SLOTS = 8 };

/* The loop-invariant part of specular_ibl for one alpha: (xi, L, pdf) of every sample. */
typedef struct {
    bool valid;
    float alpha;
    int n;
    vec2 xi[SL_HAMMERSLEY_MAX];
    vec3 L[SL_HAMMERSLEY_MAX];
    float pdf[SL_HAMMERSLEY_MAX];
} lobe_table;

struct sl_lighting_task {
    const sl_lighting_uniforms *owner; /* the uniforms the tables were built from */
    int next;                          /* round-robin victim */
    lobe_table slots[SLOTS];
    sl_lighting_stats stats;
};

/* ======================= the port of shaders/lighting.frag ======================= */

/* GLSL: hammersley_point */
static vec2 hammersley_point(const sl_lighting_uniforms *u, int k)
{
    vec4 h = u->uHammersley.hammersley[k >> 1];
    return ((k & 1) == 0) ? vec2(h.x, h.y) : vec2(h.z, h.w);
}

/* GLSL: skewed_sample */
static vec3 skewed_sample(vec2 xi, float alpha)
{
    vec2 uv = vec2(xi.x, acosf(clamp(powf(xi.y, 1.0f / (alpha + 1.0f)), -1.0f, 1.0f)) / PI);
    return sl_uv_to_dir(uv);
}

/* GLSL: sample_pdf */
static float sample_pdf(vec2 xi, float alpha)
{
    return (alpha + 1.0f) / (2.0f * PI) * powf(xi.y, alpha / (alpha + 1.0f));
}

/* GLSL: mip_level */
static float mip_level(const sl_lighting_uniforms *u, float D, float pdf, vec3 w)
{
    if (u->uLodRule == LOD_NONE)
        return 0.0f;
    float d = 1.0f;
    if (u->uDistortion != 0)
        d = 0.5f * PI * maxf(sqrtf(maxf(1.0f - w.z * w.z, 0.0f)), u->uSinThetaMin);
    float lod;
    if (u->uLodRule == LOD_SPEC)
        lod = u->uLodBase - 0.5f * log2f(maxf(D * d, TINY));
    else if (u->uLodRule == LOD_SPEC_D4)
        lod = u->uLodBase - 0.5f * log2f(maxf(D / 4.0f * d, TINY));
    else
        lod = u->uLodBase - 0.5f * log2f(maxf(4.0f * PI * pdf * d, TINY)) + 1.0f;
    return clamp(lod, 0.0f, u->uEnvMaxLod);
}

/* GLSL: facing_normal */
static vec3 facing_normal(vec3 N, vec3 V)
{
    float len2 = dot(N, N);
    if (!(len2 > TINY))
        return V;
    N = scale(N, 1.0f / sqrtf(len2));
    float NdotV = dot(N, V);
    if (NdotV < MIN_NDOTV)
        N = normalize(add(N, scale(V, MIN_NDOTV - NdotV)));
    return N;
}

/* GLSL: irradiance. sl_irradiance_eval (src/ibl/irradiance.c) is both branches: the SH9 sum
 * over uSH and the map lookup of uIrradianceMap. */
static vec3 irradiance(const sl_lighting_uniforms *u, vec3 N)
{
    return sl_irradiance_eval(u->uIrradiance, N);
}

/* Find or build the table for alpha (C only: the hoisted part of specular_ibl). */
static const lobe_table *lobe_for(const sl_lighting_uniforms *u, sl_lighting_task *task, float alpha)
{
    int n = (int)u->uHammersley.N;
    if (task->owner != u) {
        sl_lighting_task_reset(task);
        task->owner = u;
    }
    for (int s = 0; s < SLOTS; s++) {
        const lobe_table *t = &task->slots[s];
        if (t->valid && t->alpha == alpha && t->n == n)
            return t;
    }
    lobe_table *t = &task->slots[task->next];
    task->next = (task->next + 1) % SLOTS;
    for (int k = 0; k < n; k++) {
        t->xi[k] = hammersley_point(u, k);
        t->L[k] = skewed_sample(t->xi[k], alpha);
        t->pdf[k] = sample_pdf(t->xi[k], alpha);
    }
    t->alpha = alpha;
    t->n = n;
    t->valid = true;
    return t;
}

/* GLSL: specular_ibl */
static vec3 specular_ibl(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha,
                         sl_lighting_task *task, sl_lighting_trace *trace)
{
    float NdotV = dot(N, V);
    vec3 R = normalize(sub(scale(N, 2.0f * NdotV), V));
    vec3 axis = (R.x * R.x + R.y * R.y < POLE_EPS) ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 0.0f, 1.0f);
    vec3 A = normalize(cross(axis, R));
    vec3 B = normalize(cross(R, A));
    int n = (int)u->uHammersley.N;
    vec3 sum = vec3s(0.0f);
    const lobe_table *lobe = task ? lobe_for(u, task, alpha) : NULL;
    int below = 0;
    if (trace) {
        trace->NdotV = NdotV;
        trace->R = R;
        trace->A = A;
        trace->B = B;
        trace->pole_frame = axis.x == 1.0f;
        trace->sample_count = n;
    }
    for (int k = 0; k < n; k++) {
        vec2 xi = lobe ? lobe->xi[k] : hammersley_point(u, k);
        vec3 L = lobe ? lobe->L[k] : skewed_sample(xi, alpha);
        float pdf = lobe ? lobe->pdf[k] : sample_pdf(xi, alpha);
        vec3 w = normalize(add(add(scale(A, L.x), scale(B, L.y)), scale(R, L.z)));
        float wN = dot(w, N);
        if (trace) {
            sl_lighting_trace_sample *ts = &trace->samples[k];
            memset(ts, 0, sizeof *ts);
            ts->xi = xi;
            ts->L = L;
            ts->pdf = pdf;
            ts->w = w;
            ts->wN = wN;
            ts->sum = sum;
        }
        if (wN <= 0.0f) {
            below++;
            continue;
        }
        vec3 H = normalize(add(w, V));
        float NdotH = dot(N, H);
        float LdotH = dot(w, H);
        float D = sl_brdf_D(NdotH, alpha);
        vec3 F = sl_brdf_F(Ks, LdotH);
        float G = sl_brdf_G(LdotH, (sl_gterm)u->uGTerm);
        float lod = mip_level(u, D, pdf, w);
        vec3 Li = scale(textureLod(u->uEnv, sl_dir_to_uv(w), lod), u->uEnvIntensity);
        float weight = G * wN / 4.0f;
        if (u->uEstimator == ESTIMATOR_CONSISTENT)
            weight = weight * D / pdf;
        vec3 c = scale(mul(F, Li), weight);
        sum = add(sum, c);
        if (trace) {
            sl_lighting_trace_sample *ts = &trace->samples[k];
            ts->H = H;
            ts->NdotH = NdotH;
            ts->LdotH = LdotH;
            ts->D = D;
            ts->F = F;
            ts->G = G;
            ts->lod = lod;
            ts->Li = Li;
            ts->c = c;
            ts->sum = sum;
        }
    }
    if (task) {
        task->stats.samples += n;
        task->stats.below_horizon += below;
        task->stats.pole_frames += axis.x == 1.0f;
    }
    return scale(sum, 1.0f / (float)(n > 1 ? n : 1));
}

/* GLSL: point_light */
static vec3 point_light(const sl_lighting_uniforms *u, int i, vec3 P, vec3 N, vec3 V, vec3 Kd, vec3 Ks,
                        float alpha)
{
    vec3 toLight = sub(u->uLightPosition[i], P);
    float d2 = dot(toLight, toLight);
    if (d2 < MIN_LIGHT_D2)
        return vec3s(0.0f);
    vec3 L = scale(toLight, 1.0f / sqrtf(d2));
    float NdotL = dot(N, L);
    if (NdotL <= 0.0f)
        return vec3s(0.0f);
    vec3 H = normalize(add(L, V));
    float LdotH = dot(L, H);
    vec3 f = vec3s(0.0f);
    if (u->uDiffuse != 0)
        f = add(f, scale(Kd, 1.0f / PI));
    if (u->uSpecular != 0)
        f = add(f, scale(sl_brdf_F(Ks, LdotH),
                         sl_brdf_D(dot(N, H), alpha) * sl_brdf_G(LdotH, (sl_gterm)u->uGTerm) / 4.0f));
    return scale(mul(f, u->uLightColor[i]), u->uLightIntensity[i] / d2 * NdotL);
}

/* GLSL: background */
static vec3 background(const sl_lighting_uniforms *u, vec2 fragCoord)
{
    vec2 ndc = sub(scale(vec2(fragCoord.x / u->uViewport.x, fragCoord.y / u->uViewport.y), 2.0f), vec2s(1.0f));
    vec4 nearP = mat4_mul_vec4(u->uInvViewProj, vec4(ndc.x, ndc.y, -1.0f, 1.0f));
    vec4 farP = mat4_mul_vec4(u->uInvViewProj, vec4(ndc.x, ndc.y, 1.0f, 1.0f));
    vec3 d = normalize(sub(scale(xyz(farP), 1.0f / farP.w), scale(xyz(nearP), 1.0f / nearP.w)));
    return scale(textureLod(u->uEnv, sl_dir_to_uv(mat3_mul_vec3(u->uEnvRotation, d)), 0.0f), u->uEnvIntensity);
}

static bool finite3(vec3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

/* GLSL: main. pixel = (x, y) = ivec2(gl_FragCoord.xy); the texel fields are the texelFetches. */
vec3 sl_lighting_shade(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x, int y,
                       sl_lighting_task *task, sl_lighting_trace *trace)
{
    const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x, y);
    vec2 fragCoord = vec2((float)x + 0.5f, (float)y + 0.5f);
    float depth = t->depth;
    vec3 color = vec3s(0.0f);
    if (trace) {
        trace->frag_coord = fragCoord;
        trace->texel = *t;
        trace->covered = !(depth >= 1.0f);
    }
    if (depth >= 1.0f) {
        color = background(u, fragCoord);
        if (trace)
            trace->background = color;
        if (task)
            task->stats.background++;
    } else {
        vec3 P = t->position;
        vec3 Kd = t->kd;
        vec3 Ks = t->ks;
        float alpha = clamp(t->alpha, 0.0f, MAX_ALPHA);
        vec3 V = normalize(sub(u->uEye, P));
        vec3 N = facing_normal(t->normal, V);
        vec3 Nenv = mat3_mul_vec3(u->uEnvRotation, N);
        vec3 Venv = mat3_mul_vec3(u->uEnvRotation, V);
        if (task)
            task->stats.bent_normals += dot(t->normal, V) < MIN_NDOTV * length(t->normal);
        if (trace) {
            trace->V = V;
            trace->N = N;
            trace->bent = dot(t->normal, V) < MIN_NDOTV * length(t->normal);
            trace->Nenv = Nenv;
            trace->Venv = Venv;
            trace->alpha = alpha;
        }
        if (u->uDiffuse != 0) {
            vec3 E = irradiance(u, Nenv);
            vec3 diffuse = scale(mul(scale(Kd, 1.0f / PI), E), u->uEnvIntensity);
            color = add(color, diffuse);
            if (trace) {
                trace->irradiance = E;
                trace->diffuse = diffuse;
            }
        }
        if (u->uSpecular != 0) {
            vec3 specular = specular_ibl(u, Nenv, Venv, Ks, alpha, task, trace);
            color = add(color, specular);
            if (trace)
                trace->specular = specular;
        }
        if (u->uPointLights != 0) {
            for (int i = 0; i < u->uLightCount; i++) {
                vec3 light = point_light(u, i, P, N, V, Kd, Ks, alpha);
                color = add(color, light);
                if (trace) {
                    trace->light[i] = light;
                    trace->lights = add(trace->lights, light);
                }
            }
        }
    }
    bool finite = finite3(color);
    if (!finite && task)
        task->stats.nonfinite++;
    if (trace) {
        trace->repaired = !finite;
        trace->total = finite ? color : vec3s(0.0f);
    }
    return finite ? color : vec3s(0.0f);
}

/* ======================= C only: options, uniforms, tasks, pass ======================= */

sl_lighting_options sl_lighting_options_resolve(const sl_lighting_options *opt)
{
    sl_lighting_options r = opt ? *opt : (sl_lighting_options){0};
    if (r.samples == 0)
        r.samples = SL_LIGHTING_DEFAULT_SAMPLES;
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

static const char *const lod_names[] = {"default", "none", "spec", "spec-d4", "gems"};
static const char *const estimator_names[] = {"default", "spec", "consistent"};
static const char *const gterm_names[] = {"default", "inv-lh2", "one"};

const char *sl_lod_rule_name(sl_lod_rule rule)
{
    return (unsigned)rule <= SL_LOD_GEMS ? lod_names[rule] : "?";
}
const char *sl_estimator_name(sl_estimator estimator)
{
    return (unsigned)estimator <= SL_ESTIMATOR_CONSISTENT ? estimator_names[estimator] : "?";
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
    int i = parse_name(name, lod_names, 5);
    if (i < 0)
        return false;
    *rule = (sl_lod_rule)i;
    return true;
}
bool sl_estimator_parse(const char *name, sl_estimator *estimator)
{
    int i = parse_name(name, estimator_names, 3);
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
    if ((unsigned)o.lod_rule > SL_LOD_GEMS || (unsigned)o.estimator > SL_ESTIMATOR_CONSISTENT ||
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

    sl_hammersley set;
    if (!sl_hammersley_build(&set, o.samples, err))
        return false;
    sl_hammersley_pack_std140(&set, &u->uHammersley);

    const sl_env_level *l0 = &desc->env->levels[0];
    u->uEnv = desc->env;
    u->uEnvMaxLod = (float)(desc->env->level_count - 1);
    /* In float, as a shader computing it would; log2 of a product of ints <= 2^28 is exact enough. */
    u->uLodBase = 0.5f * log2f((float)l0->width * (float)l0->height / (float)o.samples);
    u->uSinThetaMin = sinf(PI / (2.0f * (float)l0->height));
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
    u->options = o;
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

enum { TILE = 32 };

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
                for (int x = x0; x < x1; x++) {
                    vec3 c = sl_lighting_shade(u, gb, x, y, task, NULL);
                    row[3 * x + 0] = c.x;
                    row[3 * x + 1] = c.y;
                    row[3 * x + 2] = c.z;
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

float sl_lighting_mip_level(const sl_lighting_uniforms *u, float D, float pdf, vec3 w)
{
    return mip_level(u, D, pdf, w);
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
    print3(f, "R", t->R);
    print3(f, "A", t->A);
    print3(f, "B", t->B);
    fprintf(f, "  %-12s %s\n", "A axis", t->pole_frame ? "X (R near a pole)" : "Z");
    fprintf(f, "specular samples (N = %d)\n", t->sample_count);
    fprintf(f, "  %4s %-17s %-26s %-9s %-26s %-8s %-26s %-8s %-10s %-8s %-26s %-8s %-26s %-26s\n", "k", "xi",
            "L (skewed)", "p(w)", "w", "w.N", "H", "L.H", "D", "G", "F", "lod", "Li", "contribution");
    for (int k = 0; k < t->sample_count; k++) {
        const sl_lighting_trace_sample *s = &t->samples[k];
        fprintf(f, "  %4d (%.5f,%.5f) (%+.5f,%+.5f,%+.5f) %-9.4g (%+.5f,%+.5f,%+.5f) %+-8.4f", k, (double)s->xi.x,
                (double)s->xi.y, (double)s->L.x, (double)s->L.y, (double)s->L.z, (double)s->pdf, (double)s->w.x,
                (double)s->w.y, (double)s->w.z, (double)s->wN);
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
    print3(f, "lights", t->lights);
    print3(f, "total", t->total);
    if (t->repaired)
        fprintf(f, "  a NaN/Inf was replaced by 0\n");
}
