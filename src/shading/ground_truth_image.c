/* ground_truth_image.c - ground truth of a whole G-buffer, cached on disk (see
 * ground_truth_image.h for the contract and the cache format).
 *
 * The per-pixel integral is sl_ground_truth_shade's loop (src/ibl/ground_truth.c) with one change: it
 * accumulates the specular sums for both G terms at once. Both loops use the same node table
 * (sl_ground_truth) and the same operations in the same order, so each G term's result is
 * the one sl_ground_truth_shade returns; test_ground_truth_image checks that. */
#include "ground_truth_image.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/hash.h"

#include "../core/timer.h"
#include "lighting_internal.h"

#define PI_D 3.14159265358979323846
#define GT_IMAGE_MAGIC "softlight ground truth v1"
/* Part of the key: bump when the integral or the per-pixel conventions change, so stale
 * caches are recomputed rather than trusted. */
#define GT_IMAGE_VERSION "level-0 texel quadrature (ground_truth.h); facing_normal 0.01; alpha <= 1e7; both G; GGX alpha <= -1"
#define GT_HEADER_MAX 4096


/* ---- hashing: FNV-1a 64 (core/hash.h) ---- */

static uint64_t env_hash(const sl_env *env)
{
    const sl_env_level *l = &env->levels[0];
    uint64_t h = sl_fnv1a(SL_FNV1A_START, &l->width, sizeof l->width);
    h = sl_fnv1a(h, &l->height, sizeof l->height);
    return sl_fnv1a(h, l->texels, (size_t)l->width * (size_t)l->height * sizeof *l->texels);
}

static uint64_t gbuffer_hash(const sl_gbuffer *gb)
{
    _Static_assert(sizeof(sl_gbuffer_texel) == 14 * sizeof(float), "G-buffer texel has no padding to hash");
    uint64_t h = sl_fnv1a(SL_FNV1A_START, &gb->width, sizeof gb->width);
    h = sl_fnv1a(h, &gb->height, sizeof gb->height);
    h = sl_fnv1a(h, gb->texels, (size_t)gb->width * (size_t)gb->height * sizeof *gb->texels);
    if (gb->extra) /* occlusion and emission change the result (the tag is their writer's depth) */
        h = sl_fnv1a(h, gb->extra, (size_t)gb->width * (size_t)gb->height * sizeof *gb->extra);
    return h;
}

static uint64_t combine_key(uint64_t env_h, uint64_t gb_h, const sl_gt_image_desc *d)
{
    uint64_t h = sl_fnv1a(SL_FNV1A_START, GT_IMAGE_VERSION, sizeof GT_IMAGE_VERSION);
    h = sl_fnv1a(h, &env_h, sizeof env_h);
    h = sl_fnv1a(h, &gb_h, sizeof gb_h);
    h = sl_fnv1a(h, &d->eye, sizeof d->eye);
    h = sl_fnv1a(h, &d->env_rotation_deg, sizeof d->env_rotation_deg);
    return sl_fnv1a(h, &d->env_intensity, sizeof d->env_intensity);
}

uint64_t sl_gt_image_key(const sl_gt_image_desc *desc)
{
    return combine_key(env_hash(desc->env), gbuffer_hash(desc->gbuffer), desc);
}

/* ---- images ---- */

void sl_gt_image_free(sl_gt_image *img)
{
    if (!img)
        return;
    sl_image_free(&img->diffuse);
    sl_image_free(&img->specular[0]);
    sl_image_free(&img->specular[1]);
    sl_image_free(&img->mask);
    memset(img, 0, sizeof *img);
}

static bool alloc_planes(sl_gt_image *img, int w, int h, sl_error *err)
{
    img->width = w;
    img->height = h;
    return sl_image_alloc(&img->diffuse, w, h, 3, err) && sl_image_alloc(&img->specular[0], w, h, 3, err) &&
           sl_image_alloc(&img->specular[1], w, h, 3, err) && sl_image_alloc(&img->mask, w, h, 1, err);
}

