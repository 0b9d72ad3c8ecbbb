/* ground_truth_image.c - ground truth of a whole G-buffer, cached on disk (see
 * ground_truth_image.h for the contract and the cache format).
 *
 * The per-pixel integral is sl_ground_truth_shade's loop (src/ibl/ground_truth.c) with one change: it
 * accumulates the specular sums for both G terms at once. Both loops use the same node table
 * (sl_ground_truth) and the same kernel per node (sl_gt_node_kernel, which splits the texels near
 * a narrow lobe's peak), so each G term's result is the one sl_ground_truth_shade returns;
 * test_ground_truth_image checks that.
 *
 * Visibility and point lights (the second half of "the integral"): the nodes regrouped by
 * cell, one ray per cell, the same per-node terms (add_node); test_visibility checks them
 * against closed forms and, with nothing in the way, against the blind pass. */
#include "ground_truth_image.h"

#include <math.h>
#include <stddef.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/hash.h"

#include "../core/timer.h"
#include "lighting_internal.h"
#include "visibility.h"

#define PI_D 3.14159265358979323846
#define GT_IMAGE_MAGIC "softlight ground truth v1"
/* Part of the key: bump when the integral or the per-pixel conventions change, so stale
 * caches are recomputed rather than trusted. */
#define GT_IMAGE_VERSION "level-0 texel quadrature, split near narrow lobes' peaks (ground_truth.h); facing_normal 0.01; alpha <= 1e7; both G; GGX alpha <= -1"
#define GT_HEADER_MAX 4096
/* Part of the key with visibility or lights only (the blind truth's key is left as it was). */
#define GT_VIS_VERSION "visibility: one ray per cell at its nodes' centroid above both horizons, Ng from the eye ray, the offset relative to the extent; point lights as lighting.frag"


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

/* The geometry's hash when visibility is on (0 otherwise: then it is not part of the key). */
static uint64_t vis_hash(const sl_gt_image_desc *d)
{
    return d->visibility && d->scene ? sl_visibility_scene_hash(d->scene, d->textures) : 0;
}

static uint64_t combine_key(uint64_t env_h, uint64_t gb_h, uint64_t vis_h, const sl_gt_image_desc *d)
{
    uint64_t h = sl_fnv1a(SL_FNV1A_START, GT_IMAGE_VERSION, sizeof GT_IMAGE_VERSION);
    h = sl_fnv1a(h, &env_h, sizeof env_h);
    h = sl_fnv1a(h, &gb_h, sizeof gb_h);
    h = sl_fnv1a(h, &d->eye, sizeof d->eye);
    h = sl_fnv1a(h, &d->env_rotation_deg, sizeof d->env_rotation_deg);
    h = sl_fnv1a(h, &d->env_intensity, sizeof d->env_intensity);
    if (!d->visibility && !d->lights)
        return h; /* the blind truth's key, as it always was */
    h = sl_fnv1a_str(h, GT_VIS_VERSION);
    const int settings[3] = {d->visibility, d->visibility ? d->visibility_level : -1, d->lights};
    h = sl_fnv1a(h, settings, sizeof settings);
    if (d->visibility)
        h = sl_fnv1a(h, &vis_h, sizeof vis_h);
    if (d->lights) {
        h = sl_fnv1a(h, &d->scene->light_count, sizeof d->scene->light_count);
        /* what the truth reads of a light: its 7 floats in order (not "shadow", a renderer's setting) */
        _Static_assert(offsetof(sl_point_light, intensity) == 6 * sizeof(float), "a point light's floats are packed");
        for (int i = 0; i < d->scene->light_count; i++)
            h = sl_fnv1a(h, &d->scene->lights[i], 7 * sizeof(float));
    }
    return h;
}