bool sl_gt_image_total(const sl_gt_image *img, sl_gt_geometry g, sl_image *total, sl_error *err)
{
    if (g != SL_GT_G_INV_LH2 && g != SL_GT_G_ONE)
        return sl_fail(err, SL_ERR_RANGE, "ground truth: unknown G choice %d", (int)g);
    if (!img->diffuse.data)
        return sl_fail(err, SL_ERR_RANGE, "ground truth: empty image");
    if (!sl_image_alloc(total, img->width, img->height, 3, err))
        return false;
    size_t n = (size_t)img->width * (size_t)img->height * 3;
    for (size_t i = 0; i < n; i++)
        total->data[i] = img->diffuse.data[i] + img->specular[g].data[i];
    return true;
}

/* ---- the integral ---- */

static bool finite3(vec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }

/* sl_ground_truth_shade for unit, environment-space n and v, with both G terms. */
static void shade_both(const sl_ground_truth *gt, const double n[3], const double v[3], const double kd[3],
                       const double ks[3], double alpha, double intensity, double diffuse[3], double spec[2][3])
{
    const double nx = n[0], ny = n[1], nz = n[2], vx = v[0], vy = v[1], vz = v[2];
    const double nv = nx * vx + ny * vy + nz * vz;
    const double d_norm = (alpha + 2.0) / (2.0 * PI_D);
    /* alpha < 0: a GGX lobe (lobe_param's range [-2, -1]), whose G has no --g choice: both
     * planes get the same sums */
    const bool ggx = alpha < 0.0;
    const double a2 = ggx ? sl_ground_truth_ggx_a2(-1.0 - alpha) : 0.0;
    const double *restrict x = gt->x, *restrict y = gt->y, *restrict z = gt->z;
    const double *restrict r = gt->r, *restrict g = gt->g, *restrict b = gt->b;
    double dr = 0, dg = 0, db = 0;
    /* [0]: G = 1/(L.H)^2, [1]: G = 1; s0 = sum k L, s1 = sum k p5 L (ground_truth.c) */
    double s0[2][3] = {{0}}, s1[2][3] = {{0}};
    for (size_t t = 0; t < gt->count; t++) {
        double c = nx * x[t] + ny * y[t] + nz * z[t];
        if (!(c > 0.0))
            continue;
        dr += c * r[t];
        dg += c * g[t];
        db += c * b[t];
        double len2 = 2.0 + 2.0 * (vx * x[t] + vy * y[t] + vz * z[t]);
        if (!(len2 > 1e-24))
            continue;
        double len = sqrt(len2);
        double nh = (c + nv) / len;
        if (!(nh > 0.0))
            continue;
        /* (N.H)^alpha <= exp(-alpha (1 - N.H)) rounds to exactly 0 in double past 746: skipping
         * those texels adds nothing ground_truth.c would not add as +0 (same bits, less pow). */
        if (alpha * (1.0 - nh) > 746.0)
            continue;
        double lh = 0.5 * len;
        double k_one, k_inv;
        if (ggx) {
            k_one = k_inv = sl_ground_truth_ggx_dvis(nh, c, nv, a2) * c; /* as ground_truth.c */
        } else {
            double base = 0.25 * d_norm * pow(nh, alpha);
            k_one = base * 1.0 * c; /* as ground_truth.c: 0.25 d pow * gterm * c */
            k_inv = base * (1.0 / (lh * lh)) * c;
        }
        double p = 1.0 - lh;
        p = p > 0.0 ? p : 0.0;
        double p5 = (p * p) * (p * p) * p;
        s0[0][0] += k_inv * r[t];
        s0[0][1] += k_inv * g[t];
        s0[0][2] += k_inv * b[t];
        s1[0][0] += k_inv * p5 * r[t];
        s1[0][1] += k_inv * p5 * g[t];
        s1[0][2] += k_inv * p5 * b[t];
        s0[1][0] += k_one * r[t];
        s0[1][1] += k_one * g[t];
        s0[1][2] += k_one * b[t];
        s1[1][0] += k_one * p5 * r[t];
        s1[1][1] += k_one * p5 * g[t];
        s1[1][2] += k_one * p5 * b[t];
    }
    const double dsum[3] = {dr, dg, db};
    for (int ch = 0; ch < 3; ch++) {
        diffuse[ch] = intensity * kd[ch] / PI_D * dsum[ch];
        for (int gi = 0; gi < 2; gi++)
            spec[gi][ch] = intensity * (ks[ch] * s0[gi][ch] + (1.0 - ks[ch]) * s1[gi][ch]);
    }
}

static void unit_d(vec3 a, double out[3])
{
    double x = (double)a.x, y = (double)a.y, z = (double)a.z;
    double len = sqrt(x * x + y * y + z * z);
    out[0] = x / len;
    out[1] = y / len;
    out[2] = z / len;
}

/* The G-buffer's extra channels (gbuffer.h), as the lighting shader applies them: occlusion scales
 * the image-based terms (both parts here), emission joins the diffuse part (view-independent). */
static void apply_extra(const sl_gbuffer_extra *e, float *diffuse, float *spec0, float *spec1)
{
    const float em[3] = {e->emissive.x, e->emissive.y, e->emissive.z};
    for (int c = 0; c < 3; c++) {
        diffuse[c] = diffuse[c] * e->occlusion + em[c];
        spec0[c] *= e->occlusion;
        spec1[c] *= e->occlusion;
    }
}

/* One covered texel: N, V as the shader forms them, then into the environment frame. */
static void shade_texel(const sl_ground_truth *gt, const sl_gbuffer_texel *t, vec3 eye, double cr, double sr,
                        double intensity, float *diffuse, float *spec0, float *spec1)
{
    vec3 V = normalize(sub(eye, t->position));
    vec3 N = sl_shade_facing_normal(t->normal, V); /* the shader's own */
    double nw[3], vw[3];
    unit_d(N, nw);
    unit_d(V, vw);
    /* world -> environment: d_env = Rz(-rotation) d_world (ground_truth.h) */
    const double n[3] = {cr * nw[0] + sr * nw[1], -sr * nw[0] + cr * nw[1], nw[2]};
    const double v[3] = {cr * vw[0] + sr * vw[1], -sr * vw[0] + cr * vw[1], vw[2]};
    const double kd[3] = {(double)t->kd.x, (double)t->kd.y, (double)t->kd.z};
    const double ks[3] = {(double)t->ks.x, (double)t->ks.y, (double)t->ks.z};
    float a = shade_lobe_param(t->alpha); /* the shader's own: Phong exponent, or GGX (< 0) */
    double d[3], s[2][3];
    shade_both(gt, n, v, kd, ks, (double)a, intensity, d, s);
    for (int ch = 0; ch < 3; ch++) {
        diffuse[ch] = (float)d[ch];
        spec0[ch] = (float)s[0][ch];
        spec1[ch] = (float)s[1][ch];
    }
}

static bool check_inputs(const sl_gt_image_desc *d, sl_error *err)
{
    if (!d->env || d->env->level_count < 1)
        return sl_fail(err, SL_ERR_RANGE, "ground truth image: no environment");
    const sl_gbuffer *gb = d->gbuffer;
    if (!gb || !gb->texels || gb->width < 1 || gb->height < 1)
        return sl_fail(err, SL_ERR_RANGE, "ground truth image: empty G-buffer");
    if (!finite3(d->eye))
        return sl_fail(err, SL_ERR_RANGE, "ground truth image: eye not finite");
    if (!isfinite(d->env_intensity) || d->env_intensity < 0.0f || !isfinite(d->env_rotation_deg))
        return sl_fail(err, SL_ERR_RANGE, "ground truth image: intensity %g / rotation %g not usable",
                       (double)d->env_intensity, (double)d->env_rotation_deg);
    for (int y = 0; y < gb->height; y++)
        for (int x = 0; x < gb->width; x++) {
            const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x, y);
            if (!sl_gbuffer_covered(t))
                continue;
            if (!finite3(t->position) || !finite3(t->normal) || !finite3(t->kd) || !finite3(t->ks) ||
                !isfinite(t->alpha))
                return sl_fail(err, SL_ERR_RANGE, "ground truth image: G-buffer texel %d,%d (row 0 = bottom) "
                               "has a non-finite field", x, y);
            vec3 v = sub(d->eye, t->position);
            if (!(dot(v, v) > 0.0f))
                return sl_fail(err, SL_ERR_RANGE, "ground truth image: texel %d,%d is at the eye", x, y);
        }
    return true;
}