uint64_t sl_gt_image_key(const sl_gt_image_desc *desc)
{
    return combine_key(env_hash(desc->env), gbuffer_hash(desc->gbuffer), vis_hash(desc), desc);
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

/* Node w (unit, environment space, c = N.w > 0) with radiance-times-weight rgb into the sums: a
 * texel's node (split near a narrow lobe's peak: sl_gt_node_kernel), or a point light's direction
 * (`texel` false: read at w). The blind loop (shade_both) and the visibility pass add every node
 * through it. */
static inline void add_node(const sl_gt_lobe *l, double c, double wx, double wy, double wz, bool texel,
                            const double rgb[3], double dsum[3], double s0[2][3], double s1[2][3])
{
    for (int ch = 0; ch < 3; ch++)
        dsum[ch] += c * rgb[ch];
    double k[4]; /* k_inv, k_inv p5, k_one, k_one p5 */
    if (!sl_gt_node_kernel(l, c, wx, wy, wz, texel, k))
        return;
    for (int ch = 0; ch < 3; ch++) {
        s0[0][ch] += k[0] * rgb[ch];
        s1[0][ch] += k[1] * rgb[ch];
        s0[1][ch] += k[2] * rgb[ch];
        s1[1][ch] += k[3] * rgb[ch];
    }
}

/* sl_ground_truth_shade for unit, environment-space n and v, with both G terms. */
static void shade_both(const sl_ground_truth *gt, const double n[3], const double v[3], const double kd[3],
                       const double ks[3], double alpha, double intensity, double diffuse[3], double spec[2][3])
{
    const double nx = n[0], ny = n[1], nz = n[2];
    /* alpha < 0: a GGX lobe (lobe_param's range [-2, -1]), whose G has no --g choice: both
     * planes get the same sums */
    const bool ggx = alpha < 0.0;
    sl_gt_lobe lobe;
    sl_gt_lobe_init(&lobe, n, v, ggx, alpha, ggx ? sl_ground_truth_ggx_a2(-1.0 - alpha) : 0.0, gt->width, gt->height);
    const double *restrict x = gt->x, *restrict y = gt->y, *restrict z = gt->z;
    const double *restrict r = gt->r, *restrict g = gt->g, *restrict b = gt->b;
    /* [0]: G = 1/(L.H)^2, [1]: G = 1; s0 = sum k L, s1 = sum k p5 L (ground_truth.c) */
    double dsum[3] = {0}, s0[2][3] = {{0}}, s1[2][3] = {{0}};
    for (size_t t = 0; t < gt->count; t++) {
        double c = nx * x[t] + ny * y[t] + nz * z[t];
        if (c > 0.0)
            add_node(&lobe, c, x[t], y[t], z[t], true, (const double[3]){r[t], g[t], b[t]}, dsum, s0, s1);
    }
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

/* ---- visibility (docs/ibl.md "Visibility") ----
 *
 * The level-0 nodes regrouped by cell: cell (cx, cy) holds the texels of columns
 * [cx S, cx S + S) and rows [cy S, cy S + S), S = 2^level (the last cells of a size that S does not
 * divide are smaller), contiguous, each cell's in row-major order. A cell carries the normalised
 * sum of its nodes' directions (dc) and the sine of its cone: every node w of the cell has
 * w.dc >= cos(half), so a normal n with n.dc >= sin(half) has every node above its horizon and
 * one with n.dc <= -sin(half) has none. */
typedef struct {
    size_t count;                      /* cells */
    size_t *start;                     /* count + 1: cell c's nodes are [start[c], start[c + 1]) */
    double *x, *y, *z, *r, *g, *b;     /* the nodes, regrouped */
    double *cx, *cy, *cz, *sin_half;   /* per cell; sin_half 2 when the cone is not below 90 degrees */
} vis_cells;

static void vis_cells_free(vis_cells *c)
{
    free(c->start);
    free(c->x);
    free(c->cx);
    memset(c, 0, sizeof *c);
}

static bool vis_cells_build(vis_cells *c, const sl_ground_truth *gt, int level, sl_error *err)
{
    memset(c, 0, sizeof *c);
    const int S = 1 << level, W = gt->width, H = gt->height;
    const int cw = (W + S - 1) / S, ch = (H + S - 1) / S;
    c->count = (size_t)cw * (size_t)ch;
    c->start = malloc((c->count + 1) * sizeof *c->start);
    c->x = malloc(6 * gt->count * sizeof *c->x);
    c->cx = malloc(4 * c->count * sizeof *c->cx);
    if (!c->start || !c->x || !c->cx) {
        vis_cells_free(c);
        return sl_fail(err, SL_ERR_MEMORY, "ground truth: no memory for the visibility cells");
    }
    c->y = c->x + gt->count;
    c->z = c->y + gt->count;
    c->r = c->z + gt->count;
    c->g = c->r + gt->count;
    c->b = c->g + gt->count;
    c->cy = c->cx + c->count;
    c->cz = c->cy + c->count;
    c->sin_half = c->cz + c->count;
    size_t k = 0, cell = 0;
    for (int gy = 0; gy < ch; gy++)
        for (int gx = 0; gx < cw; gx++, cell++) {
            c->start[cell] = k;
            double sx = 0, sy = 0, sz = 0;
            for (int y = gy * S; y < gy * S + S && y < H; y++)
                for (int x = gx * S; x < gx * S + S && x < W; x++, k++) {
                    size_t t = (size_t)y * (size_t)W + (size_t)x;
                    c->x[k] = gt->x[t];
                    c->y[k] = gt->y[t];
                    c->z[k] = gt->z[t];
                    c->r[k] = gt->r[t];
                    c->g[k] = gt->g[t];
                    c->b[k] = gt->b[t];
                    sx += gt->x[t];
                    sy += gt->y[t];
                    sz += gt->z[t];
                }
            double len = sqrt(sx * sx + sy * sy + sz * sz);
            double cos_min = 1.0;
            if (len > 0.0) {
                sx /= len;
                sy /= len;
                sz /= len;
                for (size_t j = c->start[cell]; j < k; j++) {
                    double wl = c->x[j] * c->x[j] + c->y[j] * c->y[j] + c->z[j] * c->z[j];
                    if (!(wl > 0.5)) /* a node without a direction (weight 0) carries nothing */
                        continue;
                    double d = sx * c->x[j] + sy * c->y[j] + sz * c->z[j];
                    cos_min = d < cos_min ? d : cos_min;
                }
            } else {
                cos_min = -1.0;
            }
            c->cx[cell] = sx;
            c->cy[cell] = sy;
            c->cz[cell] = sz;
            /* a margin over the rounding of the dots (the tests it serves are conservative) */
            c->sin_half[cell] = cos_min > 0.0 ? sqrt(1.0 - cos_min * cos_min) + 1e-9 : 2.0;
        }
    c->start[cell] = k;
    return true;
}

/* What one pixel's visibility pass shares. */
typedef struct {
    const vis_cells *cells;
    const sl_visibility *vis;
    const sl_scene *scene; /* point lights: NULL for none */
    double cr, sr;         /* world -> environment: d_env = Rz(-rotation) d_world */
} vis_frame;

/* env -> world for a ray: d_world = Rz(rotation) d_env */
static void to_world(const vis_frame *f, const double e[3], double w[3])
{
    w[0] = f->cr * e[0] - f->sr * e[1];
    w[1] = f->sr * e[0] + f->cr * e[1];
    w[2] = e[2];
}

/* The environment's part with visibility: sums over the nodes of the cells P sees. ng is the
 * geometric normal in environment space, org the rays' origin (world). Returns the rays traced. */
static long vis_environment(const vis_frame *f, const sl_gt_lobe *l, const double ng[3], const double org[3],
                            double dsum[3], double s0[2][3], double s1[2][3])
{
    const vis_cells *cl = f->cells;
    long rays = 0;
    for (size_t c = 0; c < cl->count; c++) {
        const double sh = cl->sin_half[c];
        const double dn = l->n[0] * cl->cx[c] + l->n[1] * cl->cy[c] + l->n[2] * cl->cz[c];
        const double dg = ng[0] * cl->cx[c] + ng[1] * cl->cy[c] + ng[2] * cl->cz[c];
        if (dn <= -sh || dg <= -sh)
            continue; /* no node above one of the horizons */
        const size_t t0 = cl->start[c], t1 = cl->start[c + 1];
        double d[3] = {cl->cx[c], cl->cy[c], cl->cz[c]};
        if (!(dn >= sh && dg >= sh)) { /* the cell straddles a horizon: the centroid of its part above both */
            double sx = 0, sy = 0, sz = 0;
            for (size_t t = t0; t < t1; t++) {
                const double wx = cl->x[t], wy = cl->y[t], wz = cl->z[t];
                if (l->n[0] * wx + l->n[1] * wy + l->n[2] * wz > 0.0 && ng[0] * wx + ng[1] * wy + ng[2] * wz > 0.0) {
                    sx += wx;
                    sy += wy;
                    sz += wz;
                }
            }
            double len = sqrt(sx * sx + sy * sy + sz * sz);
            if (!(len > 0.0))
                continue;
            d[0] = sx / len;
            d[1] = sy / len;
            d[2] = sz / len;
        }
        double dw[3];
        to_world(f, d, dw);
        rays++;
        if (sl_visibility_occluded(f->vis, org, dw, (double)INFINITY))
            continue;
        for (size_t t = t0; t < t1; t++) {
            const double wx = cl->x[t], wy = cl->y[t], wz = cl->z[t];
            double cn = l->n[0] * wx + l->n[1] * wy + l->n[2] * wz;
            if (!(cn > 0.0))
                continue;
            if (!(ng[0] * wx + ng[1] * wy + ng[2] * wz > 0.0))
                continue; /* behind the surface itself */
            const double rgb[3] = {cl->r[t], cl->g[t], cl->b[t]};
            add_node(l, cn, wx, wy, wz, true, rgb, dsum, s0, s1);
        }
    }
    return rays;
}

/* The scene's point lights as lighting.frag's point_light adds them: f color intensity / d^2
 * (N.L)+, in double; with visibility (vis non-NULL) each times a shadow ray from org to the light,
 * and 0 below the geometric horizon. Adds to diffuse and both specular planes. */
static long add_point_lights(const vis_frame *f, const sl_gt_lobe *l, vec3 p, const double *ng_world,
                             const double org[3], const double kd[3], const double ks[3], float *diffuse,
                             float *spec0, float *spec1)
{
    long rays = 0;
    const sl_scene *sc = f->scene;
    double d[3] = {0}, s0[2][3] = {{0}}, s1[2][3] = {{0}};
    for (int i = 0; i < sc->light_count; i++) {
        const sl_point_light *li = &sc->lights[i];
        double tw[3] = {(double)li->position.x - (double)p.x, (double)li->position.y - (double)p.y,
                        (double)li->position.z - (double)p.z};
        double d2 = tw[0] * tw[0] + tw[1] * tw[1] + tw[2] * tw[2];
        if (d2 < 1e-8) /* the shader's MIN_LIGHT_D2 */
            continue;
        double dist = sqrt(d2);
        double lw[3] = {tw[0] / dist, tw[1] / dist, tw[2] / dist};
        /* into the environment's frame, where n and v are */
        double le[3] = {f->cr * lw[0] + f->sr * lw[1], -f->sr * lw[0] + f->cr * lw[1], lw[2]};
        double c = l->n[0] * le[0] + l->n[1] * le[1] + l->n[2] * le[2];
        if (!(c > 0.0))
            continue;
        if (ng_world) {
            if (!(ng_world[0] * lw[0] + ng_world[1] * lw[1] + ng_world[2] * lw[2] > 0.0))
                continue;
            double to[3] = {(double)li->position.x - org[0], (double)li->position.y - org[1],
                            (double)li->position.z - org[2]};
            double td = sqrt(to[0] * to[0] + to[1] * to[1] + to[2] * to[2]);
            double dir[3] = {to[0] / td, to[1] / td, to[2] / td};
            rays++;
            if (sl_visibility_occluded(f->vis, org, dir, td * (1.0 - 1e-6)))
                continue;
        }
        const double e = (double)li->intensity / d2;
        const double rgb[3] = {(double)li->color.x * e, (double)li->color.y * e, (double)li->color.z * e};
        add_node(l, c, le[0], le[1], le[2], false, rgb, d, s0, s1);
    }
    for (int ch = 0; ch < 3; ch++) {
        diffuse[ch] += (float)(kd[ch] / PI_D * d[ch]);
        spec0[ch] += (float)(ks[ch] * s0[0][ch] + (1.0 - ks[ch]) * s1[0][ch]);
        spec1[ch] += (float)(ks[ch] * s0[1][ch] + (1.0 - ks[ch]) * s1[1][ch]);
    }
    return rays;
}

/* shade_texel with visibility and/or point lights: the image-based part is the blind one (shade_texel)
 * without visibility. Occlusion and emission (apply_extra) are applied here, before the point
 * lights, as the shader orders them. */
static long shade_texel_vis(const sl_ground_truth *gt, const vis_frame *f, const sl_gbuffer_texel *t,
                            const sl_gbuffer_extra *extra, vec3 eye, double intensity, long *fallbacks,
                            float *diffuse, float *spec0, float *spec1)
{
    vec3 V = normalize(sub(eye, t->position));
    vec3 N = sl_shade_facing_normal(t->normal, V);
    double nw[3], vw[3];
    unit_d(N, nw);
    unit_d(V, vw);
    const double cr = f->cr, sr = f->sr;
    const double n[3] = {cr * nw[0] + sr * nw[1], -sr * nw[0] + cr * nw[1], nw[2]};
    const double v[3] = {cr * vw[0] + sr * vw[1], -sr * vw[0] + cr * vw[1], vw[2]};
    const double alpha = (double)shade_lobe_param(t->alpha);
    const bool ggx = alpha < 0.0;
    sl_gt_lobe l;
    sl_gt_lobe_init(&l, n, v, ggx, alpha, ggx ? sl_ground_truth_ggx_a2(-1.0 - alpha) : 0.0, gt->width, gt->height);
    const double kd[3] = {(double)t->kd.x, (double)t->kd.y, (double)t->kd.z};
    const double ks[3] = {(double)t->ks.x, (double)t->ks.y, (double)t->ks.z};
    long rays = 0;
    double ngw[3], org[3] = {0};
    const double *ng_world = NULL;
    if (f->vis) {
        rays++;
        if (!sl_visibility_surface(f->vis, eye, t->position, ngw)) {
            (*fallbacks)++;
            memcpy(ngw, nw, sizeof ngw);
        }
        ng_world = ngw;
        const double off = sl_visibility_offset(f->vis, t->position);
        org[0] = (double)t->position.x + off * ngw[0];
        org[1] = (double)t->position.y + off * ngw[1];
        org[2] = (double)t->position.z + off * ngw[2];
        const double nge[3] = {cr * ngw[0] + sr * ngw[1], -sr * ngw[0] + cr * ngw[1], ngw[2]};
        double dsum[3] = {0}, s0[2][3] = {{0}}, s1[2][3] = {{0}};
        rays += vis_environment(f, &l, nge, org, dsum, s0, s1);
        for (int ch = 0; ch < 3; ch++) {
            diffuse[ch] = (float)(intensity * kd[ch] / PI_D * dsum[ch]);
            spec0[ch] = (float)(intensity * (ks[ch] * s0[0][ch] + (1.0 - ks[ch]) * s1[0][ch]));
            spec1[ch] = (float)(intensity * (ks[ch] * s0[1][ch] + (1.0 - ks[ch]) * s1[1][ch]));
        }
    } else {
        shade_texel(gt, t, eye, cr, sr, intensity, diffuse, spec0, spec1);
    }
    if (extra)
        apply_extra(extra, diffuse, spec0, spec1);
    if (f->scene)
        rays += add_point_lights(f, &l, t->position, ng_world, org, kd, ks, diffuse, spec0, spec1);
    return rays;
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
    if ((d->visibility || d->lights) && !d->scene)
        return sl_fail(err, SL_ERR_RANGE, "ground truth image: visibility and point lights need the scene");
    if (d->visibility && (d->visibility_level < 0 || d->visibility_level > SL_GT_VIS_LEVEL_MAX))
        return sl_fail(err, SL_ERR_RANGE, "ground truth image: visibility level %d, must be in 0..%d",
                       d->visibility_level, SL_GT_VIS_LEVEL_MAX);
    if (d->visibility && !sl_visibility_available())
        return sl_fail(err, SL_ERR_RANGE, "--visibility needs Embree 3, and this build has none "
                       "(install libembree-dev and rebuild)");
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
    /* visibility and point lights: the scene's triangles and the regrouped nodes */
    const bool extended = d->visibility || d->lights;
    vis_cells cells = {0};
    vis_frame vf = {.cells = &cells, .scene = d->lights ? d->scene : NULL, .cr = cr, .sr = sr};
    sl_visibility *vis = NULL;
    if (d->visibility) {
        vis = sl_visibility_create(d->scene, d->textures, nthreads, err);
        if (!vis || !vis_cells_build(&cells, &gt, d->visibility_level, err)) {
            sl_visibility_free(vis);
            sl_ground_truth_free(&gt);
            return false;
        }
        vf.vis = vis;
    }
    long rays = 0, fallbacks = 0;
    /* Rows are independent: each writes its own row of every plane. Thread 0 is the calling
     * thread and reports progress after each row it finishes. */
    /* the ray counts are summed with atomics, not a reduction clause: clang implements that with
     * a named critical section, a global symbol the library would export (tests/cli/exports.sh) */
#pragma omp parallel for schedule(dynamic, 1) num_threads(nthreads)
    for (int y = 0; y < h; y++) {
        const int row = h - 1 - y; /* image row 0 = top = G-buffer row h - 1 */
        long row_done = 0, row_rays = 0, row_fallbacks = 0;
        for (int x = 0; x < w; x++) {
            const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x, y);
            if (!sl_gbuffer_covered(t))
                continue;
            sl_image_pixel(&out->mask, x, row)[0] = 1.0f;
            if (extended) {
                row_rays += shade_texel_vis(&gt, &vf, t, gb->extra ? &gb->extra[t - gb->texels] : NULL, eye,
                                            intensity, &row_fallbacks, sl_image_pixel(&out->diffuse, x, row),
                                            sl_image_pixel(&out->specular[0], x, row),
                                            sl_image_pixel(&out->specular[1], x, row));
                row_done++;
                continue;
            }
            shade_texel(&gt, t, eye, cr, sr, intensity, sl_image_pixel(&out->diffuse, x, row),
                        sl_image_pixel(&out->specular[0], x, row), sl_image_pixel(&out->specular[1], x, row));
            if (gb->extra)
                apply_extra(&gb->extra[t - gb->texels], sl_image_pixel(&out->diffuse, x, row),
                            sl_image_pixel(&out->specular[0], x, row), sl_image_pixel(&out->specular[1], x, row));
            row_done++;
        }
        if (extended) {
#pragma omp atomic
            rays += row_rays;
#pragma omp atomic
            fallbacks += row_fallbacks;
        }
        long now;
#pragma omp atomic capture
        now = done += row_done;
        if (d->progress && omp_get_thread_num() == 0 && now < total)
            d->progress(d->progress_user, now, total);
    }
    out->seconds = sl_now_seconds() - t0;
    out->rays = rays;
    out->ng_fallbacks = fallbacks;
    if (d->progress)
        d->progress(d->progress_user, total, total);
    vis_cells_free(&cells);
    sl_visibility_free(vis);
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
                        uint64_t vis_h, sl_error *err)
{
    char header[GT_HEADER_MAX], label[1024];
    /* one line: a newline in the label would end the header field early */
    snprintf(label, sizeof label, "%s", d->label ? d->label : "-");
    for (char *p = label; *p; p++)
        if (*p == '\n' || *p == '\r')
            *p = ' ';
    const sl_env_level *l0 = &d->env->levels[0];
    char extended[512] = ""; /* only with visibility or point lights: the blind header is as it was */
    if (d->visibility || d->lights)
        snprintf(extended, sizeof extended, "visibility %s level %d geometry fnv1a64 %016llx rays %ld\n"
                 "point_lights %d\n%s\n", d->visibility ? "on" : "off", d->visibility ? d->visibility_level : -1,
                 (unsigned long long)vis_h, img->rays, d->lights ? d->scene->light_count : 0, GT_VIS_VERSION);
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
                     "%s"
                     "seconds %.1f\n"
                     "planes diffuse specular-inv-lh2 specular-one (RGB) mask (1), float32 little endian, "
                     "row 0 = top\n"
                     "key %016llx\n"
                     "data\n",
                     label, img->width, img->height, img->covered, l0->width, l0->height,
                     (unsigned long long)env_h, (unsigned long long)gb_h, (double)d->eye.x, (double)d->eye.y,
                     (double)d->eye.z, (double)d->env_rotation_deg, (double)d->env_intensity, GT_IMAGE_VERSION,
                     extended, img->seconds, (unsigned long long)img->key);
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
    uint64_t env_h = env_hash(desc->env), gb_h = gbuffer_hash(desc->gbuffer), vis_h = vis_hash(desc);
    uint64_t key = combine_key(env_h, gb_h, vis_h, desc);
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
    if (desc->cache_path && !write_cache(out, desc, env_h, gb_h, vis_h, err)) {
        sl_gt_image_free(out);
        return false;
    }
    return true;
}