static bool integrate(sl_gt_image *out, const sl_gt_image_desc *d, sl_error *err)
{
    const sl_gbuffer *gb = d->gbuffer;
    const int w = gb->width, h = gb->height;
    long total = 0;
    for (size_t i = 0; i < (size_t)w * (size_t)h; i++)
        total += sl_gbuffer_covered(&gb->texels[i]);
    out->covered = total;
    sl_ground_truth gt;
    if (!sl_ground_truth_init(&gt, d->env, err))
        return false;
    const double phi = (double)radians(d->env_rotation_deg);
    const double cr = cos(phi), sr = sin(phi), intensity = (double)d->env_intensity;
    const vec3 eye = d->eye;
    long done = 0;
    double t0 = sl_now_seconds();
    int nthreads = d->threads > 0 ? d->threads : omp_get_max_threads();
    /* Rows are independent: each writes its own row of every plane. Thread 0 is the calling
     * thread and reports progress after each row it finishes. */
#pragma omp parallel for schedule(dynamic, 1) num_threads(nthreads)
    for (int y = 0; y < h; y++) {
        const int row = h - 1 - y; /* image row 0 = top = G-buffer row h - 1 */
        long row_done = 0;
        for (int x = 0; x < w; x++) {
            const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x, y);
            if (!sl_gbuffer_covered(t))
                continue;
            sl_image_pixel(&out->mask, x, row)[0] = 1.0f;
            shade_texel(&gt, t, eye, cr, sr, intensity, sl_image_pixel(&out->diffuse, x, row),
                        sl_image_pixel(&out->specular[0], x, row), sl_image_pixel(&out->specular[1], x, row));
            if (gb->extra)
                apply_extra(&gb->extra[t - gb->texels], sl_image_pixel(&out->diffuse, x, row),
                            sl_image_pixel(&out->specular[0], x, row), sl_image_pixel(&out->specular[1], x, row));
            row_done++;
        }
        long now;
#pragma omp atomic capture
        now = done += row_done;
        if (d->progress && omp_get_thread_num() == 0 && now < total)
            d->progress(d->progress_user, now, total);
    }
    out->seconds = sl_now_seconds() - t0;
    if (d->progress)
        d->progress(d->progress_user, total, total);
    sl_ground_truth_free(&gt);
    return true;
}

/* ---- the cache file ---- */

static void put_f32(unsigned char *p, float v)
{
    uint32_t u;
    memcpy(&u, &v, 4);
    p[0] = (unsigned char)u;
    p[1] = (unsigned char)(u >> 8);
    p[2] = (unsigned char)(u >> 16);
    p[3] = (unsigned char)(u >> 24);
}

static float get_f32(const unsigned char *p)
{
    uint32_t u = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
    float v;
    memcpy(&v, &u, 4);
    return v;
}

/* The planes in file order: diffuse, specular G = 1/(L.H)^2, specular G = 1 (RGB), mask. */
static size_t payload_floats(int w, int h) { return (size_t)w * (size_t)h * 10; }

static bool write_cache(const sl_gt_image *img, const sl_gt_image_desc *d, uint64_t env_h, uint64_t gb_h,
                        sl_error *err)
{
    char header[GT_HEADER_MAX], label[1024];
    /* one line: a newline in the label would end the header field early */
    snprintf(label, sizeof label, "%s", d->label ? d->label : "-");
    for (char *p = label; *p; p++)
        if (*p == '\n' || *p == '\r')
            *p = ' ';
    const sl_env_level *l0 = &d->env->levels[0];
    int n = snprintf(header, sizeof header,
                     GT_IMAGE_MAGIC "\n"
                     "label %s\n"
                     "size %d %d\n"
                     "covered %ld\n"
                     "env %dx%d fnv1a64 %016llx\n"
                     "gbuffer fnv1a64 %016llx\n"
                     "eye %.9g %.9g %.9g\n"
                     "rotation_deg %.9g\n"
                     "intensity %.9g\n"
                     "integrator %s\n"
                     "seconds %.1f\n"
                     "planes diffuse specular-inv-lh2 specular-one (RGB) mask (1), float32 little endian, "
                     "row 0 = top\n"
                     "key %016llx\n"
                     "data\n",
                     label, img->width, img->height, img->covered, l0->width, l0->height,
                     (unsigned long long)env_h, (unsigned long long)gb_h, (double)d->eye.x, (double)d->eye.y,
                     (double)d->eye.z, (double)d->env_rotation_deg, (double)d->env_intensity, GT_IMAGE_VERSION,
                     img->seconds, (unsigned long long)img->key);
    if (n < 0 || (size_t)n >= sizeof header)
        return sl_fail(err, SL_ERR_RANGE, "%s: ground-truth header too long (label?)", d->cache_path);
    size_t px = (size_t)img->width * (size_t)img->height;
    size_t size = (size_t)n + 4 * payload_floats(img->width, img->height);
    unsigned char *bytes = malloc(size);
    if (!bytes)
        return sl_fail(err, SL_ERR_MEMORY, "%s: no memory for the cache (%zu bytes)", d->cache_path, size);
    memcpy(bytes, header, (size_t)n);
    unsigned char *p = bytes + n;
    const sl_image *planes[4] = {&img->diffuse, &img->specular[0], &img->specular[1], &img->mask};
    for (int k = 0; k < 4; k++) {
        size_t count = px * (size_t)planes[k]->channels;
        for (size_t i = 0; i < count; i++, p += 4)
            put_f32(p, planes[k]->data[i]);
    }
    bool ok = sl_write_file_atomic(d->cache_path, bytes, size, err);
    free(bytes);
    return ok;
}

/* Read the cache when its key and size match; false (no error) otherwise. */
static bool read_cache(sl_gt_image *img, const sl_gt_image_desc *d, uint64_t key)
{
    unsigned char *bytes = NULL;
    size_t size = 0;
    if (!sl_read_file(d->cache_path, SL_IMAGE_MAX_FILE_BYTES, &bytes, &size, NULL))
        return false;
    bool ok = false;
    const char *magic = GT_IMAGE_MAGIC "\n";
    size_t head = 0;
    /* the header ends at the first "\ndata\n" */
    for (size_t i = 0; i + 6 <= size && i < GT_HEADER_MAX; i++)
        if (!memcmp(bytes + i, "\ndata\n", 6)) {
            head = i + 6;
            break;
        }
    if (!head || size < strlen(magic) || memcmp(bytes, magic, strlen(magic)))
        goto done;
    char header[GT_HEADER_MAX + 8]; /* head <= GT_HEADER_MAX + 5 */
    memcpy(header, bytes, head);
    header[head] = '\0';
    const char *ks = strstr(header, "\nkey "), *ss = strstr(header, "\nsize "), *cs = strstr(header, "\ncovered ");
    unsigned long long file_key;
    int w, h;
    long covered;
    if (!ks || !ss || !cs || sscanf(ks, "\nkey %llx", &file_key) != 1 || sscanf(ss, "\nsize %d %d", &w, &h) != 2 ||
        sscanf(cs, "\ncovered %ld", &covered) != 1)
        goto done;
    if (file_key != key || w != d->gbuffer->width || h != d->gbuffer->height)
        goto done;
    if (size - head != 4 * payload_floats(w, h))
        goto done;
    if (!alloc_planes(img, w, h, NULL))
        goto done;
    const unsigned char *p = bytes + head;
    sl_image *planes[4] = {&img->diffuse, &img->specular[0], &img->specular[1], &img->mask};
    size_t px = (size_t)w * (size_t)h;
    for (int k = 0; k < 4; k++) {
        size_t count = px * (size_t)planes[k]->channels;
        for (size_t i = 0; i < count; i++, p += 4) {
            float v = get_f32(p);
            if (!isfinite(v) || v < 0.0f) { /* a damaged file: recompute, never pass it on */
                sl_gt_image_free(img);
                goto done;
            }
            planes[k]->data[i] = v;
        }
    }
    img->covered = covered;
    img->key = key;
    img->from_cache = true;
    ok = true;
done:
    free(bytes);
    return ok;
}

bool sl_gt_image_compute(sl_gt_image *out, const sl_gt_image_desc *desc, sl_error *err)
{
    memset(out, 0, sizeof *out);
    if (!check_inputs(desc, err))
        return false;
    uint64_t env_h = env_hash(desc->env), gb_h = gbuffer_hash(desc->gbuffer);
    uint64_t key = combine_key(env_h, gb_h, desc);
    if (desc->cache_path && read_cache(out, desc, key)) {
        if (desc->progress)
            desc->progress(desc->progress_user, out->covered, out->covered);
        return true;
    }
    if (!alloc_planes(out, desc->gbuffer->width, desc->gbuffer->height, err) || !integrate(out, desc, err)) {
        sl_gt_image_free(out);
        return false;
    }
    out->key = key;
    if (desc->cache_path && !write_cache(out, desc, env_h, gb_h, err)) {
        sl_gt_image_free(out);
        return false;
    }
    return true;
}
